// The subcommands of `maille`. Exit codes: 0 success, 1 bad input, 2 usage, 3 blow-up,
// 4 output error, 130 interrupted (Ctrl-C).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "maille/exit_codes.hpp"

namespace maille::app {

// The exit codes, named once in the library (maille/exit_codes.hpp): ok, bad_input, usage,
// blow_up, output_error, interrupted.
using enum exit_code::Exit;

struct RunOptions {
  std::string scene;
  std::optional<std::uint64_t> steps;
  std::optional<double> duration;
  std::string out;  // empty: out/<scene name>
  std::optional<int> every;
  std::string format = "ply";
  bool smooth = false;  // obj frames: the smooth surface through the particles
  int lod = 4;          // its sub-segments per physical edge, 1 to 16
  std::optional<int> threads;
  bool no_frames = false;
  std::optional<std::uint64_t> checkpoint_every;  // steps between checkpoints (DIR/checkpoint.bin)
  std::string resume;                             // DIR of a checkpoint to continue from
  bool no_self_collision = false;                 // skip the scene's [self_collision] stage
  std::vector<std::string> sets;                  // --set KEY=VALUE overrides
  std::string backend;                            // empty: the scene's ([simulation] backend)
  std::optional<int> gpu_device;                  // EGL device index for the gpu backend
  std::string audio;  // --audio FILE.wav: the scene's [[listen]] channels (docs/sound.md)
};
int run(const RunOptions& o);
// `sets`: scene overrides KEY=VALUE (`--set`, see src/scene/overrides.hpp), in order.
int validate(const std::string& scene, const std::vector<std::string>& sets = {});
// `backend`: also describe that backend (for gpu: driver, device, limits) and say whether the
// scene runs there; with no scene, describe the backend only.
int info(const std::string& scene, const std::vector<std::string>& sets = {},
         const std::string& backend = {}, std::optional<int> gpu_device = {});

// Every declared scene table's keys and every named choice (`maille info --keys`): keys.cpp.
// With `docs`, rewrites that file's key tables instead (`--update-docs docs/scene-format.md`).
int describe_keys(const std::string& docs = {});

struct BenchOptions {
  std::string scene;
  std::uint64_t steps = 1000;
  std::uint64_t warmup = 0;  // steps run before the timing (a cloth settles on an obstacle)
  std::optional<int> threads;
  int repeat = 3;
  bool header = true;
  bool no_self_collision = false;
  std::vector<std::string> sets;      // --set KEY=VALUE overrides
  std::vector<std::string> backends;  // one CSV row each; empty: the scene's
  std::optional<int> gpu_device;
};
int bench(const BenchOptions& o);

// `maille render`: pictures and videos with no display (EGL surfaceless, see movie.hpp).
struct RenderCommandOptions {
  std::string scene;
  std::string out;  // FILE.mp4: a video; FILE.png: the last frame; anything else: a directory
  int width = 1280, height = 720;  // pixels
  double fps = 30;                 // frames per simulated second
  std::optional<double> duration;  // simulated seconds (default: the scene's)
  // yaw, pitch[, zoom]: degrees, degrees, distance factor (CLI11 splits "--camera 25,15,1")
  std::vector<double> camera{25, 15, 1};
  int samples = 4;      // antialiasing samples per pixel
  bool mesh = false;    // draw the links inside cloth surfaces too
  bool smooth = false;  // cloth faces as a smooth surface (smooth_surface.hpp)
  int lod = 4;          // its sub-segments per physical edge, 1 to 16
  std::optional<int> threads;
  bool no_self_collision = false;
  std::vector<std::string>
      stage_options;              // "STAGE.OPTION=VALUE", e.g. self_collision.draw_cells=on
  std::vector<std::string> sets;  // --set KEY=VALUE overrides
  std::string backend;            // empty: the scene's
  std::optional<int> gpu_device;
};
int render(const RenderCommandOptions& o);

// `maille play`: live sound (play.cpp, docs/sound.md "Playing live").
struct PlayOptions {
  std::string scene;
  std::string driver;  // jack | alsa | pulse; empty: the first that opens
  std::string device;  // empty: the default
  int rate = 48000;
  std::size_t buffer = 64;
  std::optional<double> duration;  // s of audio; none: until Ctrl-C
  std::vector<std::string> sets;
  std::optional<int> threads;  // default 1
  std::string record;          // --record FILE.wav: the samples sent, float32
  bool benchmark = false;      // no device: CPU time per period over --duration (default 5 s)
};
int play(const PlayOptions& o);

}  // namespace maille::app
