#include "commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include <unistd.h>

#include "maille/backend.hpp"
#include "maille/clock.hpp"
#include "maille/interrupt.hpp"
#include "maille/intersections.hpp"
#include "maille/io.hpp"
#include "maille/limits.hpp"
#include "maille/scene.hpp"
#include "maille/scene_run.hpp"
#include "maille/simulator.hpp"
#include "maille/smooth_surface.hpp"
#include "maille/stability.hpp"
#include "maille/sweep.hpp"
#include "sound.hpp"
#ifdef MAILLE_WITH_RENDER
#include <cstdlib>
#include <memory>

#include "maille/render/movie.hpp"
#endif

namespace maille::app {

namespace {

// What an interrupt says while a scene loads and its simulator is set up: nothing of the run is
// written yet and no loop polls, so it ends the process at once (exit 130), whatever step of
// the loading it is in (a long sampling, a large build). The commands that write files count
// interrupts instead once their simulator is built (interrupt::counted), so that an interrupt
// while frame 0 is written or during the run ends with complete files (and exit 130).
constexpr char kLoadingInterrupted[] = "interrupted while loading the scene: nothing written\n";

std::optional<Scene> load_or_report(const std::string& path,
                                    const std::vector<std::string>& sets = {}) {
  try {
    Result<Scene> r = load_scene(path, sets);
    if (!r) {
      std::cerr << r.error().to_string() << '\n';
      return std::nullopt;
    }
    return std::move(r.value());
  } catch (const std::bad_alloc&) {  // the size checks should make this unreachable
    std::cerr << path << ": error: out of memory while building the scene\n";
    return std::nullopt;
  }
}

#ifdef MAILLE_WITH_RENDER
// The number of steps a render of `duration` seconds takes, refused (usage error) above
// limits::max_steps: a run that cannot end is a mistake, not a request (SceneRun checks a run's).
std::optional<std::uint64_t> steps_for(double duration, double step, const char* what) {
  const double n = std::round(duration / step);
  if (!(n <= double(limits::max_steps))) {
    std::cerr << "error: " << what << " " << duration << " s at a step of " << step << " s is " << n
              << " steps, more than the limit of " << double(limits::max_steps) << '\n';
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(n);
}
#endif

std::uint64_t points_of(const Model& m, PointKind k) {
  return m.points.count(k);
}

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::cerr << "warning: " << w << '\n';
}

}  // namespace

namespace {

// `maille validate SWEEP.toml`: the sweep file, its scene, every axis' key and every value, each
// error at the sweep file's line and column.
int validate_sweep(const std::string& path, const std::vector<std::string>& sets) {
  if (!sets.empty()) {
    std::cerr << path << ": error: a sweep file takes no --set (its axes are the overrides)\n";
    return usage;
  }
  Result<Sweep> sweep = load_sweep(path);
  if (!sweep) {
    std::cerr << sweep.error().to_string() << '\n';
    return bad_input;
  }
  for (auto check : {check_sweep_keys, check_sweep_values})
    if (const auto bad = check(*sweep)) {
      std::cerr << bad->to_string() << '\n';
      return bad_input;
    }
  std::cout << path << ": ok (a sweep of " << sweep->case_count() << " cases over "
            << sweep->scene.string() << ":";
  for (const auto& axis : sweep->axes)
    std::cout << ' ' << axis.key << " (" << axis.values.size() << " values)";
  std::cout << ")\n";
  return ok;
}

}  // namespace

// A cloth that starts through itself or through another (surface faces that cross, exact
// test: maille/intersections.hpp): no contact response can undo it.
static void warn_initial_crossings(const Simulator& sim) {
  const auto& faces = sim.model().surface.triangles;
  if (faces.empty()) return;
  IntersectionCount count;
  if (const std::size_t n = count.count(sim.state().x(), faces))
    std::cerr << "warning: " << n << " pair" << (n == 1 ? "" : "s")
              << " of the surface's triangles cross in the initial state: the cloth starts "
                 "through itself (or through another); self-collision holds it as it is, it "
                 "cannot pull it back\n";
}

int validate(const std::string& path, const std::vector<std::string>& sets) {
  interrupt::at_once(kLoadingInterrupted);  // writes nothing: an interrupt ends it at once
  if (is_sweep_file(path)) return validate_sweep(path, sets);
  auto scene = load_or_report(path, sets);
  if (!scene) return bad_input;
  try {
    Simulator sim(std::move(scene->model), scene->settings);
    print_warnings(setup_warnings(sim));
    warn_initial_crossings(sim);
    std::cout << path << ": ok (" << sim.model().points.size() << " points, "
              << sim.model().links.total() << " links";
    if (const auto n = scene->audio.listeners.size())
      std::cout << ", " << n << (n == 1 ? " listener" : " listeners");
    std::cout << ")\n";
    describe_audio(std::cout, scene->audio, sim.settings().step);
  } catch (const std::exception& e) {
    std::cerr << path << ": error: " << e.what() << '\n';
    return bad_input;
  }
  return ok;
}

namespace {

// The backend's description (for gpu: driver, device, limits, EGL devices), made by starting it.
int describe_backend(const std::string& name, std::optional<int> device) {
  const BackendRegistry::Entry* entry = BackendRegistry::global().find(name);
  if (!entry) {
    std::cerr << "error: unknown backend '" << name
              << "' (this program has: " << BackendRegistry::global().names() << ")\n";
    return usage;
  }
  std::cout << "backend      " << entry->name << ": " << entry->doc << '\n';
  if (!entry->make) return ok;
  try {
    BackendOptions options;
    if (device) options.device = *device;
    std::cout << entry->make(options)->describe();
  } catch (const std::exception& e) {
    std::cerr << "error: backend " << name << " cannot start: " << e.what() << '\n';
    return output_error;
  }
  return ok;
}

}  // namespace

int info(const std::string& path, const std::vector<std::string>& sets, const std::string& backend,
         std::optional<int> gpu_device) {
  interrupt::at_once(kLoadingInterrupted);  // writes nothing: an interrupt ends it at once
  if (!backend.empty())
    if (const int code = describe_backend(backend, gpu_device); code != ok) return code;
  if (path.empty()) return ok;
  auto scene = load_or_report(path, sets);
  if (!scene) return bad_input;
  if (!backend.empty()) scene->settings.backend = backend;
  if (gpu_device) scene->settings.backend_options.device = *gpu_device;
  std::optional<Simulator> built;
  try {
    built.emplace(std::move(scene->model), scene->settings);
  } catch (const std::invalid_argument& e) {
    std::cerr << path << ": error: " << e.what() << '\n';
    return bad_input;
  }
  Simulator& sim = *built;
  const Model& m = sim.model();
  const auto& s = sim.settings();
  print_warnings(sim.stage_warnings());
  std::cout << "scene        " << scene->name << '\n';
  if (!scene->description.empty()) std::cout << "description  " << scene->description << '\n';
  std::cout << "points       " << m.points.size() << "  (masses " << points_of(m, PointKind::free)
            << ", fixed " << points_of(m, PointKind::fixed) << ", driven "
            << points_of(m, PointKind::driven) << ")\n";
  for (const auto& pool : m.links.pools())
    std::cout << "links        " << pool->size() << " " << pool->keyword() << '\n';
  std::cout << "faces        " << m.surface.triangles.size() << '\n';
  for (const auto& g : m.groups)
    std::cout << "group        " << g.name << " (" << g.builder << "): points " << g.first << ".."
              << g.first + g.count - 1 << '\n';
  std::cout << "integrator   " << s.integrator << ", step " << s.step << " s, duration "
            << s.duration << " s, frame every " << s.publish_every << " steps, threads "
            << sim.threads() << (sim.follows_cores() ? " to start, then chosen during the run" : "")
            << '\n';
  describe_audio(std::cout, scene->audio, s.step);
  for (const StageSpec& spec : m.stages) {  // every declared key with its resolved value
    if (spec.parameters.empty()) continue;
    std::cout << "stage        " << spec.name << ":";
    for (const auto& [key, value] : spec.parameters) std::cout << ' ' << key << '=' << value;
    std::cout << '\n';
  }
  const auto& st = sim.stability();
  if (std::isinf(st.max_step)) {
    // Unconditionally stable schemes (implicit Euler): say so, and give the stiffest link and
    // the explicit (leapfrog) limit for reference.
    const auto leapfrog = IntegratorRegistry::builtin().find("leapfrog")->make(s.implicit);
    const StabilityEstimate ref = estimate_stability(m, *leapfrog);
    if (std::isinf(ref.max_step)) {
      std::cout << "stability    no stiff link: any step is stable\n";
    } else {
      std::cout << "stability    every step is stable for " << s.integrator
                << "; stiffest: " << ref.link_kind << " links at point " << ref.point << ", omega "
                << ref.omega << " rad/s, damping " << ref.damping_rate
                << " 1/s; for reference, the leapfrog limit is " << ref.max_step
                << " s (the scene's step is " << s.step / ref.max_step << " of it)\n";
    }
  } else {
    std::cout << "stability    largest stable step " << st.max_step << " s (" << st.link_kind
              << " links at point " << st.point << ", omega " << st.omega << " rad/s, damping "
              << st.damping_rate << " 1/s); the scene's step is "
              << (s.step <= st.max_step ? "within it" : "BEYOND it") << " (" << s.step / st.max_step
              << " of the limit)\n";
  }
  return ok;
}

namespace {

// The summary lines of a run that got to its loop: what was simulated and written, then how it
// ended (the final energy, or why not).
int report_run(const SceneRun& run, bool sound) {
  const SceneRunReport& r = run.report();
  const double particle_steps = double(r.steps_run) * double(r.points);
  std::printf(
      "maille: %s: %llu steps (%.4g s simulated) in %.3g s wall, %.3g ns per particle-step, "
      "%llu frames and %llu stats rows in %s\n",
      run.scene().name.c_str(), static_cast<unsigned long long>(r.steps_run),
      double(r.steps_run) * run.settings().step, r.wall,
      particle_steps > 0 ? r.wall * 1e9 / particle_steps : 0.0,
      static_cast<unsigned long long>(r.frames), static_cast<unsigned long long>(r.stats_rows),
      run.out().string().c_str());
  if (!r.unconverged.empty()) std::cerr << "warning: " << r.unconverged << '\n';
  if (r.exit == interrupted) {
    std::cerr << "interrupted at step " << r.steps_taken << "; the frames and stats"
              << (sound ? " written so far and the audio of the simulated time" : " written so far")
              << " are complete\n";
    return interrupted;
  }
  if (r.exit != ok) {
    std::cerr << r.error << '\n';
    return r.exit;
  }
  const Energies& e = *r.energies;
  std::printf(
      "maille: final energy %.6g J (kinetic %.6g, elastic %.6g, gravity %.6g, contact %.6g)\n",
      e.total(), e.kinetic, e.elastic, e.gravity, e.contact);
  return ok;
}

}  // namespace

int run(const RunOptions& o) {
  interrupt::at_once(kLoadingInterrupted);
  const auto format = parse_frame_format(o.format);
  SceneRunOptions so;
  so.scene = o.scene;
  so.sets = o.sets;
  so.steps = o.steps;
  so.duration = o.duration;
  so.duration_name = o.duration ? "--duration" : "the scene's duration";
  so.threads = o.threads;
  so.every = o.every;
  so.backend = o.backend;
  so.gpu_device = o.gpu_device;
  so.no_self_collision = o.no_self_collision;
  so.out = o.out;
  so.frames = !o.no_frames;
  so.format = format.value_or(FrameFormat::ply);
  so.smooth_lod = o.smooth ? o.lod : 0;
  so.checkpoint_every = o.checkpoint_every;
  so.resume = o.resume;
  SceneRun run(std::move(so));
  if (!run.load() && run.report().exit == bad_input) {
    std::cerr << run.report().error << '\n';
    return bad_input;
  }
  if (!format) {
    std::cerr << "unknown format '" << o.format << "'\n";
    return usage;
  }
  if (o.smooth && *format != FrameFormat::obj) {
    std::cerr << "--smooth writes OBJ frames: add --format obj\n";
    return usage;
  }
  if (run.report().exit != ok) {  // the steps to take: refused beyond the limit
    std::cerr << run.report().error << '\n';
    return run.report().exit;
  }
  const Scene& scene = run.scene();
  if (o.audio.empty() && !scene.audio.listeners.empty())
    std::printf(
        "maille: the scene has %zu [[listen]] channel%s: add --audio FILE.wav to write them\n",
        scene.audio.listeners.size(), scene.audio.listeners.size() == 1 ? "" : "s");
  if (!o.audio.empty())
    if (const int code = check_audio(o.scene, scene.audio,
                                     double(run.steps()) * run.settings().step, !o.resume.empty());
        code != ok)
      return code;
  // Refused before the output directory is made: nothing is left behind.
  if (o.smooth && SmoothSurface(scene.model).empty()) {
    std::cerr << o.scene << ": error: --smooth: the scene has no surface to smooth\n";
    return bad_input;
  }
  if (!o.audio.empty()) {
    const std::string clash = audio_clash(o.audio, o.scene, run.out());
    if (!clash.empty()) {
      std::cerr << "error: --audio " << o.audio << ": " << clash
                << "; name another file (nothing was written)\n";
      return usage;
    }
  }
  std::optional<audio::Recorder> sound;  // --audio: the listeners' stage, installed last
  SceneRunHooks hooks;
  hooks.stop = [] { return interrupt::received() > 0; };
  hooks.warn = [](const std::string& w) { std::cerr << "warning: " << w << '\n'; };
  if (!o.audio.empty())
    hooks.attach = [&](Simulator& sim) {
      sound.emplace(scene.audio, run.settings().step).attach(sim);
    };
  // From here on the loop polls the interrupts and the files end complete.
  hooks.loaded = [] { interrupt::counted(); };
  hooks.finish = [&](const Simulator&) {
    if (sound) write_sound(*sound, o.audio);
  };
  const SceneRunReport& r = run.run(hooks);
  if (!r.written) {  // refused or interrupted before the output folder was made
    std::cerr << r.error << '\n';
    return r.exit;
  }
  if (r.exit != ok && r.exit != blow_up && r.exit != interrupted) {  // an output or a checkpoint
    std::cerr << r.error << '\n';
    return r.exit;
  }
  return report_run(run, sound.has_value());
}

namespace {

struct BenchRow {
  std::string backend;
  std::uint64_t points = 0, links = 0;
  int threads = 1;
  double seconds = 1e300;               // the fastest repetition
  std::map<std::string, double> stage;  // ns in that repetition, by profile stage
};

// The fastest of o.repeat timed runs of o.steps steps, each after o.warmup untimed ones. A device
// backend runs asynchronously: the clock starts and stops on a finished device (Simulator::wait).
std::optional<BenchRow> bench_backend(const Scene& scene, SimulationSettings settings,
                                      const BenchOptions& o, int& exit_code) {
  BenchRow row;
  row.backend = settings.backend;
  for (int r = 0; r < o.repeat; ++r) {
    std::optional<Simulator> built;
    try {
      built.emplace(scene.model, settings);
    } catch (const std::exception& e) {
      std::cerr << o.scene << ": error: " << e.what() << '\n';
      exit_code = bad_input;
      return std::nullopt;
    }
    Simulator& sim = *built;
    row.points = sim.model().points.size();
    row.links = sim.model().links.total();
    if (o.warmup > 0 && !sim.run_steps(o.warmup)) {
      std::cerr << "error: " << sim.blow_up()->message << '\n';
      exit_code = blow_up;
      return std::nullopt;
    }
    sim.wait();
    std::map<std::string, double> before;  // stage times of the warm-up, not reported
    for (const auto& s : sim.profile().stages()) before[s.name] = s.total_ns;
    const auto t0 = WallClock::now();
    bool fine = sim.run_steps(o.steps);
    sim.wait();
    const double wall = seconds_since(t0);
    if (fine) fine = sim.check_energy();  // a device flags non-finite values at its cadence
    if (!fine) {
      std::cerr << "error: " << sim.blow_up()->message << '\n';
      exit_code = blow_up;
      return std::nullopt;
    }
    if (wall < row.seconds) {
      row.seconds = wall;
      row.threads = sim.threads();  // the default's changes with the cores during the run
      for (const auto& s : sim.profile().stages()) row.stage[s.name] = s.total_ns - before[s.name];
    }
  }
  return row;
}

}  // namespace

int bench(const BenchOptions& o) {
  auto scene = load_or_report(o.scene, o.sets);
  if (!scene) return bad_input;
  SimulationSettings settings = scene->settings;
  if (o.threads) settings.threads = *o.threads;
  if (o.no_self_collision) settings.disabled_stages.push_back("self_collision");
  if (o.gpu_device) settings.backend_options.device = *o.gpu_device;
  settings.publish_every = kNeverEvery;  // no publication cost in a benchmark
  settings.sample_every = kNeverEvery;
  std::vector<std::string> backends = o.backends;
  if (backends.empty()) backends.push_back(settings.backend);
  std::vector<BenchRow> rows;
  for (const auto& b : backends) {
    settings.backend = b;
    int code = ok;
    auto row = bench_backend(*scene, settings, o, code);
    if (!row) return code;
    rows.push_back(std::move(*row));
  }
  // Stage columns: every stage any backend timed (a device backend times fewer), empty where a
  // backend has none.
  std::vector<std::string> stages;
  for (const auto& r : rows)
    for (const auto& [name, ns] : r.stage)
      if (std::find(stages.begin(), stages.end(), name) == stages.end()) stages.push_back(name);
  std::sort(stages.begin(), stages.end());
  if (o.header) {
    std::printf(
        "scene,points,links,threads,steps,seconds,ns_per_particle_step,backend,"
        "particle_steps_per_second");
    for (const auto& name : stages) std::printf(",ns_pps_%s", name.c_str());
    std::printf("\n");
  }
  for (const auto& r : rows) {
    const double ps = double(o.steps) * double(r.points);
    std::printf("%s,%llu,%llu,%d,%llu,%.6g,%.4g,%s,%.4g", scene->name.c_str(),
                static_cast<unsigned long long>(r.points), static_cast<unsigned long long>(r.links),
                r.threads, static_cast<unsigned long long>(o.steps), r.seconds,
                r.seconds * 1e9 / ps, r.backend.c_str(), ps / r.seconds);
    for (const auto& name : stages) {
      const auto it = r.stage.find(name);
      if (it == r.stage.end())
        std::printf(",");
      else
        std::printf(",%.4g", it->second / ps);
    }
    std::printf("\n");
  }
  return ok;
}

#ifdef MAILLE_WITH_RENDER
namespace {

// A one-line progress bar on stderr, redrawn in place, only when stderr is a terminal (logs and
// tests get the summary line alone).
class ProgressBar {
 public:
  ProgressBar() : tty_(isatty(STDERR_FILENO) == 1), t0_(WallClock::now()) {}
  ~ProgressBar() {
    if (drawn_) std::fputc('\n', stderr);
  }
  void update(std::uint64_t done, std::uint64_t total) {
    if (!tty_ || total == 0) return;
    const double elapsed = seconds_since(t0_);
    if (done < total && elapsed - last_ < 0.1) return;  // at most 10 redraws per second
    last_ = elapsed;
    constexpr int kWidth = 30;
    const double f = double(done) / double(total);
    const int filled = static_cast<int>(f * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '=');
    if (filled < kWidth)
      bar += '>' + std::string(static_cast<std::size_t>(kWidth - filled - 1), ' ');
    const double left = done > 0 ? elapsed * double(total - done) / double(done) : 0;
    std::fprintf(stderr, "\r[%s] %3d%% frame %llu/%llu, %.0f s left ", bar.c_str(),
                 static_cast<int>(f * 100), static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(total), left);
    std::fflush(stderr);
    drawn_ = true;
  }

