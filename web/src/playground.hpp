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
#include "maille/smooth_surface.hpp"

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

// A key the page makes a slider for (Playground::slider_keys): every number and integer key the
// engine declares for the scene's tables (stage_keys.hpp: [self_collision], [[obstacle]],
// [fields.wind], [simulation.implicit], [[contact]]) that the table's method uses, with the
// declared range and documentation, whether the text writes it or not; then the other numbers
// the text writes (builders, [simulation], [fields]), bounded as the link kinds' fields of that
// name declare (ParamField's bound) where one does.
struct SliderKey {
  std::string key;  // as --set takes it: "self_collision.thickness", "obstacle[0].friction"
  double value = 0;
  double lo = 0, hi = 0;  // the declared range; lo == hi: none declared
  bool lo_open = false;   // (lo, ...: lo itself excluded (a positive bound)
  bool integer = false;
  bool declared = false;         // from a table's declaration (else: a number the text writes)
  bool written = false;          // the text (or a --set) gives it
  std::string bound;             // "positive", "non_negative" or "" (any)
  std::string unit, doc, range;  // range as the docs write it
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
  // Threads per step: 1 in the one-thread module; up to the cores (at most 4) in the threaded
  // one (docs/web.md, "Threads"). A running scene goes on from its state. Returns the count set.
  int set_threads(int n);
  int threads() const { return threads_; }
  static int max_threads();

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
  // The smooth surface over the cloth (include/maille/smooth_surface.hpp): its layout, which the
  // page's WebGL2 vertex shader evaluates with the shared smooth_math.glsl; the vertex normals
  // PN triangles bend to, now; and the CPU evaluation (the shader's test oracle).
  const SmoothSurface& smooth() const { return smooth_; }
  const std::vector<float>& smooth_normals();
  const SmoothMesh& smooth_evaluate(int lod);
  // Mouse drag through the viewer's drag spring (apps/viewer/drag_spring.hpp).
  void grab(std::uint32_t point, const Vec3& target);
  void move_to(const Vec3& target);
  void release();
  // Listened channels ([[listen]]) as `maille run --audio` makes them (docs/sound.md,
  // "Sampling"): samples at the scene's [audio] rate, taken every K-th step when the step is
  // 1 / (K rate), else through the engine's StreamResampler (sinc or linear, as the scene says).
  // Channel-interleaved, since the last take (cleared by it); before any gain.
  std::vector<float> take_listened();
  int audio_rate() const;
  struct Listening;              // the listen stage's state (playground_sound.cpp)
  std::string sampling() const;  // SamplingPlan::describe()
  std::vector<DeclaredKey> declared_keys() const;
  std::vector<SliderKey> slider_keys() const;  // playground_keys.cpp

 private:
  void start(Scene scene, std::optional<State> keep);
  void listen(Simulator& sim, bool continuing);

  std::optional<Scene> scene_;
  std::unique_ptr<Simulator> sim_;
  std::string text_, source_name_;
  std::vector<std::string> overrides_;
  std::shared_ptr<viewer::DragState> drag_;
  bool drag_installed_ = false;
  render::RenderTopology topology_;
  std::vector<float> normals_;
  SmoothSurface smooth_;
  std::vector<float> smooth_normals_;
  SmoothMesh smooth_mesh_;
  std::vector<Solid> solids_;
  std::vector<SurfaceInstance> surfaces_;  // the last snapshot's
  std::shared_ptr<Listening> listening_;   // shared with the simulator's listen stage
  double last_step_ms_ = 0;
  int threads_ = 1;
};

}  // namespace maille::web
