#include "commands.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include <unistd.h>

#include "maille/backend.hpp"
#include "maille/checkpoint.hpp"
#include "maille/intersections.hpp"
#include "maille/io.hpp"
#include "maille/limits.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/smooth_surface.hpp"
#include "maille/stability.hpp"
#include "maille/sweep.hpp"
#include "maille/temporary_files.hpp"
#include "sound.hpp"
#ifdef MAILLE_WITH_RENDER
#include <cstdlib>
#include <memory>

#include "maille/render/movie.hpp"
#endif

namespace maille::app {

namespace {

std::atomic<bool> g_stop{false};

// The first stats row where the self-colliding cloth crosses itself (stats.csv
// `intersecting_pairs`, [self_collision] check): said once per run (`said`), with its step and
// time.
void warn_first_crossing(const EnergySample& e, const Profile& p, bool& said) {
  if (said) return;
  for (const Profile::Counter& c : p.counters())
    if (c.name == "intersecting_pairs" && c.last > 0) {
      said = true;
      std::cerr << "maille: warning: " << c.last << " pair" << (c.last == 1 ? "" : "s")
                << " of triangles of the self-colliding cloth cross at step " << e.step
                << " (t = " << e.time
                << " s): the cloth passes through itself (stats.csv intersecting_pairs; "
                   "[self_collision] check = \"every_step\" stops at the first)\n";
    }
}
// While a scene loads and its simulator is set up, nothing of this run is written yet and no
// loop polls g_stop: an interrupt then ends the process at once (exit 130), whatever step of
// the loading it is in (a long sampling, a large build).
std::atomic<bool> g_loading{false};
extern "C" void on_signal(int) {
  g_stop = true;
  if (!g_loading) return;
  remove_open_temporaries();
  constexpr char msg[] = "interrupted while loading the scene: nothing written\n";
  [[maybe_unused]] const auto n = ::write(2, msg, sizeof msg - 1);
  ::_exit(interrupted);
}

// Installed first thing by the commands, in the loading state; the commands that write files
// leave it (loading_done) once their simulator is built, so that an interrupt while frame 0 is
// written or during the run ends with complete files (and exit 130).
void install_interrupt_handler() {
  g_loading = true;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}
void loading_done() {
  g_loading = false;
}

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

// Creates the output directory; on failure says which and why ("Permission denied", "No space
// left on device", "Not a directory") and returns false (exit 4).
bool make_output_directory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!ec && std::filesystem::is_directory(dir, ec)) return true;
  std::cerr << "error: cannot create the output directory " << dir.string() << ": "
            << (ec ? ec.message() : std::string("a file of that name exists")) << '\n';
  return false;
}

// The number of steps a run of `duration` seconds takes, refused (usage error) above
// limits::max_steps: a run that cannot end is a mistake, not a request.
std::optional<std::uint64_t> steps_for(double duration, double step, const char* what) {
  const double n = std::round(duration / step);
  if (!(n <= double(limits::max_steps))) {
    std::cerr << "error: " << what << " " << duration << " s at a step of " << step << " s is " << n
              << " steps, more than the limit of " << double(limits::max_steps) << '\n';
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(n);
}

std::uint64_t points_of(const Model& m, PointKind k) {
  return m.points.count(k);
}

void warn_if_unstable(const Simulator& sim) {
  const auto& st = sim.stability();
  if (sim.settings().step > st.max_step)
    std::cerr << "warning: step " << sim.settings().step << " s exceeds the "
              << sim.integrator().name() << " stability estimate " << st.max_step << " s (set by "
              << st.link_kind << " links at point " << st.point << "); expect a blow-up\n";
}

// What the stages find doubtful in their settings (self-collision that can leak).
void warn_stages(const Simulator& sim) {
  for (const std::string& w : sim.stage_warnings()) std::cerr << "warning: " << w << '\n';
}

// The header and the first `rows` rows of a previous stats.csv (resuming from a checkpoint taken
// after those rows). Throws std::invalid_argument when the file has fewer.
std::vector<std::string> kept_stats(const std::filesystem::path& path, std::uint64_t rows) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (lines.size() < rows + 1 && std::getline(in, line)) lines.push_back(line);
  if (lines.size() < rows + 1)
    throw std::invalid_argument(path.string() + " has fewer rows than the checkpoint recorded (" +
                                std::to_string(rows) + "): cannot resume its statistics");
  return lines;
}

