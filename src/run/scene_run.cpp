#include "maille/scene_run.hpp"

#include <cmath>
#include <fstream>
#include <new>
#include <sstream>
#include <stdexcept>

#include "maille/checkpoint.hpp"
#include "maille/clock.hpp"
#include "maille/limits.hpp"

namespace maille {

namespace {

// The first stats row where the self-colliding cloth crosses itself (stats.csv
// `intersecting_pairs`, [self_collision] check): said once per run (`said`), with its step and
// time.
std::optional<std::string> first_crossing(const EnergySample& e, const Profile& p, bool& said) {
  if (said) return std::nullopt;
  for (const Profile::Counter& c : p.counters())
    if (c.name == "intersecting_pairs" && c.last > 0) {
      said = true;
      std::ostringstream m;
      m << c.last << " pair" << (c.last == 1 ? "" : "s")
        << " of triangles of the self-colliding cloth cross at step " << e.step
        << " (t = " << e.time
        << " s): the cloth passes through itself (stats.csv intersecting_pairs; "
           "[self_collision] check = \"every_step\" stops at the first)";
      return m.str();
    }
  return std::nullopt;
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

}  // namespace

std::vector<std::string> setup_warnings(const Simulator& sim) {
  std::vector<std::string> out;
  const auto& st = sim.stability();
  if (sim.settings().step > st.max_step) {
    std::ostringstream m;
    m << "step " << sim.settings().step << " s exceeds the " << sim.integrator().name()
      << " stability estimate " << st.max_step << " s (set by " << st.link_kind
      << " links at point " << st.point << "); expect a blow-up";
    out.push_back(m.str());
  }
  for (const std::string& w : sim.stage_warnings()) out.push_back(w);
  return out;
}

SceneRun::SceneRun(SceneRunOptions options) : o_(std::move(options)) {}

void SceneRun::refuse(int exit, std::string error) {
  report_.exit = exit;
  report_.error = std::move(error);
}

bool SceneRun::load() {
  try {
    Result<Scene> r = load_scene(o_.scene, o_.sets);
    if (!r) {
      report_.input = r.error();
      refuse(exit_code::bad_input, r.error().to_string());
      return false;
    }
    scene_ = std::move(r.value());
  } catch (const std::bad_alloc&) {  // the size checks should make this unreachable
    refuse(exit_code::bad_input,
           o_.scene.string() + ": error: out of memory while building the scene");
    return false;
  }
  settings_ = scene_.settings;
  if (o_.no_self_collision) settings_.disabled_stages.push_back("self_collision");
  if (o_.every) settings_.publish_every = *o_.every;
  if (o_.threads) settings_.threads = *o_.threads;
  if (!o_.backend.empty()) settings_.backend = o_.backend;
  if (o_.gpu_device) settings_.backend_options.device = *o_.gpu_device;
  out_ = !o_.out.empty()      ? o_.out
         : !o_.resume.empty() ? o_.resume
                              : "out" / std::filesystem::path(scene_.name);
  if (o_.steps) {
    steps_ = *o_.steps;
    return true;
  }
  // A run that cannot end is a mistake, not a request: refused above limits::max_steps.
  const double duration = o_.duration ? *o_.duration : settings_.duration;
  const double n = std::round(duration / settings_.step);
  if (!(n <= double(limits::max_steps))) {
    const std::string what = !o_.duration_name.empty() ? o_.duration_name
                             : o_.duration             ? "the duration"
                                                       : "the scene's duration";
    std::ostringstream m;
    m << "error: " << what << " " << duration << " s at a step of " << settings_.step << " s is "
      << n << " steps, more than the limit of " << double(limits::max_steps);
    refuse(exit_code::usage, m.str());
    return false;
  }
  steps_ = static_cast<std::uint64_t>(n);
  return true;
}

const SceneRunReport& SceneRun::run(const SceneRunHooks& hooks) {
  const std::string scene = o_.scene.string();
  // The simulator first: a set-up it refuses (a stage the GPU backend lacks, a device that
  // cannot start) leaves no output directory behind.
  std::optional<Simulator> built;
  try {
    built.emplace(std::move(scene_.model), settings_);
    // stats.csv reads the timings of the sampled steps only: the others read no clock.
    built->set_stage_timing(Simulator::StageTiming::sampled_steps);
    if (hooks.attach) hooks.attach(*built);
  } catch (const std::invalid_argument& e) {
    report_.input = InputError{scene, 0, 0, "", e.what()};
    refuse(exit_code::bad_input, scene + ": error: " + e.what());
    return report_;
  } catch (const std::bad_alloc&) {
    refuse(exit_code::bad_input, scene + ": error: out of memory");
    return report_;
  }
  if (hooks.loaded) hooks.loaded();
  if (hooks.stop && hooks.stop()) {
    refuse(exit_code::interrupted, "interrupted while loading the scene: nothing written");
    return report_;
  }
  std::error_code ec;
  std::filesystem::create_directories(out_, ec);
  if (ec || !std::filesystem::is_directory(out_, ec)) {  // "Permission denied", "No space ..."
    refuse(exit_code::output_error,
           "error: cannot create the output directory " + out_.string() + ": " +
               (ec ? ec.message() : std::string("a file of that name exists")));
    return report_;
  }
  report_.written = true;
  try {
    simulate(*built, hooks);
  } catch (const std::runtime_error& e) {
    refuse(exit_code::output_error, std::string("error: ") + e.what());
  } catch (const std::invalid_argument& e) {
    report_.input = InputError{scene, 0, 0, "", e.what()};
    refuse(exit_code::bad_input, scene + ": error: " + e.what());
  } catch (const std::bad_alloc&) {
    refuse(exit_code::bad_input, scene + ": error: out of memory");
  }
  return report_;
}

void SceneRun::simulate(Simulator& sim, const SceneRunHooks& hooks) {
  auto warn = [&](const std::string& w) {
    if (hooks.warn) hooks.warn(w);
  };
  auto stop = [&] { return hooks.stop && hooks.stop(); };
  report_.points = sim.model().points.size();
  for (const std::string& w : setup_warnings(sim)) warn(w);
  // Resuming: the state, the frame count and the statistics rows continue from the checkpoint;
  // the steps still count from the start of the simulation.
  std::vector<std::string> kept;
  if (!o_.resume.empty()) {
    const auto path = o_.resume / "checkpoint.bin";
    Result<Checkpoint> c = read_checkpoint(path, model_fingerprint(sim.model(), sim.settings()));
    if (!c) {
      report_.input = c.error();
      return refuse(exit_code::bad_input, c.error().to_string());
    }
    if (c->integrator != settings_.integrator || c->step != settings_.step)
      throw std::invalid_argument(path.string() + ": " +
                                  scheme_mismatch(c->integrator, c->step, "the scene now says",
                                                  settings_.integrator, settings_.step));
    kept = kept_stats(o_.resume / "stats.csv", c->stats_rows);
    sim.restore(std::move(c->state), c->frames_published);
  }
  FrameWriter frames(out_, o_.format, sim.model(), o_.smooth_lod);
  StatsWriter stats(out_ / "stats.csv", kept);
  if (o_.frames) sim.on_publish([&](const Snapshot& s) { frames(s); });
  bool crossing_said = false;
  sim.on_sample([&](const EnergySample& e, const Profile& p) {
    stats.write(e, p);
    if (auto w = first_crossing(e, p, crossing_said)) warn(*w);
  });
  // A stop asked for inside a long implicit step abandons it: the last whole step's state stays.
  if (hooks.stop) sim.on_stop_request(hooks.stop);
  if (o_.resume.empty() && !stop()) sim.publish_now();  // frame 0: the initial state
  auto checkpoint = [&] {
    write_checkpoint(out_ / "checkpoint.bin", checkpoint_of(sim, stats.rows()));
  };
  const std::optional<std::uint64_t> every = o_.checkpoint_every;

  const auto t0 = WallClock::now();
  std::uint64_t done = 0;
  while (sim.steps_taken() < steps_ && !stop() && sim.step()) {
    ++done;
    if (every && sim.steps_taken() % *every == 0) checkpoint();
  }
  if (!sim.blow_up()) sim.check_energy();  // a runaway since the last check
  report_.wall = seconds_since(t0);
  if (every && !sim.blow_up() && sim.steps_taken() % *every != 0)
    checkpoint();              // where this run stopped (the end, or an interrupt)
  stats.close(sim.profile());  // the header is there even when no row is
  // What was simulated, whole: after a blow-up up to it, after a stop up to the last step.
  if (hooks.finish) hooks.finish(sim);

  report_.steps_run = done;
  report_.steps_taken = sim.steps_taken();
  report_.simulated = sim.time();
  report_.frames = frames.written();
  report_.stats_rows = stats.rows();
  report_.unconverged = unconverged_text(sim);
  if (sim.blow_up()) {
    report_.blow_up = *sim.blow_up();
    return refuse(exit_code::blow_up, "error: " + sim.blow_up()->message);
  }
  if (stop()) return refuse(exit_code::interrupted, {});
  const Energies e = sim.energies();
  if (!std::isfinite(e.total()))  // check_energy catches it; never exit 0 with one
    return refuse(exit_code::blow_up, "error: the final energy is not finite");
  report_.energies = e;
}

}  // namespace maille
