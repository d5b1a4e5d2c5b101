#include "commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include <unistd.h>

#include "command_support.hpp"
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

namespace maille::app {

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

}  // namespace maille::app
