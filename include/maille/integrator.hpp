// Time-integration schemes. A scheme advances positions and velocities by one step h given the
// forces already computed at the current state; multi-stage schemes ask for more force passes.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/names.hpp"
#include "maille/profile.hpp"
#include "maille/registry.hpp"
#include "maille/stage.hpp"
#include "maille/stage_keys.hpp"
#include "maille/state.hpp"

namespace maille {

// Recomputes every force stage at the state's current x, v (and time, for driven points and
// gusts) into s.f().
class ForceEvaluator {
 public:
  virtual ~ForceEvaluator() = default;
  virtual void evaluate(State& s) = 0;
  // The same without the contact stages (implicit schemes only): the step's contact set stays
  // the one the last evaluate() found, and s.f() gets every other force at s. Newton iterates
  // use it (the set was found with a margin covering the step's motion).
  virtual void evaluate_keeping_contacts(State& s) { evaluate(s); }
  // The step's contacts (contact_set.hpp), found by the last evaluate() under an implicit
  // scheme: their forces are not in s.f(); solvers evaluate them.
  virtual const ContactSet& contacts() const {
    static const ContactSet none;
    return none;
  }
  // The contact stages search again at the iterate s (Stage::find_contacts_again): the set's
  // arrays are refilled in place, everywhere or (`moved` not empty) around those points only.
  // False when no stage searched.
  virtual bool find_contacts_again(State& /*s*/, std::span<const std::uint32_t> /*moved*/) {
    return false;
  }
  // Whether to abandon the step now (Ctrl-C during a step that may last minutes). Solvers ask
  // between their iterations (sweeps, CG and Newton iterations) and return at once when true;
  // the simulator then puts the state back to the step's start (Simulator::on_stop_request).
  virtual bool stop_requested() { return false; }
  // Whether an evaluation was refused (a non-finite state before a stage: the simulator
  // reports it as a blow-up); solvers then stop iterating on it.
  virtual bool failed() const { return false; }
};

// Implicit Euler's linear (or block) solver ([simulation.implicit] solver = "...").
enum class ImplicitSolver : std::uint8_t { matrix_free, eigen, vbd };
template <>
struct NameTable<ImplicitSolver> {
  static constexpr std::string_view what = "implicit solver";
  static constexpr std::array<Name<ImplicitSolver>, 3> names{{
      {ImplicitSolver::matrix_free, "matrix_free", "CG over the links' Jacobian blocks"},
      {ImplicitSolver::eigen, "eigen", "CG on an assembled Eigen sparse matrix"},
      {ImplicitSolver::vbd, "vbd", "vertex block descent: Newton steps per point, by colour"},
  }};
};

// VBD's coarse correction ([simulation.implicit] coarse = "..."; src/integrators/vbd_coarse.hpp).
enum class VbdCoarse : std::uint8_t { aggregates, off };
template <>
struct NameTable<VbdCoarse> {
  static constexpr std::string_view what = "coarse correction";
  static constexpr std::array<Name<VbdCoarse>, 2> names{{
      {VbdCoarse::aggregates, "aggregates",
       "a linear solve over aggregates of points every other sweep (convergence that does not "
       "degrade with resolution)"},
      {VbdCoarse::off, "off", "sweeps only (with the Chebyshev acceleration)"},
  }};
};

// Settings of the implicit scheme ([simulation.implicit] in scene files).
struct ImplicitSettings {
  ImplicitSolver solver = ImplicitSolver::matrix_free;
  Real tolerance = Real(1e-6);               // CG stops when |r| <= tolerance |b|
  int max_iterations = 1000;                 // CG iterations per solve
  int newton_iterations = 1;                 // CG: linearisations per step (1: Baraff-Witkin)
  int iterations = 10;                       // vbd: sweeps over every free point per step, >= 1
  Real acceleration = Real(0.9);             // vbd: Chebyshev factor rho in [0, 1); 0 = off
  VbdCoarse coarse = VbdCoarse::aggregates;  // vbd: the coarse correction (replaces Chebyshev)

