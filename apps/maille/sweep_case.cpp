#include "sweep_case.hpp"

#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "maille/io.hpp"
#include "maille/limits.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille::app {

namespace {

constexpr const char* kMarkerFormat = "maille-sweep-case 1";

// Shortest text that reads back to the same double.
std::string number(double v) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}

std::optional<double> to_double(const std::string& text) {
  double v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else
      out += c;
  }
  return out;
}

std::string unescape(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '\\' || i + 1 == s.size()) {
      out += s[i];
      continue;
    }
    const char c = s[++i];
    out += c == 'n' ? '\n' : c == 'r' ? '\r' : c;
  }
  return out;
}

// The first and the last line of a stats.csv (the header, and the last row when there is one).
void read_stats(const std::filesystem::path& path, CaseResult& r) {
  std::ifstream in(path);
  std::string line, last;
  std::uint64_t lines = 0;
  while (std::getline(in, line)) {
    if (lines++ == 0)
      r.stats_header = line;
    else
      last = line;
  }
  r.stats_last = last;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

CaseResult failed(CaseResult r, int exit_code, std::string message) {
  r.status = "error";
  r.exit_code = exit_code;
  r.message = std::move(message);
  r.retry = exit_code == 4;  // the disk, not the case: run it again next time
  return r;
}

// The case itself, as `maille run` runs a scene (apps/maille/commands.cpp, run()): the same
// settings, frame 0 published, the energy samples to stats.csv, the final runaway check.
CaseResult simulate(const Sweep& sweep, std::uint64_t index, const std::filesystem::path& dir,
                    std::optional<int> threads, CaseResult r, const std::atomic<int>& stop) {
  Result<Scene> scene = load_scene(sweep.scene, sweep.overrides(index));
  if (!scene) return failed(std::move(r), 1, scene.error().to_string());
  SimulationSettings settings = scene->settings;
  if (threads) settings.threads = *threads;
  const double duration = sweep.duration ? *sweep.duration : settings.duration;
  const double n = std::round(duration / settings.step);
  if (!(n <= double(limits::max_steps))) {
    std::ostringstream m;
    m << "the duration " << duration << " s at a step of " << settings.step << " s is " << n
      << " steps, more than the limit of " << double(limits::max_steps);
    return failed(std::move(r), 2, m.str());
  }
  const auto steps = static_cast<std::uint64_t>(n);
  std::optional<Simulator> built;
  try {
    built.emplace(std::move(scene->model), settings);
  } catch (const std::invalid_argument& e) {
    return failed(std::move(r), 1, sweep.scene.string() + ": error: " + e.what());
  }
  Simulator& sim = *built;
  std::optional<FrameWriter> frames;
  if (sweep.frames) frames.emplace(dir, FrameFormat::ply, sim.model());
  StatsWriter stats(dir / "stats.csv");
  if (frames) sim.on_publish([&](const Snapshot& s) { (*frames)(s); });
  sim.on_sample([&](const EnergySample& e, const Profile& p) { stats.write(e, p); });
  // A second Ctrl-C (or mpirun's SIGTERM after its SIGINT) abandons a long implicit step too.
  sim.on_stop_request([&stop] { return stop.load() >= 2; });
  sim.publish_now();  // frame 0: the initial state
  while (sim.steps_taken() < steps && stop.load() < 2 && sim.step()) {
  }
  if (!sim.blow_up()) sim.check_energy();  // a runaway since the last check
  stats.close(sim.profile());
  r.simulated_seconds = sim.time();
  if (sim.blow_up()) {
    r.status = "blowup";
    r.exit_code = 3;
    r.message = sim.blow_up()->message;
  } else if (sim.steps_taken() < steps) {
    r.retry = true;  // abandoned by a second Ctrl-C
    r.status = "error";
    r.exit_code = 130;
    r.message = "interrupted";
  } else {
    r.status = "ok";
    r.final_energy = sim.energies().total();
  }
  read_stats(dir / "stats.csv", r);
  return r;
}

}  // namespace

