// The engine as the page sees it: one scene at a time, stepped on one thread, read without
// copies. Embind exposes it (bindings.cpp); web/page/maille.js wraps it into window.maille.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "maille/render/topology.hpp"
#include "maille/result.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille::viewer {
class DragState;
}

namespace maille::web {

// A scene read from text, or where the text is wrong.
struct LoadResult {
  bool ok = false;
  InputError error;  // when !ok: line and column of the text (1-based; 0 when not tied to one)
};

// A numeric key written in the scene text, by its `--set` path ("flag[0].stiffness").
struct DeclaredKey {
  std::string key;
  double value = 0;
  bool integer = false;
};

// A solid to draw (an obstacle): its mesh's vertices once, its placement every frame.
struct Solid {
  std::string name;
  std::vector<float> vertices;        // render::solid_vertices: 6 floats per vertex
  std::array<float, 12> placement{};  // direct (3x3, row-major), then translation
  std::array<float, 4> colour{};
};

class Playground {
 public:
  Playground();
  ~Playground();

  // Reads `text` (named `source_name` in errors; mesh files are found next to it), with the
  // `--set` overrides given, and starts it when it is valid; otherwise the running scene stays.
  LoadResult load(const std::string& text, const std::string& source_name,
                  const std::vector<std::string>& overrides);
  // `--set KEY=VALUE` on the current text: the scene is read again with the override added; when
  // the model keeps its size, the run continues from the current state (positions, velocities,
  // time and the scheme's history), otherwise it restarts.
  LoadResult set(const std::string& key, const std::string& value);
  bool loaded() const { return sim_ != nullptr; }
  // Steps until n are taken or a blow-up stops the run: the steps taken.
  std::uint64_t step(std::uint64_t n);
  void reset();

  const Simulator& simulator() const { return *sim_; }
  Simulator& simulator() { return *sim_; }
  const Scene& scene() const { return *scene_; }
  const std::string& text() const { return text_; }
  const std::vector<std::string>& overrides() const { return overrides_; }
  std::uint64_t state_hash() const;
  double last_step_ms() const { return last_step_ms_; }

  // Drawing: the static topology, the surface normals now, the solids now.
  const render::RenderTopology& topology() const { return topology_; }
  const std::vector<float>& normals();
  const std::vector<Solid>& solids();
  // Mouse drag through the viewer's drag spring (apps/viewer/drag_spring.hpp).
  void grab(std::uint32_t point, const Vec3& target);
  void move_to(const Vec3& target);
  void release();
  // Listened channels ([[listen]]): one value per step and channel, interleaved, since the last
  // take (cleared by it). The page resamples them to the audio rate.
  std::vector<float> take_listened();
  std::vector<DeclaredKey> declared_keys() const;

 private:
  void start(Scene scene, std::optional<State> keep);
  void record_listened();

  std::optional<Scene> scene_;
  std::unique_ptr<Simulator> sim_;
  std::string text_, source_name_;
  std::vector<std::string> overrides_;
  std::shared_ptr<viewer::DragState> drag_;
  bool drag_installed_ = false;
  render::RenderTopology topology_;
  std::vector<float> normals_;
  std::vector<Solid> solids_;
  std::vector<SurfaceInstance> surfaces_;  // the last snapshot's
  std::vector<Vec3> initial_;              // listened positions are displacements from here
  std::vector<float> listened_;
  double last_step_ms_ = 0;
};

}  // namespace maille::web
