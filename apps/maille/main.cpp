// maille: run, check and measure scenes from the command line.
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "maille/io.hpp"
#ifdef MAILLE_WITH_RENDER
#include "maille/gpu.hpp"
#endif
#include "maille/cores.hpp"
#include "maille/limits.hpp"
#include "study.hpp"
#include "sweep.hpp"

namespace {

// A number in [lo, hi] (lo excluded when `open_low`), NaN and infinity refused, with a short
// message: CLI::PositiveNumber lets NaN through and prints a 309-digit range. Bad values are
// usage errors (exit 2). Integer options are range-checked here before CLI11 converts them, so
// 18446744073709551616 steps is refused instead of wrapped.
CLI::Validator number_in(double lo, double hi, bool open_low = false) {
  std::ostringstream desc;
  desc.precision(10);
  desc << (open_low ? "in (" : "in [") << lo << ", " << hi << "]";
  return CLI::Validator(
      [lo, hi, open_low, d = desc.str()](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(v))
          return "must be a finite number (got '" + text + "')";
        if (v < lo || v > hi || (open_low && v == lo))
          return "must be " + d + " (got " + text + ")";
        return {};
      },
      desc.str());
}

// An output path: not empty (`--audio ""` would write nothing, `--out ""` the current folder).
const CLI::Validator kOutputPath(
    [](std::string& text) -> std::string {
      return text.empty() ? "must name a file or a directory (got an empty path)" : "";
    },
    "PATH");

const CLI::Validator kThreads = number_in(1, maille::limits::max_threads);
const CLI::Validator kSteps = number_in(1, double(maille::limits::max_steps));
const CLI::Validator kDuration = number_in(0, maille::limits::max_duration, true);
const CLI::Validator kDevice = number_in(0, 64);
const char* const backend_help =
    "Where the step runs: cpu (every stage and scheme, double) or gpu (OpenGL 4.5 compute, "
    "float); default: the scene's [simulation] backend, else cpu";
const char* const gpu_device_help =
    "EGL device index for the gpu backend (`maille info --backend gpu` lists them; default: "
    "Mesa's surfaceless platform)";

// The file a command reads, its first argument: required, and it must exist.
CLI::Option* add_input(CLI::App* cmd, const std::string& name, std::string& file,
                       const std::string& help) {
  return cmd->add_option(name, file, help)->required()->check(CLI::ExistingFile);
}

// The scene file every command that runs one takes first (validate and info check it themselves:
// their own message for a missing file).
CLI::Option* add_scene(CLI::App* cmd, std::string& scene) {
  return add_input(cmd, "scene", scene, "Scene file (TOML)");
}

