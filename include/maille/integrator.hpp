// Time-integration schemes. A scheme advances positions and velocities by one step h given the
// forces already computed at the current state; multi-stage schemes ask for more force passes.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/state.hpp"

namespace maille {

// Recomputes every force stage at the state's current x, v into s.f().
class ForceEvaluator {
 public:
  virtual ~ForceEvaluator() = default;
  virtual void evaluate(State& s) = 0;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual std::string_view name() const = 0;
  // On entry s.f() holds the forces at (s.x, s.v); on exit s.x, s.v are advanced by h.
  // Fixed and driven points (inverse mass 0) are never moved here.
  virtual void advance(const Model& m, State& s, Real h, ForceEvaluator& forces) = 0;
  // Velocities at the time of s.x (schemes with staggered velocities synchronise them), for
  // kinetic energy. s.f() must hold the forces at s.x.
  virtual void synchronized_velocity(const Model& m, const State& s, Real h,
                                     std::span<Vec3> out) const;
  // Largest stable step for the test equation x'' = -omega2 x - c x'.
  virtual Real stable_step(Real omega2, Real c) const = 0;
  // Forget any history (after a reset or a change of step).
  virtual void reset() {}
  void set_threads(int threads) { threads_ = threads; }

 protected:
  int threads_ = 1;
};

// The stability limit shared by the kick-drift schemes (leapfrog, symplectic Euler), from the
// Jury conditions of their recurrence on x'' = -w2 x - c x':  h^2 w2 + 2 h c < 4.
Real kick_drift_stable_step(Real omega2, Real c);

class IntegratorRegistry {
 public:
  struct Entry {
    std::string name;
    std::string description;
    std::function<std::unique_ptr<Integrator>()> make;
  };
  void add(Entry e) { entries_.push_back(std::move(e)); }
  const Entry* find(std::string_view name) const;
  std::span<const Entry> entries() const { return entries_; }
  std::string names() const;
  static const IntegratorRegistry& builtin();

 private:
  std::vector<Entry> entries_;
};

}  // namespace maille
