#include "sweep.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "maille/clock.hpp"
#include "maille/interrupt.hpp"
#include "maille/io.hpp"
#include "maille/sweep.hpp"
#include "sweep_case.hpp"
#include "sweep_world.hpp"

namespace maille::app {

namespace {

namespace fs = std::filesystem;

// Ctrl-C (SIGINT) or SIGTERM (interrupt.hpp, counted): the first stops handing out cases (the
// running ones finish), the second abandons the running ones between two steps (a rerun runs
// them again).
constexpr char kStopping[] =
    "\nmaille sweep: stopping after the current cases (a second Ctrl-C abandons them)\n";

// A rank bound to fewer cores than it has threads (mpirun binds each rank to one core when it
// starts two or fewer) runs its threads on top of each other: say so.
void warn_if_bound(int rank, std::optional<int> threads) {
  cpu_set_t set;
  if (!threads || *threads <= 1 || sched_getaffinity(0, sizeof set, &set) != 0) return;
  const int cores = CPU_COUNT(&set);
  if (cores >= *threads) return;
  std::ostringstream m;  // one write: the ranks' lines do not interleave
  m << "warning: rank " << rank << " runs " << *threads << " threads on " << cores
    << " core(s) (its binding): start it with mpirun --bind-to none, or --map-by "
       "ppr:1:node:pe="
    << *threads << "; srun --cpus-per-task=" << *threads << "\n";
  std::cerr << m.str();
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string field;
  while (std::getline(s, field, ',')) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

// FNV-1a of a file's bytes: an edited scene is another sweep.
std::string file_hash(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t h = 14695981039346656037ull;
  char c;
  while (in.get(c)) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  char buffer[20];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

// What makes the cases of DIR: written as DIR/sweep.txt by the first run, compared by reruns.
std::string identity(const Sweep& s) {
  std::ostringstream t;
  std::error_code ec;
  const fs::path scene = fs::weakly_canonical(s.scene, ec);
  t << "maille sweep 1\n"
    << "scene = " << (ec ? s.scene : scene).string() << '\n'
    << "scene_fnv1a = " << file_hash(s.scene) << '\n'
    << "duration = " << (s.duration ? number(*s.duration) : std::string("the scene's")) << '\n'
    << "frames = " << (s.frames ? "true" : "false") << '\n';
  for (const auto& a : s.axes) {
    t << "axis " << a.key << " =";
    for (const auto& v : a.values) t << ' ' << v;
    t << '\n';
  }
  t << "cases = " << s.case_count() << '\n';
  return t.str();
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every case's state, shared by rank 0's main thread and its dispatcher thread: the cases left
// to hand out, the results so far, and summary.csv rewritten (atomically) as results arrive.
class Ledger {
 public:
  Ledger(const Sweep& sweep, fs::path out) : sweep_(sweep), out_(std::move(out)) {}

  void add_done(CaseResult r) { results_.emplace(r.index, std::move(r)); }
  void add_todo(std::uint64_t i) { todo_.push_back(i); }
  std::size_t done() const { return results_.size(); }

  std::optional<std::uint64_t> take() {
    std::lock_guard lock(m_);
    if (interrupt::received().load() >= 1 || todo_.empty()) return std::nullopt;
    const std::uint64_t i = todo_.front();
    todo_.pop_front();
    return i;
  }

  void give_back(std::uint64_t i) {
    std::lock_guard lock(m_);
    todo_.push_front(i);
  }

  void record(CaseResult r) {
    std::lock_guard lock(m_);
    if (r.exit_code == interrupted) {  // abandoned at a second Ctrl-C: not done, a rerun runs it
      std::printf("maille sweep: case %s interrupted on rank %d\n", sweep_.case_id(r.index).c_str(),
                  r.rank);
      std::fflush(stdout);
      return;
    }
    if (r.exit_code == output_error) output_failed_ = true;
    std::string line = "maille sweep: case " + sweep_.case_id(r.index) + " " + r.status;
    if (r.status != "ok") {
      const std::string first = r.message.substr(0, r.message.find('\n'));
      line += " (exit " + std::to_string(r.exit_code) + ": " + first + ")";
    }
    std::printf("%s on rank %d in %.3g s [%zu of %llu]\n", line.c_str(), r.rank, r.wall_seconds,
                results_.size() + 1, static_cast<unsigned long long>(sweep_.case_count()));
    std::fflush(stdout);
    results_.insert_or_assign(r.index, std::move(r));
    dirty_ = true;
    flush_locked(false);
  }

  // Writes the summary when results arrived since the last write and it is time (at most one
  // write per second while cases run), or now when `force` (a stop, the end).
  void flush(bool force) {
    std::lock_guard lock(m_);
    flush_locked(force);
  }

  bool output_failed() const { return output_failed_; }
  // The counts of the final line: ok, blowup, error.
  std::map<std::string, int> counts() const {
    std::map<std::string, int> c;
    for (const auto& [i, r] : results_) ++c[r.status];
    return c;
  }

 private:
  void flush_locked(bool force) {
    if (!dirty_ && !force) return;
    const auto now = WallClock::now();
    if (!force && now - last_write_ < std::chrono::seconds(1)) return;
    try {
      write_summary();
      dirty_ = false;
    } catch (const std::runtime_error& e) {
      if (!summary_failed_) std::cerr << "error: " << e.what() << '\n';
      summary_failed_ = output_failed_ = true;
    }
    last_write_ = now;
  }

  // summary.csv: case, one column per axis, status ... final_energy, then the columns of the
  // cases' stats.csv (their union, in the order first met) filled from each case's last row.
  void write_summary() const {
    std::vector<std::string> stats_columns;
    for (const auto& [i, r] : results_)
      for (const auto& name : split(r.stats_header))
        if (std::find(stats_columns.begin(), stats_columns.end(), name) == stats_columns.end())
          stats_columns.push_back(name);
    AtomicFile file(out_ / "summary.csv");
    auto& o = file.stream();
    o << "case";
    for (const auto& a : sweep_.axes) o << ',' << csv_field(a.key);
    o << ",status,exit_code,message,rank,wall_seconds,simulated_seconds,final_energy";
    for (const auto& name : stats_columns) o << ',' << csv_field(name);
    o << '\n';
    for (const auto& [i, r] : results_) {
      o << sweep_.case_id(i);
      const auto c = sweep_.coordinates(i);
      for (std::size_t k = 0; k < sweep_.axes.size(); ++k)
        o << ',' << csv_field(sweep_.axes[k].labels[c[k]]);
      o << ',' << r.status << ',' << r.exit_code << ',' << csv_field(r.message) << ',' << r.rank
        << ',' << number(r.wall_seconds) << ',' << number(r.simulated_seconds) << ','
        << (r.final_energy ? number(*r.final_energy) : std::string());
      std::map<std::string, std::string> last;
      const auto names = split(r.stats_header), values = split(r.stats_last);
      for (std::size_t k = 0; k < names.size() && k < values.size(); ++k)
        last[names[k]] = values[k];
      for (const auto& name : stats_columns) {
        const auto it = last.find(name);
        o << ',' << (it == last.end() ? std::string() : csv_field(it->second));
      }
      o << '\n';
    }
    file.commit();
  }

  const Sweep& sweep_;
  fs::path out_;
  std::mutex m_;
  std::deque<std::uint64_t> todo_;
  std::map<std::uint64_t, CaseResult> results_;  // by case number: the summary's order
  bool dirty_ = true;
  bool output_failed_ = false, summary_failed_ = false;
  WallClock::time_point last_write_{};
};

// Rank 0, before any case runs: DIR and DIR/cases, the lock that keeps a second sweep out, the
// sweep's identity (a rerun must be the same sweep), and the cases an earlier run finished.
// Returns the exit code (ok to go on).
int prepare(const Sweep& sweep, const fs::path& out, Ledger& ledger, int& lock_fd) {
  std::error_code ec;
  fs::create_directories(out / "cases", ec);
  if (ec || !fs::is_directory(out / "cases", ec)) {
    std::cerr << "error: cannot create the output directory " << (out / "cases").string() << ": "
              << (ec ? ec.message() : std::string("a file of that name exists")) << '\n';
    return output_error;
  }
  lock_fd = ::open((out / "sweep.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd < 0) {
    std::cerr << "error: cannot write " << (out / "sweep.lock").string() << ": "
              << std::strerror(errno) << '\n';
    return output_error;
  }
  // A file system without locks (some parallel ones) cannot tell: go on.
  if (::flock(lock_fd, LOCK_EX | LOCK_NB) != 0 && (errno == EWOULDBLOCK || errno == EAGAIN)) {
    std::cerr << "error: another maille sweep is running in " << out.string()
              << " (it holds sweep.lock); wait for it to end, or give another --out\n";
    return bad_input;
  }
  const std::string id = identity(sweep);
  const fs::path id_path = out / "sweep.txt";
  if (fs::exists(id_path, ec)) {
    const std::string before = read_text(id_path);
    if (before != id) {
      std::cerr << id_path.string()
                << ": error: the folder holds the cases of another sweep (the axes, the "
                   "duration, the frames or the scene file differ); give another --out, or "
                   "remove it to start again\n--- there:\n"
                << before << "--- this sweep:\n"
                << id;
      return bad_input;
    }
  } else {
    try {
      AtomicFile f(id_path);
      f.stream() << id;
      f.commit();
    } catch (const std::runtime_error& e) {
      std::cerr << "error: " << e.what() << '\n';
      return output_error;
    }
  }
  for (std::uint64_t i = 0; i < sweep.case_count(); ++i) {
    if (auto r = read_marker(out / "cases" / sweep.case_id(i), i))
      ledger.add_done(std::move(*r));
    else
      ledger.add_todo(i);
  }
  return ok;
}

}  // namespace

int sweep(const SweepOptions& o) {
  const auto t0 = WallClock::now();
  std::unique_ptr<World> world = World::start();
  if (!world) return usage;
  const int rank = world->rank();
  warn_if_bound(rank, o.threads);
  interrupt::counted(rank == 0 ? kStopping : nullptr);  // one rank says it

  // Every rank reads the sweep file (a few lines); rank 0 alone checks it against the scene,
  // and every rank ends with rank 0's verdict. Nothing is written before it.
  Result<Sweep> read = load_sweep(o.sweep);
  int code = ok;
  if (!read) {
    if (rank == 0) std::cerr << read.error().to_string() << '\n';
    code = bad_input;
  } else if (rank == 0) {
    if (auto bad = check_sweep_keys(*read)) {
      std::cerr << bad->to_string() << '\n';
      code = bad_input;
    }
  }
  code = world->broadcast(code);
  if (code != ok) return code;
  const Sweep& sw = *read;
  const fs::path out(o.out);

  Ledger ledger(sw, out);
  int lock_fd = -1;
  if (rank == 0) code = prepare(sw, out, ledger, lock_fd);
  code = world->broadcast(code);
  if (code != ok) {
    if (lock_fd >= 0) ::close(lock_fd);
    return code;
  }
  auto run = [&](std::uint64_t i) {
    return run_case(sw, i, out / "cases" / sw.case_id(i), o.threads, rank, interrupt::received());
  };

  if (rank != 0) {
    world->work(run, interrupt::received());
    return world->broadcast(ok);
  }

  const std::size_t skipped = ledger.done();
  if (skipped > 0)
    std::printf("maille sweep: %zu of %llu cases already done in %s, skipped\n", skipped,
                static_cast<unsigned long long>(sw.case_count()), out.string().c_str());
  // The other ranks' requests, answered by a thread of rank 0 while its main thread runs
  // cases too (or, when the MPI library allows no other thread, by the main thread alone).
  std::atomic<bool> stop_seen{false};
  Dispatch d{[&] { return ledger.take(); }, [&](std::uint64_t i) { ledger.give_back(i); },
             [&](CaseResult r) { ledger.record(std::move(r)); },
             [&] {
               // A stop: the summary of the cases done goes to disk now (mpirun kills the
               // ranks a second after Ctrl-C).
               const bool stopping = interrupt::received().load() >= 1;
               ledger.flush(stopping && !stop_seen.exchange(stopping));
             }};
  std::thread dispatcher;
  if (world->size() > 1 && world->dispatcher_thread())
    dispatcher = std::thread([&] { world->serve(d); });
  else if (world->size() > 1) {
    std::cerr << "warning: the MPI library allows no second thread (MPI_THREAD_SERIALIZED): "
                 "rank 0 hands out cases and runs none\n";
    world->serve(d);
  }
  while (auto i = ledger.take()) ledger.record(run(*i));
  if (interrupt::received().load() >= 1) ledger.flush(true);
  if (dispatcher.joinable()) dispatcher.join();
  ledger.flush(true);
  ::close(lock_fd);

  const auto counts = ledger.counts();
  const auto count = [&](const char* s) {
    const auto it = counts.find(s);
    return it == counts.end() ? 0 : it->second;
  };
  std::printf(
      "maille sweep: %zu of %llu cases (%d ok, %d blowup, %d error; %zu done before) in %.3g s "
      "wall on %d rank%s; summary in %s\n",
      ledger.done(), static_cast<unsigned long long>(sw.case_count()), count("ok"), count("blowup"),
      count("error"), skipped, seconds_since(t0), world->size(), world->size() > 1 ? "s" : "",
      (out / "summary.csv").string().c_str());
  std::fflush(stdout);
  if (ledger.done() < sw.case_count()) {
    std::cerr << "interrupted: " << sw.case_count() - ledger.done()
              << " cases not run; the summary lists the cases done; run the same command again "
                 "to run the others\n";
    code = interrupted;
  } else if (ledger.output_failed()) {
    std::cerr << "error: some files could not be written (see above); the cases concerned run "
                 "again when the same command is run again\n";
    code = output_error;
  }
  return world->broadcast(code);
}

}  // namespace maille::app
