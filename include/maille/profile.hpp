// Per-step timings and counters: every stage of the step is timed into one of these.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace maille {

class Profile {
 public:
  struct Stage {
    std::string name;
    double last_ns = 0;   // time spent in the stage during the last step, ns
    double total_ns = 0;  // since the start (or the last reset), ns
  };
  struct Counter {
    std::string name;
    std::uint64_t last = 0;   // value during the last step
    std::uint64_t total = 0;  // summed over steps
  };

  struct Gauge {
    std::string name;
    double last = 0;  // value set during the last step (e.g. a solver's final residual)
  };

  // Returns a handle; calling it twice with one name returns the same handle.
  int stage(const std::string& name);
  int counter(const std::string& name);
  int gauge(const std::string& name);
  void add_time(int stage, double ns);
  void set_count(int counter, std::uint64_t value);
  // Adds to a counter another stage set this evaluation (contacts between groups add their
  // active pairs to the link stage's active_conditional_links).
  void add_count(int counter, std::uint64_t value);
  void set_gauge(int gauge, double value) { gauges_[gauge].last = value; }
  void begin_step();  // zeroes the `last` values
  // Whether this step's stages are timed (Simulator::set_stage_timing): a step not timed reads
  // no clock and leaves its stages' last_ns at 0.
  void set_timing(bool on) { timing_ = on; }
  bool timing() const { return timing_; }

  const std::vector<Stage>& stages() const { return stages_; }
  const std::vector<Counter>& counters() const { return counters_; }
  const std::vector<Gauge>& gauges() const { return gauges_; }
  double total_ns() const;
  std::uint64_t steps() const { return steps_; }

 private:
  std::vector<Stage> stages_;
  std::vector<Counter> counters_;
  std::vector<Gauge> gauges_;
  std::uint64_t steps_ = 0;
  bool timing_ = true;
};

// Columns of stats.csv that a stage writes, named once in their order and registered with the
// profile at the first write (a stage meets the simulator's profile only when it runs):
// count(p, k, n), add(p, k, n) and gauge(p, k, x) write column k.
class ProfileColumns {
 public:
  struct Column {
    std::string name;
    bool gauge = false;  // a gauge (the last value set) rather than a counter
  };
  ProfileColumns() = default;
  ProfileColumns(std::initializer_list<Column> columns) : columns_(columns) {}
  bool empty() const { return columns_.empty(); }
  void count(Profile& p, std::size_t k, std::uint64_t value) { p.set_count(id(p, k), value); }
  void add(Profile& p, std::size_t k, std::uint64_t value) { p.add_count(id(p, k), value); }
  void gauge(Profile& p, std::size_t k, double value) { p.set_gauge(id(p, k), value); }

  // One column's value for set(): a whole number (a counter's count) or any number (a gauge's).
  struct Value {
    template <std::integral T>
    Value(T v) : count(static_cast<std::uint64_t>(v)), real(static_cast<double>(v)) {}
    template <std::floating_point T>
    Value(T v) : real(static_cast<double>(v)) {}
    std::uint64_t count = 0;
    double real = 0;
  };
  // Every column at once, in their order: a counter set to its count, a gauge to its value.
  void set(Profile& p, std::initializer_list<Value> values) {
    std::size_t k = 0;
    for (const Value& v : values) {
      if (columns_[k].gauge)
        gauge(p, k, v.real);
      else
        count(p, k, v.count);
      ++k;
    }
  }

 private:
  int id(Profile& p, std::size_t k) {
    if (ids_.empty())
      for (const Column& c : columns_)
        ids_.push_back(c.gauge ? p.gauge(c.name) : p.counter(c.name));
    return ids_[k];
  }
  std::vector<Column> columns_;
  std::vector<int> ids_;
};

}  // namespace maille
