// Private to the simulator's files (simulator.cpp, simulator_backend.cpp): the profile stage
// ids it times, and the timer.
#pragma once

#include <chrono>

#include "maille/profile.hpp"
#include "maille/simulator.hpp"

namespace maille {

struct Simulator::StageIds {
  int drive, clear, links, fields, integrate, after, health, publish;
  int active_links, wind_faces;
};

namespace detail {

// Times a block into a profile stage, when the profile times this step (two clock reads: at
// audio rate, with a stage or ten per step, a quarter of a small model's step).
class Timed {
 public:
  Timed(Profile& p, int stage) : p_(p), stage_(stage), on_(p.timing()) {
    if (on_) t0_ = std::chrono::steady_clock::now();
  }
  ~Timed() {
    if (!on_) return;
    const auto dt = std::chrono::steady_clock::now() - t0_;
    p_.add_time(stage_, static_cast<double>(std::chrono::nanoseconds(dt).count()));
  }
  Timed(const Timed&) = delete;
  Timed& operator=(const Timed&) = delete;

 private:
  Profile& p_;
  int stage_;
  bool on_;
  std::chrono::steady_clock::time_point t0_{};
};

}  // namespace detail
}  // namespace maille
