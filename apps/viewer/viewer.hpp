// maille-viewer: the window, its input and its frame loop (GLFW + Dear ImGui + the renderer),
// around a PhysicsThread that runs the scene.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace maille::viewer {

struct ViewerOptions {
  std::filesystem::path scene;
  std::filesystem::path examples;    // the scene picker lists the .toml files found here
  int width = 1280, height = 800;    // window size, screen coordinates
  int frames = 0;                    // > 0: draw this many frames, then exit (tests)
  std::filesystem::path screenshot;  // with frames: the last frame written here as PNG
  bool paused = false;               // start paused
  bool smooth = false;               // cloth drawn as a smooth surface
  int lod = 4;                       // its sub-segments per physical edge, 1 to 16
  std::string backend;               // empty: the scene's ([simulation] backend)
  // Stages' live settings sent once the scene runs, (stage, option, value), through the same
  // path as the Stages panel; a refused one is shown there (and printed at the end of a
  // --frames run).
  std::vector<std::array<std::string, 3>> stage_options;
  // Sound on from the start (the Sound panel's box), through this driver and device (empty: the
  // first that opens, the default device). With --frames, a summary line at the end.
  bool sound = false;
  std::string sound_driver, sound_device;
};

// Returns the process exit code: 0, or 1 when the scene or the window cannot be opened.
int run_viewer(const ViewerOptions& options);

}  // namespace maille::viewer