std::string CaseResult::serialize() const {
  std::ostringstream s;
  s << kMarkerFormat << '\n'
    << "index=" << index << '\n'
    << "status=" << status << '\n'
    << "exit_code=" << exit_code << '\n'
    << "rank=" << rank << '\n'
    << "wall_seconds=" << number(wall_seconds) << '\n'
    << "simulated_seconds=" << number(simulated_seconds) << '\n'
    << "final_energy=" << (final_energy ? number(*final_energy) : std::string()) << '\n'
    << "retry=" << (retry ? 1 : 0) << '\n'
    << "message=" << escape(message) << '\n'
    << "stats_header=" << escape(stats_header) << '\n'
    << "stats_last=" << escape(stats_last) << '\n';
  return s.str();
}

std::optional<CaseResult> CaseResult::parse(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kMarkerFormat) return std::nullopt;
  CaseResult r;
  int fields = 0;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) return std::nullopt;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    try {
      if (key == "index")
        r.index = std::stoull(value);
      else if (key == "status")
        r.status = value;
      else if (key == "exit_code")
        r.exit_code = std::stoi(value);
      else if (key == "rank")
        r.rank = std::stoi(value);
      else if (key == "retry")
        r.retry = value == "1";
      else if (key == "message")
        r.message = unescape(value);
      else if (key == "stats_header")
        r.stats_header = unescape(value);
      else if (key == "stats_last")
        r.stats_last = unescape(value);
      else if (key == "final_energy") {
        if (!value.empty()) {
          r.final_energy = to_double(value);
          if (!r.final_energy) return std::nullopt;
        }
      } else if (key == "wall_seconds" || key == "simulated_seconds") {
        const auto v = to_double(value);
        if (!v) return std::nullopt;
        (key == "wall_seconds" ? r.wall_seconds : r.simulated_seconds) = *v;
      } else {
        return std::nullopt;
      }
    } catch (const std::exception&) {  // stoull, stoi: not a number
      return std::nullopt;
    }
    ++fields;
  }
  if (fields != 11 || (r.status != "ok" && r.status != "blowup" && r.status != "error"))
    return std::nullopt;
  return r;
}

CaseResult run_case(const Sweep& sweep, std::uint64_t index, const std::filesystem::path& dir,
                    std::optional<int> threads, int rank, const std::atomic<int>& stop) {
  const auto t0 = std::chrono::steady_clock::now();
  CaseResult r;
  r.index = index;
  r.rank = rank;
  try {
    // What an earlier, killed run left here (a temporary file, the frames of half a case) goes.
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    if (ec) throw std::runtime_error("cannot clear " + dir.string() + ": " + ec.message());
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create " + dir.string() + ": " + ec.message());
    r = simulate(sweep, index, dir, threads, std::move(r), stop);
  } catch (const std::runtime_error& e) {  // output: the frames, stats.csv, the folder
    r = failed(std::move(r), 4, std::string("error: ") + e.what());
  } catch (const std::invalid_argument& e) {
    r = failed(std::move(r), 1, sweep.scene.string() + ": error: " + e.what());
  } catch (const std::bad_alloc&) {
    r = failed(std::move(r), 1, sweep.scene.string() + ": error: out of memory");
  }
  r.wall_seconds = seconds_since(t0);
  if (r.retry) return r;
  // The marker last: its presence means every other file of the case is complete.
  try {
    AtomicFile marker(dir / "done");
    marker.stream() << r.serialize();
    marker.commit();
  } catch (const std::runtime_error& e) {
    r = failed(std::move(r), 4, std::string("error: ") + e.what());
  }
  return r;
}

std::optional<CaseResult> read_marker(const std::filesystem::path& dir, std::uint64_t index) {
  std::ifstream in(dir / "done", std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  auto r = CaseResult::parse(text.str());
  if (!r || r->index != index || r->retry) return std::nullopt;
  return r;
}

}  // namespace maille::app
