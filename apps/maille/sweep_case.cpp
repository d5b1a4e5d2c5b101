#include "sweep_case.hpp"

#include <charconv>
#include <fstream>
#include <sstream>

#include "maille/clock.hpp"
#include "maille/io.hpp"
#include "maille/scene_run.hpp"

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

CaseResult failed(CaseResult r, int code, std::string message) {
  r.status = "error";
  r.exit_code = code;
  r.message = std::move(message);
  r.retry = code == exit_code::output_error;  // the disk, not the case: run it again
  return r;
}

// The case itself, as `maille run SCENE --set ... --duration D --no-frames` runs it: the same
// SceneRun, with frames when the sweep asks for them. A second Ctrl-C (or mpirun's SIGTERM
// after its SIGINT) abandons it between two steps, or inside a long implicit step.
CaseResult simulate(const Sweep& sweep, std::uint64_t index, const std::filesystem::path& dir,
                    std::optional<int> threads, CaseResult r, const std::atomic<int>& stop) {
  SceneRunOptions o;
  o.scene = sweep.scene;
  o.sets = sweep.overrides(index);
  o.duration = sweep.duration;
  o.duration_name = sweep.duration ? "the sweep's duration" : "the scene's duration";
  o.threads = threads;
  o.out = dir;
  o.frames = sweep.frames;
  SceneRun run(std::move(o));
  if (!run.load()) return failed(std::move(r), run.report().exit, run.report().error);
  SceneRunHooks hooks;
  hooks.stop = [&stop] { return stop.load() >= 2; };
  const SceneRunReport& done = run.run(hooks);
  r.simulated_seconds = done.simulated;
  if (done.exit == exit_code::blow_up) {
    r.status = "blowup";
    r.exit_code = exit_code::blow_up;
    r.message = done.blow_up ? done.blow_up->message : done.error;
  } else if (done.exit == exit_code::interrupted) {
    r = failed(std::move(r), exit_code::interrupted, "interrupted");
    r.retry = true;  // abandoned by a second Ctrl-C: a rerun runs it
  } else if (done.exit != exit_code::ok) {
    return failed(std::move(r), done.exit, done.error);
  } else {
    r.status = "ok";
    r.final_energy = done.energies->total();
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
  const auto t0 = WallClock::now();
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
    r = failed(std::move(r), exit_code::output_error, std::string("error: ") + e.what());
  } catch (const std::invalid_argument& e) {
    r = failed(std::move(r), exit_code::bad_input, sweep.scene.string() + ": error: " + e.what());
  } catch (const std::bad_alloc&) {
    r = failed(std::move(r), exit_code::bad_input, sweep.scene.string() + ": error: out of memory");
  }
  r.wall_seconds = seconds_since(t0);
  if (r.retry) return r;
  // The marker last: its presence means every other file of the case is complete.
  try {
    AtomicFile marker(dir / "done");
    marker.stream() << r.serialize();
    marker.commit();
  } catch (const std::runtime_error& e) {
    r = failed(std::move(r), exit_code::output_error, std::string("error: ") + e.what());
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
