// Per-step timings and counters: every stage of the step is timed into one of these.
#pragma once

#include <cstdint>
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

}  // namespace maille