Checkpoint checkpoint_of(const Simulator& sim, std::uint64_t stats_rows) {
  return {sim.state(),         sim.settings().integrator,
          sim.settings().step, sim.frames_published(),
          stats_rows,          model_fingerprint(sim.model(), sim.settings())};
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What makes `--audio` name a file the run reads or writes otherwise (the scene, the output
// directory, its stats.csv, checkpoint.bin or a frame), or "" when it names none: a WAV written
// there would silently replace it.
std::string audio_clash(const std::filesystem::path& audio, const std::filesystem::path& scene,
                        const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(audio, ec);
  if (ec) return {};
  if (a == fs::weakly_canonical(scene, ec) || fs::equivalent(audio, scene, ec))
    return "it is the scene file";
  const fs::path dir = fs::weakly_canonical(out, ec);
  if (a == dir) return "it is the output directory";
  if (a.parent_path() != dir) return {};
  const std::string name = a.filename().string();
  if (name == "stats.csv" || name == "checkpoint.bin" || name == "stats.csv.tmp" ||
      name == "checkpoint.bin.tmp")
    return "the run writes its " + name + " there";
  if (name.rfind("frame_", 0) == 0)
    for (const auto& f : name_strings<FrameFormat>())
      if (a.extension() == "." + f) return "the run writes its frames under that name";
  return {};
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
  install_interrupt_handler();  // writes nothing: an interrupt ends it at once
  if (is_sweep_file(path)) return validate_sweep(path, sets);
  auto scene = load_or_report(path, sets);
  if (!scene) return bad_input;
  try {
    Simulator sim(std::move(scene->model), scene->settings);
    warn_if_unstable(sim);
    warn_stages(sim);
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
  install_interrupt_handler();  // writes nothing: an interrupt ends it at once
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
  warn_stages(sim);
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

int run(const RunOptions& o) {
  install_interrupt_handler();
  auto scene = load_or_report(o.scene, o.sets);
  if (!scene) return bad_input;
  SimulationSettings settings = scene->settings;
  if (o.no_self_collision) settings.disabled_stages.push_back("self_collision");
  if (o.every) settings.publish_every = *o.every;
  if (o.threads) settings.threads = *o.threads;
  if (!o.backend.empty()) settings.backend = o.backend;
  if (o.gpu_device) settings.backend_options.device = *o.gpu_device;
  const auto format = parse_frame_format(o.format);
  if (!format) {
    std::cerr << "unknown format '" << o.format << "'\n";
    return usage;
  }
  if (o.smooth && *format != FrameFormat::obj) {
    std::cerr << "--smooth writes OBJ frames: add --format obj\n";
    return usage;
  }
  const std::optional<std::uint64_t> steps =
      o.steps ? o.steps
              : steps_for(o.duration ? *o.duration : settings.duration, settings.step,
                          o.duration ? "--duration" : "the scene's duration");
  if (!steps) return usage;
  if (o.audio.empty() && !scene->audio.listeners.empty())
    std::printf(
        "maille: the scene has %zu [[listen]] channel%s: add --audio FILE.wav to write them\n",
        scene->audio.listeners.size(), scene->audio.listeners.size() == 1 ? "" : "s");
  if (!o.audio.empty()) {  // --audio: the scene must say what to listen to
    if (scene->audio.listeners.empty()) {
      std::cerr << o.scene
                << ": error: --audio: the scene has no [[listen]] table (docs/sound.md)\n";
      return bad_input;
    }
    if (!o.resume.empty()) {
      std::cerr << "error: --audio records from t = 0: it cannot be combined with --resume\n";
      return usage;
    }
    if (planned_wav_bytes(scene->audio, double(*steps) * settings.step) > max_wav_data_bytes) {
      std::cerr << "error: --audio: " << double(*steps) * settings.step << " s of "
                << scene->audio.listeners.size()
                << " channels is beyond the 4 GiB a WAV file can hold\n";
      return usage;
    }
    // The channels are held in memory until the end (the gain is set from their peaks): a
    // recording beyond the memory budget would die of it after minutes, losing everything.
    const double held =
        double(planned_audio_memory_bytes(scene->audio, double(*steps) * settings.step));
    if (held > double(limits::memory_budget_bytes())) {
      std::cerr << "error: --audio: " << double(*steps) * settings.step << " s of "
                << scene->audio.listeners.size() << " channels at " << scene->audio.settings.rate
                << " Hz are held in memory until the end, about " << held / double(1 << 30)
                << " GiB, beyond the memory budget of "
                << double(limits::memory_budget_bytes()) / double(1 << 30)
                << " GiB (half the physical memory): shorten the run (--duration) or listen to "
                   "fewer points\n";
      return usage;
    }
  }
  // Refused before the output directory is made: nothing is left behind.
  if (o.smooth && SmoothSurface(scene->model).empty()) {
    std::cerr << o.scene << ": error: --smooth: the scene has no surface to smooth\n";
    return bad_input;
  }
  const std::filesystem::path out = !o.out.empty() ? std::filesystem::path(o.out)
                                    : !o.resume.empty()
                                        ? std::filesystem::path(o.resume)
                                        : std::filesystem::path("out") / scene->name;

  if (!o.audio.empty()) {
    const std::string clash = audio_clash(o.audio, o.scene, out);
    if (!clash.empty()) {
      std::cerr << "error: --audio " << o.audio << ": " << clash
                << "; name another file (nothing was written)\n";
      return usage;
    }
  }
  // The simulator first: a set-up it refuses (a stage the GPU backend lacks, a device that
  // cannot start) leaves no output directory behind.
  std::optional<Simulator> built;
  std::optional<audio::Recorder> sound;  // --audio: the listeners' stage, installed last
  try {
    built.emplace(std::move(scene->model), settings);
    // stats.csv reads the timings of the sampled steps only: the others read no clock.
    built->set_stage_timing(Simulator::StageTiming::sampled_steps);
    if (!o.audio.empty()) sound.emplace(scene->audio, settings.step).attach(*built);
  } catch (const std::invalid_argument& e) {
    std::cerr << o.scene << ": error: " << e.what() << '\n';
    return bad_input;
  }
  loading_done();  // from here on the loop polls g_stop and the files end complete
  if (g_stop) {
    std::cerr << "interrupted while loading the scene: nothing written\n";
    return interrupted;
  }
  if (!make_output_directory(out)) return output_error;
  try {
    Simulator& sim = *built;
    warn_if_unstable(sim);
    warn_stages(sim);
    // Resuming: the state, the frame count and the statistics rows continue from the
    // checkpoint; `--steps`/`--duration` still count from the start of the simulation.
    std::vector<std::string> kept;
    if (!o.resume.empty()) {
      const auto path = std::filesystem::path(o.resume) / "checkpoint.bin";
      Result<Checkpoint> c = read_checkpoint(path, model_fingerprint(sim.model(), sim.settings()));
      if (!c) {
        std::cerr << c.error().to_string() << '\n';
        return bad_input;
      }
      if (c->integrator != settings.integrator || c->step != settings.step)
        throw std::invalid_argument(path.string() + ": " +
                                    scheme_mismatch(c->integrator, c->step, "the scene now says",
                                                    settings.integrator, settings.step));
      kept = kept_stats(std::filesystem::path(o.resume) / "stats.csv", c->stats_rows);
      sim.restore(std::move(c->state), c->frames_published);
    }
    FrameWriter frames(out, *format, sim.model(), o.smooth ? o.lod : 0);
    StatsWriter stats(out / "stats.csv", kept);
    if (!o.no_frames) sim.on_publish([&](const Snapshot& s) { frames(s); });
    bool crossing_said = false;
    sim.on_sample([&](const EnergySample& e, const Profile& p) {
      stats.write(e, p);
      warn_first_crossing(e, p, crossing_said);
    });
    // Ctrl-C inside a long implicit step abandons it: the state of the last whole step stays.
    sim.on_stop_request([] { return g_stop.load(); });
    if (o.resume.empty() && !g_stop) sim.publish_now();  // frame 0: the initial state
    auto checkpoint = [&] {
      write_checkpoint(out / "checkpoint.bin", checkpoint_of(sim, stats.rows()));
    };

    const auto t0 = std::chrono::steady_clock::now();
    std::uint64_t done = 0;
    while (sim.steps_taken() < *steps && !g_stop && sim.step()) {
      ++done;
      if (o.checkpoint_every && sim.steps_taken() % *o.checkpoint_every == 0) checkpoint();
    }
    if (!sim.blow_up()) sim.check_energy();  // a runaway since the last check
    const double wall = seconds_since(t0);
    if (o.checkpoint_every && !sim.blow_up() && sim.steps_taken() % *o.checkpoint_every != 0)
      checkpoint();              // where this run stopped (the end, or an interrupt)
    stats.close(sim.profile());  // the header is there even when no row is
    // What was simulated, whole: after a blow-up up to it, after Ctrl-C up to the last step.
    if (sound) write_sound(*sound, o.audio);

    const double particle_steps = double(done) * sim.model().points.size();
    std::printf(
        "maille: %s: %llu steps (%.4g s simulated) in %.3g s wall, %.3g ns per particle-step, "
        "%llu frames and %llu stats rows in %s\n",
        scene->name.c_str(), static_cast<unsigned long long>(done), double(done) * settings.step,
        wall, particle_steps > 0 ? wall * 1e9 / particle_steps : 0.0,
        static_cast<unsigned long long>(frames.written()),
        static_cast<unsigned long long>(stats.rows()), out.string().c_str());
    if (const std::string note = unconverged_text(sim); !note.empty())
      std::cerr << "warning: " << note << '\n';
    if (sim.blow_up()) {
      std::cerr << "error: " << sim.blow_up()->message << '\n';
      return blow_up;
    }
    if (g_stop) {
      std::cerr << "interrupted at step " << sim.steps_taken() << "; the frames and stats"
                << (sound ? " written so far and the audio of the simulated time"
                          : " written so far")
                << " are complete\n";
      return interrupted;
    }
    const Energies e = sim.energies();
    if (!std::isfinite(e.total())) {  // check_energy catches it; never exit 0 with one
      std::cerr << "error: the final energy is not finite\n";
      return blow_up;
    }
    std::printf(
        "maille: final energy %.6g J (kinetic %.6g, elastic %.6g, gravity %.6g, contact %.6g)\n",
        e.total(), e.kinetic, e.elastic, e.gravity, e.contact);
  } catch (const std::runtime_error& e) {
    std::cerr << "error: " << e.what() << '\n';
    return output_error;
  } catch (const std::invalid_argument& e) {
    std::cerr << o.scene << ": error: " << e.what() << '\n';
    return bad_input;
  } catch (const std::bad_alloc&) {
    std::cerr << o.scene << ": error: out of memory\n";
    return bad_input;
  }
  return ok;
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
    const auto t0 = std::chrono::steady_clock::now();
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
  ProgressBar() : tty_(isatty(STDERR_FILENO) == 1), t0_(std::chrono::steady_clock::now()) {}
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
  std::chrono::steady_clock::time_point t0_;
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
  install_interrupt_handler();
  auto scene = load_or_report(o.scene, o.sets);
  if (!scene) return bad_input;
  loading_done();  // the movie's loop polls g_stop (its simulator is built inside it)
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
    m.stop_requested = [] { return g_stop.load(); };
    const auto t0 = std::chrono::steady_clock::now();
    render::MovieReport r;
    {
      ProgressBar bar;
      r = render::render_movie(*scene, m, *sink, [&](std::uint64_t done, std::uint64_t total) {
        bar.update(done, total);
        return !g_stop;
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
