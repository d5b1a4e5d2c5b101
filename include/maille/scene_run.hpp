// A run of a scene file: a scene and its overrides in, a run out. `maille run`, each case of
// `maille sweep` and the Python module's maille.run() are this one sequence (docs/architecture.md,
// "Running a scene"):
//
//   load()   the scene with its overrides (load_scene, as --set), the options' settings, the
//            steps to take (counted from t = 0, refused beyond limits::max_steps)
//   run()    the simulator (stage timings on sampled steps only); hooks.attach (the audio
//            recorder); hooks.loaded; an interrupt so far ends it with nothing written; the
//            output folder; warnings (a step beyond the stability estimate, the stages'
//            doubts); a checkpoint resumed; the frame and statistics writers; frame 0; the
//            loop, polling hooks.stop between steps and inside long implicit steps, with
//            checkpoints at their cadence; the runaway check since the last sample; the last
//            checkpoint; stats.csv closed; hooks.finish (the WAV); the outcome: a blow-up, an
//            interrupt, or the final energies (never exit 0 with a non-finite one)
//
// What differs between the programs goes through the hooks: how a stop is asked for (the
// command line's signal handler, a sweep's second Ctrl-C, Python's signal handlers), where
// warnings go (stderr, Python warnings, nowhere), what else is listened to (the audio).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "maille/energy.hpp"
#include "maille/exit_codes.hpp"
#include "maille/io.hpp"
#include "maille/result.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {

struct SceneRunOptions {
  std::filesystem::path scene;
  std::vector<std::string> sets;  // --set KEY=VALUE overrides, in order
  // How far, counted from t = 0: `steps`, else `duration` seconds, else the scene's duration.
  std::optional<std::uint64_t> steps;
  std::optional<double> duration;
  // How a duration too long to run is named in the refusal ("--duration"; default "the
  // duration" given, "the scene's duration" otherwise).
  std::string duration_name;
  // Settings that are no scene keys (the command line's options).
  std::optional<int> threads;
  std::optional<int> every;  // steps between frames (the scene's output_every otherwise)
  std::string backend;       // empty: the scene's
  std::optional<int> gpu_device;
  bool no_self_collision = false;  // the scene's [self_collision] stage left out
  // Outputs. out empty: the resumed folder, else out/<scene name>.
  std::filesystem::path out;
  bool frames = true;
  FrameFormat format = FrameFormat::ply;
  int smooth_lod = 0;                             // > 0: OBJ frames of the smooth surface
  std::optional<std::uint64_t> checkpoint_every;  // steps between out/checkpoint.bin
  std::filesystem::path resume;                   // a folder with checkpoint.bin and stats.csv
};

struct SceneRunHooks {
  std::function<bool()> stop;                    // true: stop between two steps (none: never)
  std::function<void(const std::string&)> warn;  // each warning, once (none: dropped)
  std::function<void(Simulator&)> attach;        // before anything runs: more stages
  std::function<void()> loaded;                  // the simulator is built; nothing is written yet
  std::function<void(const Simulator&)> finish;  // after stats.csv is closed, whatever the end
};

struct SceneRunReport {
  int exit = exit_code::ok;  // exit_code::Exit
  // What went wrong as the command line says it (one line, no newline); empty when ok and for
  // an interrupt during the loop (the caller names what it leaves complete).
  std::string error;
  std::optional<InputError> input;  // a refused scene or setting (exit bad_input), as read
  std::optional<BlowUp> blow_up;    // a numerical blow-up (exit blow_up)
  bool written = false;             // the output folder was made and its files written
  std::uint64_t steps_run = 0;      // steps taken by this run (after a resume: since it)
  std::uint64_t steps_taken = 0;    // the simulator's count from t = 0
  double simulated = 0;             // s, the simulator's time
  double wall = 0;                  // s, the loop and the final check
  std::uint64_t points = 0, frames = 0, stats_rows = 0;
  std::string unconverged;           // an implicit step that ended unconverged (unconverged_text)
  std::optional<Energies> energies;  // the final energies (exit ok)
};

// What a program says of a simulator before it runs: a step beyond the scheme's stability
// estimate, the stages' doubts about their settings (self-collision that can leak).
std::vector<std::string> setup_warnings(const Simulator& sim);

class SceneRun {
 public:
  explicit SceneRun(SceneRunOptions options);

  // Reads the scene, applies the settings and counts the steps. False: report() says why
  // (bad_input, or usage for a run longer than limits::max_steps).
  bool load();
  // After load(): what a caller checks before running (the scene's listeners, its surface).
  const Scene& scene() const { return scene_; }
  const SimulationSettings& settings() const { return settings_; }
  std::uint64_t steps() const { return steps_; }
  const std::filesystem::path& out() const { return out_; }

  // Runs the loaded scene (see the top of this file). Exceptions are turned into the report:
  // std::invalid_argument and std::bad_alloc bad_input, std::runtime_error output_error.
  const SceneRunReport& run(const SceneRunHooks& hooks = {});
  const SceneRunReport& report() const { return report_; }

 private:
  void simulate(Simulator& sim, const SceneRunHooks& hooks);
  void refuse(int exit, std::string error);

  SceneRunOptions o_;
  Scene scene_;
  SimulationSettings settings_;
  std::uint64_t steps_ = 0;
  std::filesystem::path out_;
  SceneRunReport report_;
};

}  // namespace maille