 private:
  bool tty_;
  bool drawn_ = false;
  WallClock::time_point t0_;
  double last_ = -1;
};

// "yaw,pitch[,zoom]" in degrees, degrees and a distance factor.
std::string camera_text(const std::vector<double>& v) {
  std::ostringstream s;
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str();
}

// yaw, pitch[, zoom] as CLI11 split them (2 or 3 values: it refuses others).
bool set_camera(const std::vector<double>& v, render::MovieSettings& m) {
  if (v.size() < 2 || v.size() > 3) return false;
  const double zoom = v.size() == 3 ? v[2] : m.zoom;
  // Finite angles, a pitch that keeps the up vector defined, a zoom that frames something.
  if (!std::isfinite(v[0]) || !(std::abs(v[0]) <= 3600) || !(std::abs(v[1]) <= 89) ||
      !(zoom > 0.001 && zoom <= 1000))
    return false;
  m.yaw = v[0];
  m.pitch = v[1];
  m.zoom = zoom;
  return true;
}

}  // namespace

int render(const RenderCommandOptions& o) {
  interrupt::at_once(kLoadingInterrupted);
  auto scene = load_or_report(o.scene, o.sets);
  if (!scene) return bad_input;
  interrupt::counted();  // the movie's loop polls them (its simulator is built inside it)
  if (o.no_self_collision) scene->settings.disabled_stages.push_back("self_collision");
  if (!o.backend.empty()) scene->settings.backend = o.backend;
  if (o.gpu_device) scene->settings.backend_options.device = *o.gpu_device;
  render::MovieSettings m;
  for (const auto& text : o.stage_options) {
    const auto dot = text.find('.'), eq = text.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
      std::cerr << "--stage-option: expected STAGE.OPTION=VALUE, got '" << text << "'\n";
      return usage;
    }
    m.stage_options.push_back(
        {text.substr(0, dot), text.substr(dot + 1, eq - dot - 1), text.substr(eq + 1)});
  }
  m.width = o.width;
  m.height = o.height;
  m.fps = o.fps;
  m.duration = o.duration ? *o.duration : scene->settings.duration;
  m.samples = o.samples;
  m.options.links_on_surface = o.mesh;
  m.options.smooth = o.smooth;
  m.options.smooth_lod = o.lod;
  if (o.threads) m.threads = *o.threads;
  if (!set_camera(o.camera, m)) {
    std::cerr << "--camera: expected yaw,pitch[,zoom] (yaw within +-3600 degrees, pitch within "
                 "+-89 degrees, zoom in (0.001, 1000]), got '"
              << camera_text(o.camera) << "'\n";
    return usage;
  }
  const std::filesystem::path out(o.out);
  const std::string ext = out.extension().string();
  // Usage errors before anything is opened: the frame count and the video's even size.
  if (!steps_for(m.duration, scene->settings.step, "the duration")) return usage;
  if (const double frames = std::floor(m.duration * m.fps) + 1; frames > 1e7) {
    std::cerr << "error: " << m.duration << " s at " << m.fps << " frames per second is " << frames
              << " frames, more than the limit of 1e7\n";
    return usage;
  }
  if (ext == ".mp4" && (m.width % 2 || m.height % 2)) {
    std::cerr << "error: an MP4 video needs an even width and height (got " << m.width << "x"
              << m.height << ")\n";
    return usage;
  }
  try {
    std::unique_ptr<render::FrameSink> sink;
    if (ext == ".mp4") {
      if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
      sink = render::ffmpeg_video(out, m.width, m.height, m.fps);
    } else if (ext == ".png") {
      if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
      sink = render::png_still(out);
      m.last_frame_only = true;
    } else {
      sink = render::png_sequence(out);
    }
    // Ctrl-C inside a long implicit step abandons it (render_movie's stop request).
    m.stop_requested = [] { return interrupt::received() > 0; };
    const auto t0 = WallClock::now();
    render::MovieReport r;
    {
      ProgressBar bar;
      r = render::render_movie(*scene, m, *sink, [&](std::uint64_t done, std::uint64_t total) {
        bar.update(done, total);
        return interrupt::received() == 0;
      });
    }
    const double wall = seconds_since(t0);
    const double per_frame = r.frames ? 1e3 / double(r.frames) : 0.0;
    std::printf(
        "maille: render %s: %llu frames %dx%d (%.4g s simulated) in %.3g s wall: %.3g ms per "
        "frame drawing and reading back, %.3g ms writing, simulation %.3g s; %s\n",
        scene->name.c_str(), static_cast<unsigned long long>(r.frames), m.width, m.height,
        r.simulated, wall, r.render_seconds * per_frame, r.output_seconds * per_frame,
        r.simulate_seconds, sink->describe().c_str());
    std::printf("maille: OpenGL: %s\n", r.gl.c_str());
    if (r.blow_up) {
      std::cerr << "error: " << *r.blow_up << '\n';
      return blow_up;
    }
    if (r.interrupted) {
      std::cerr << "interrupted; the frames written so far are complete\n";
      return interrupted;
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "error: " << e.what() << '\n';
    return usage;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return output_error;
  }
  return ok;
}
#endif

}  // namespace maille::app