  bool operator==(const ImplicitSettings&) const = default;
};

// [simulation.implicit]'s keys (stage_keys.hpp), declared in implicit_keys.cpp: the scene reader
// reads them, docs/scene-format.md's table is checked against them.
std::span<const StageKey<ImplicitSettings>> implicit_keys();

// For the test equation x'' = -w2 x - c x' (one mass on a damped spring), a scheme maps
// (x_n, v_n) to (x_n+1, v_n+1) = (I + N) (x_n, v_n). Schemes return the increment N rather than
// I + N: its entries are O(h), and deciding |eigenvalue of I + N| <= 1 from them avoids the
// cancellation against 1 that made tiny steps look unstable.
using Amplification = std::array<std::array<double, 2>, 2>;

// When the stages that rewrite forces and velocities after the fact (Phase::response: the facet
// method's inverse dynamics) run in a scheme's step.
enum class ResponseTiming : std::uint8_t {
  // On the step's forces and velocities, before the scheme moves the points by one kick and one
  // drift (leapfrog, symplectic and explicit Euler): the rewrite is what the drift uses.
  before_integration,
  // On the motion a solve proposes (implicit Euler: x_n+1 = x_n + h v_n+1): the stage sees x_n
  // with v_n+1 and the step's mean force m (v_n+1 - v_n) / h, tests the segment x_n -> x_n+1 and
  // rewrites v_n+1; the simulator then moves the points it changed to x_n + h v'.
  after_solve,
  // Never: the scheme evaluates forces at intermediate states (RK4, velocity Verlet), where one
  // rewrite of the step's first forces would be undone by the others.
  refused,
};

class Stage;

// The implicit scheme's registry name: the simulator, its integrator and stages that judge their
// settings under it test for it (the other schemes' names live in their registry entries only).
inline constexpr std::string_view kImplicitEuler = "implicit_euler";

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual std::string_view name() const = 0;
  // On entry s.f() holds the forces at (s.x, s.v, s.time); on exit s.x, s.v are advanced by h
  // (s.time is advanced by the simulator). Fixed and driven points are never moved here.
  virtual void advance(const Model& m, State& s, Real h, ForceEvaluator& forces,
                       Profile& profile) = 0;
  // Velocities at the time of s.x (schemes with staggered velocities synchronise them), for
  // kinetic energy. s.f() must hold the forces at s.x.
  virtual void synchronized_velocity(const Model& m, const State& s, Real h,
                                     std::span<Vec3> out) const;
  // Which velocity s.v() holds between steps (stages are told through StageContext).
  virtual VelocityTime velocity_time(const State&) const { return VelocityTime::synchronous; }
  virtual Amplification increment(double h, double w2, double c) const = 0;
  // Whether the scheme solves implicitly (contact stages then find_contacts instead of apply).
  virtual bool uses_jacobians() const { return false; }
  // Force evaluations per step (the simulator's own pass included): the cost unit.
  virtual int force_evaluations() const { return 1; }
  // When stages that rewrite forces or velocities after the fact (facet responses) run.
  virtual ResponseTiming response_timing() const { return ResponseTiming::before_integration; }
  // Whether positions advance with the velocity after the step's kick (StageContext).
  virtual bool drifts_after_kick() const { return true; }
  // Why the scheme cannot integrate this model (empty: it can).
  virtual std::string check(const Model&) const { return {}; }
  // Why the scheme cannot run with this installed stage (empty: it can). Non-const stage: the
  // check may ask what the stage offers to implicit solves (Stage::finds_contacts); the CPU
  // schemes refuse none today (response stages are refused through response_timing).
  virtual std::string check_stage(Stage&) const { return {}; }
  // Drop scratch buffers sized for a model (the scheme's history lives in the State).
  virtual void reset() {}

  // Schemes whose step is one kick and one drift (v += kick f/m; x += drift v, free points
  // only) say so, so that a compute backend (backend.hpp) can run them: the kick and drift of
  // the next step from state s, and the history to record after it. nullopt: the scheme runs
  // on the CPU only.
  struct KickDrift {
    Real kick = 0, drift = 0;
    SchemeHistory history_after;
  };
  virtual std::optional<KickDrift> kick_drift_step(const State&, Real) const {
    return std::nullopt;
  }
  // Implicit schemes: their solver's settings, so that a compute backend that solves the whole
  // step on its device (Backend::steps) can tell which solver it is asked for and its
  // iterations. nullptr for every other scheme.
  virtual const ImplicitSettings* implicit_settings() const { return nullptr; }
  // The threads of the scheme's own passes; between steps only, any number of times (the
  // default thread count follows the free cores during a run: simulator.hpp). Schemes that hand
  // it to solvers override it.
  virtual void set_threads(int threads) { threads_ = threads; }

  // Largest h with spectral radius <= 1 on the test equation: 0 when no step is stable
  // (explicit Euler without damping), +inf when every step is (implicit Euler).
  Real stable_step(Real w2, Real c) const;

 protected:
  int threads_ = 1;
};

struct SimulationSettings;

struct IntegratorEntry {
  std::string name;
  std::string description;
  std::function<std::unique_ptr<Integrator>(const ImplicitSettings&)> make;
};

class IntegratorRegistry : public Registry<IntegratorEntry, &IntegratorEntry::name> {
 public:
  using Entry = IntegratorEntry;
  IntegratorRegistry() : Registry("integrator registry") {}
  static const IntegratorRegistry& builtin();
};

// Whether every eigenvalue of I + N lies in the closed unit disk (up to rounding).
bool is_stable(const Amplification& increment);

}  // namespace maille
