// Headless rendering of a scene over time: the driver behind `maille render`.
//
// The simulator advances on the calling thread; at every frame time k / fps (k = 0, 1, ...) it
// publishes a snapshot, the renderer draws it into an offscreen framebuffer of an EGL
// surfaceless context, and the pixels go to a FrameSink. The renderer sees only the snapshots.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "maille/render/frame_sink.hpp"
#include "maille/render/renderer.hpp"
#include "maille/scene.hpp"

namespace maille::render {

struct MovieSettings {
  int width = 1280, height = 720;  // pixels, > 0
  double fps = 30;                 // frames per simulated second, > 0
  double duration = 0;             // simulated seconds; <= 0: the scene's duration
  int samples = 4;                 // multisampling (antialiasing), 1 to 8
  double yaw = 25, pitch = 15;     // camera direction, degrees (see Camera)
  double zoom = 1;                 // camera distance over the auto-framed one, > 0
  bool last_frame_only = false;    // simulate the whole duration, render its last frame only
  int threads = 0;                 // simulation threads; 0: the scene's setting
  RenderOptions options;
  // Stages' live settings applied before the first frame (stage, option, value), e.g.
  // {"self_collision", "draw_cells", "on"}; stages' overlays are then drawn.
  std::vector<std::array<std::string, 3>> stage_options;
  // Polled between steps and inside long implicit steps (Simulator::on_stop_request): true
  // stops the render at the last whole step, the frames written so far complete. May be empty.
  std::function<bool()> stop_requested;
};

struct MovieReport {
  std::uint64_t frames = 0;            // frames rendered
  std::uint64_t steps = 0;             // simulation steps taken
  double simulated = 0;                // s of simulated time
  double simulate_seconds = 0;         // wall time in the simulator
  double render_seconds = 0;           // wall time drawing and reading pixels back
  double output_seconds = 0;           // wall time encoding and writing
  std::string gl;                      // the OpenGL renderer used
  std::optional<std::string> blow_up;  // the simulator's report when it stopped on a blow-up
  bool interrupted = false;            // progress returned false, or a stop was requested
};

// `progress(done, total)` is called after every frame; returning false stops the render (the
// frames written so far stay complete). Throws std::runtime_error for context or output
// failures and std::invalid_argument for settings out of range.
MovieReport render_movie(const Scene& scene, const MovieSettings& settings, FrameSink& sink,
                         const std::function<bool(std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace maille::render