// Options that several commands take, each with its check said once: a path to write (--out,
// --audio, --record) and the thread count.
template <class T>
CLI::Option* add_path(CLI::App* cmd, const std::string& name, T& path, const std::string& help) {
  return cmd->add_option(name, path, help)->check(kOutputPath);
}
template <class T>
CLI::Option* add_threads(CLI::App* cmd, T& threads, const std::string& help) {
  return cmd->add_option("--threads", threads, help)->check(kThreads);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace maille::app;
  maille::wait_passively_when_cores_are_shared(argv);  // cores.hpp: why
#ifdef MAILLE_WITH_RENDER
  maille::gpu::register_backend();
#endif
  CLI::App app{"Maille: mass-interaction physics (mass-spring cloth, ropes, nets, lattices)"};
  app.require_subcommand(1);

  RunOptions ro;
  auto* run_cmd = app.add_subcommand("run", "Run a scene headless: frames, stats.csv, a summary");
  add_scene(run_cmd, ro.scene);
  auto* steps = run_cmd->add_option("--steps", ro.steps, "Number of steps (default: duration/step)")
                    ->check(kSteps);
  run_cmd->add_option("--duration", ro.duration, "Simulated time, s (default: the scene's)")
      ->check(kDuration)
      ->excludes(steps);
  add_path(run_cmd, "--out", ro.out, "Output directory (default: out/<scene name>)");
  run_cmd
      ->add_option("--every", ro.every, "Steps between frames (default: the scene's output_every)")
      ->check(number_in(1, maille::kNeverEvery));
  run_cmd->add_option("--format", ro.format, "Frame format")
      ->check(CLI::IsMember(maille::name_strings<maille::FrameFormat>()));
  run_cmd->add_flag("--smooth", ro.smooth,
                    "OBJ frames of the smooth surface through the particles (with --format obj)");
  run_cmd->add_option("--lod", ro.lod, "Smooth surface: sub-segments per physical edge")
      ->check(CLI::Range(1, 16));
  add_threads(run_cmd, ro.threads, "Threads (default: the scene's, else auto)");
  run_cmd->add_flag("--no-frames", ro.no_frames, "Write stats.csv only, no frames");
  add_path(run_cmd, "--audio", ro.audio,
           "Write the scene's [[listen]] channels to this WAV file at [audio] rate "
           "(docs/sound.md)");
  run_cmd->add_flag("--no-self-collision", ro.no_self_collision,
                    "Ignore the scene's [self_collision] table (to see what it prevents)");
  run_cmd
      ->add_option("--checkpoint-every", ro.checkpoint_every,
                   "Write the whole state to OUT/checkpoint.bin every N steps (and at the end)")
      ->check(kSteps);
  run_cmd
      ->add_option("--resume", ro.resume,
                   "Continue from DIR/checkpoint.bin (frames and stats.csv continue in DIR "
                   "unless --out); --steps/--duration count from the start")
      ->check(CLI::ExistingDirectory);

  std::string scene;
  std::vector<std::string> sets;
  const char* set_help =
      "KEY=VALUE, repeatable: override a scene key by its path (simulation.step=2e-4, "
      "flag[0].stiffness=800, self_collision.broad_phase=brute), validated as in the file";
  run_cmd->add_option("--set", ro.sets, set_help);
  run_cmd->add_option("--backend", ro.backend, backend_help);
  run_cmd->add_option("--gpu-device", ro.gpu_device, gpu_device_help)->check(kDevice);
  PlayOptions po;
  auto* play_cmd = app.add_subcommand(
      "play", "Play a scene's [[listen]] channels live, controlled by MIDI and OSC ([[control]])");
  add_scene(play_cmd, po.scene);
  play_cmd->add_option("--driver", po.driver, "Audio driver (default: the first that opens)")
      ->check(CLI::IsMember({"jack", "alsa", "pulse"}));
  play_cmd->add_option("--device", po.device,
                       "Device: a JACK port prefix, an ALSA / PulseAudio device name (part of it)");
  play_cmd->add_option("--rate", po.rate, "Sample rate, Hz (JACK: the server's)")
      ->check(CLI::Range(1000, 384000));
  play_cmd->add_option("--buffer", po.buffer, "Frames per period (JACK: the server's)")
      ->check(CLI::Range(16, 8192));
  play_cmd->add_option("--duration", po.duration, "Seconds of sound, then stop (default: Ctrl-C)")
      ->check(kDuration);
  play_cmd->add_option("--set", po.sets, set_help);
  add_threads(play_cmd, po.threads, "Threads of the step (default 1)");
  add_path(play_cmd, "--record", po.record, "Also write the samples sent to this WAV (float32)");
  play_cmd->add_flag("--benchmark", po.benchmark,
                     "No device: the step's CPU time per period over --duration (default 5 s)");
  auto* validate_cmd = app.add_subcommand("validate", "Check a scene file; report the first error");
  validate_cmd->add_option("scene", scene, "Scene file (TOML)")->required();
  validate_cmd->add_option("--set", sets, set_help);
  auto* info_cmd = app.add_subcommand("info", "Counts by brick kind and the stability estimate");
  std::string info_backend;
  std::optional<int> info_device;
  auto* info_scene = info_cmd->add_option("scene", scene, "Scene file (TOML)");
  info_cmd->add_option("--set", sets, set_help);
  auto* info_backend_opt = info_cmd->add_option(
      "--backend", info_backend,
      "Also describe this backend (gpu: driver, device, limits) and whether the scene runs "
      "there; the scene may then be omitted");
  info_cmd->add_option("--gpu-device", info_device, gpu_device_help)->check(kDevice);
  bool info_keys = false;
  info_cmd->add_flag("--keys", info_keys,
                     "Print every declared scene table's keys (docs/scene-format.md's tables) "
                     "and every named choice");
  std::string info_docs;
  info_cmd->add_option("--update-docs", info_docs,
                       "With --keys: rewrite the key tables of this markdown file (each after its "
                       "<!-- keys: TABLE --> line; docs/scene-format.md) from the declarations");

  BenchOptions bo;
  auto* bench_cmd =
      app.add_subcommand("bench", "Run a scene for a fixed number of steps; print CSV");
  add_scene(bench_cmd, bo.scene);
  bench_cmd->add_option("--steps", bo.steps, "Steps per repetition")->check(kSteps);
  bench_cmd
      ->add_option("--warmup", bo.warmup,
                   "Steps run before each timed repetition (not timed: contacts settle)")
      ->check(kSteps);
  add_threads(bench_cmd, bo.threads, "Threads (default: the scene's, else auto)");
  bench_cmd->add_option("--repeat", bo.repeat, "Repetitions (the fastest is reported)")
      ->check(number_in(1, 1000));
  bench_cmd->add_flag("!--no-header", bo.header, "Omit the CSV header line");
  bench_cmd->add_flag("--no-self-collision", bo.no_self_collision,
                      "Ignore the scene's [self_collision] table");
  bench_cmd->add_option("--set", bo.sets, set_help);
  bench_cmd
      ->add_option("--backend", bo.backends,
                   "Backends to compare, one CSV row each: cpu, gpu or cpu,gpu (default: the "
                   "scene's)")
      ->delimiter(',');
  bench_cmd->add_option("--gpu-device", bo.gpu_device, gpu_device_help)->check(kDevice);

  StudyOptions so;
  auto* study_cmd = app.add_subcommand(
      "study",
      "Comparative studies written as CSV (integrators: stability, accuracy, energy, "
      "cost, and the implicit/explicit crossover)");
  study_cmd->add_option("topic", so.topic, "What to study")
      ->check(CLI::IsMember(
          {"integrators", "self-collision", "validity", "obstacles", "large-steps", "all"}))
      ->required();
  add_path(study_cmd, "--out", so.out,
           "Directory for the CSV files (default out/study; `all`: one "
           "subdirectory per study and durations.csv)");
  add_threads(study_cmd, so.threads, "Threads for the cost table");
  so.examples = MAILLE_EXAMPLES_DIR;
  study_cmd->add_option("--examples", so.examples,
                        "Directory of the example scenes the studies run (default: the source "
                        "tree's examples/)");
  study_cmd->add_flag("--quick", so.quick,
                      "Shorter runs (integrators: two stiffnesses in the crossover; obstacles: "
                      "a third of the simulated time)");

  SweepOptions sw;
  auto* sweep_cmd = app.add_subcommand(
      "sweep",
      "Run a scene for every combination of values in a sweep file (also under mpirun/srun, "
      "cases handed out to every rank): DIR/cases/<id>/stats.csv and DIR/summary.csv");
  add_input(sweep_cmd, "sweep", sw.sweep, "Sweep file (TOML, docs/sweep.md)");
  add_path(sweep_cmd, "--out", sw.out, "Output directory (a rerun skips the cases done there)")
      ->required();
  add_threads(sweep_cmd, sw.threads, "Threads of each case (default: the scene's, else auto)");

#ifdef MAILLE_WITH_RENDER
  RenderCommandOptions rn;
  auto* render_cmd = app.add_subcommand(
      "render", "Render a scene with no display: an MP4 video, PNG frames or one PNG still");
  add_scene(render_cmd, rn.scene);
  add_path(render_cmd, "--out", rn.out,
           "FILE.mp4 (video through ffmpeg), FILE.png (the last frame) or a directory "
           "(frame_000000.png, ...)")
      ->required();
  render_cmd->add_option("--width", rn.width, "Image width, pixels")->check(number_in(1, 16384));
  render_cmd->add_option("--height", rn.height, "Image height, pixels")->check(number_in(1, 16384));
  render_cmd->add_option("--fps", rn.fps, "Frames per simulated second")
      ->check(number_in(0, 1000, true));
  render_cmd->add_option("--duration", rn.duration, "Simulated time, s (default: the scene's)")
      ->check(kDuration);
  render_cmd
      ->add_option("--camera", rn.camera,
                   "yaw,pitch[,zoom]: view direction in degrees (yaw 0 looks along -z, "
                   "pitch from above) and distance over the auto-framed one")
      ->delimiter(',')
      ->expected(2, 3);
  render_cmd->add_option("--samples", rn.samples, "Antialiasing samples per pixel (1-8)")
      ->check(CLI::Range(1, 8));
  render_cmd->add_flag("--mesh", rn.mesh, "Also draw the links inside cloth surfaces");
  render_cmd->add_flag("--smooth", rn.smooth,
                       "Draw cloth as a smooth surface through the particles (GPU-evaluated)");
  render_cmd->add_option("--lod", rn.lod, "Smooth surface: sub-segments per physical edge")
      ->check(CLI::Range(1, 16));
  render_cmd->add_flag("--no-self-collision", rn.no_self_collision,
                       "Ignore the scene's [self_collision] table");
  render_cmd->add_option("--set", rn.sets, set_help);
  render_cmd->add_option("--stage-option", rn.stage_options,
                         "STAGE.OPTION=VALUE, repeatable: a stage's live setting, e.g. "
                         "self_collision.draw_cells=on, self_collision.draw_contacts=on");
  add_threads(render_cmd, rn.threads, "Simulation threads (default: the scene's)");
  render_cmd->add_option("--backend", rn.backend, backend_help);
  render_cmd->add_option("--gpu-device", rn.gpu_device, gpu_device_help)->check(kDevice);
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? ok : usage;
  }
  if (*run_cmd) return run(ro);
  if (*play_cmd) return play(po);
  if (*validate_cmd) return validate(scene, sets);
  if (*info_cmd) {
    if (info_keys) return describe_keys(info_docs);
    if (info_scene->count() == 0 && info_backend_opt->count() == 0) {
      std::cerr << "info: give a scene, --backend NAME, --keys, or both\n";
      return usage;
    }
    return info(scene, sets, info_backend, info_device);
  }
  if (*bench_cmd) return bench(bo);
  if (*study_cmd) return study(so);
  if (*sweep_cmd) return sweep(sw);
#ifdef MAILLE_WITH_RENDER
  if (*render_cmd) return render(rn);
#endif
  return usage;
}
