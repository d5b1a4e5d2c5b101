// The viewer's Dear ImGui panels: simulation controls, live parameters, sound, drawing options,
// plots.
// They run on the UI thread and reach the physics only through PhysicsThread's commands.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "maille/render/renderer.hpp"
#include "maille/scene.hpp"
#include "physics_thread.hpp"
#include "sound.hpp"

namespace maille::viewer {

// What the panels edit, kept between frames. Link parameters are shown as factors of the scene's
// values; a change sends the ratio new / old to the physics thread.
struct Tuning {
  std::vector<std::vector<float>> link_factor;  // [pool][field], 1 = the scene's value
  Fields fields;
  float speed = 1;  // simulated seconds per wall second
  bool as_fast_as_possible = false;
  double step = 1e-3;      // s
  float drag_factor = 1;   // times the default drag spring stiffness
  bool auto_frame = true;  // the camera follows the scene's bounding box

  static Tuning from(const Scene& scene);
};

// What the user asked for in this frame that the viewer itself must do.
struct PanelRequests {
  bool reload = false;
  std::optional<std::filesystem::path> open;  // a scene picked from the list
  bool screenshot = false;
  bool frame_scene = false;
};

PanelRequests draw_panels(const Scene& scene, PhysicsThread& physics, Tuning& tuning, Sound& sound,
                          render::RenderOptions& options,
                          const std::vector<std::filesystem::path>& examples,
                          const std::string& load_error, double frame_ms);

}  // namespace maille::viewer
