// Stages: what plugs into the step beside the built-in forces (collisions, obstacles, the
// viewer's mouse spring). A stage declares its phase, and the simulator runs it there:
//
//   step():  [forces]            drive, clear, link forces, field forces, then Phase::forces
//                                stages (also re-run by multi-pass schemes at their
//                                intermediate states)
//            [response]          Phase::response stages: rewrite forces or velocities after the
//                                fact (inverse dynamics on facets); run once per step, never by
//                                Simulator::energies(), refused by schemes that evaluate forces
//                                at intermediate states
//            integrate
//            [after_integration] Phase::after_integration stages, with the new positions (no
//                                built-in stage runs here: self-collision bins its grid in its
//                                own force pass)
//
// One virtual call per stage per step, never per brick. Stages are installed by code
// (Simulator::add_stage) or by scene tables through StageRegistry (stage_registry.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "maille/snapshot.hpp"
#include "maille/vec3.hpp"

namespace maille {
struct SimulationSettings;
}

namespace maille {

struct Model;
struct State;
class Profile;
class LinkPoolBase;
struct Mat3;

enum class Phase : std::uint8_t { forces, response, after_integration };
std::string_view to_string(Phase p);

// Which velocity State::v() holds when a stage runs (see Integrator::velocity_time).
enum class VelocityTime : std::uint8_t {
  synchronous,  // v at the time of x
  half_step,    // v(n - 1/2): leapfrog's staggered velocity
};

// What a stage knows about the step it runs in.
struct StageContext {
  double h = 0;            // step, s
  double t = 0;            // time of the state being evaluated, s
  std::uint64_t step = 0;  // steps taken since the start
  int threads = 1;         // threads the simulator runs with
  VelocityTime velocity = VelocityTime::synchronous;
  // How the scheme moves positions next (response stages predict the displacement): true, with
  // the velocity after this step's kick, x + h (v + h f / m) (leapfrog, symplectic Euler);
  // false, with the current velocity, x + h v (explicit Euler).
  bool drift_after_kick = true;
  bool jacobians = false;      // the scheme is implicit: provide implicit_links()
  Profile* profile = nullptr;  // counters and gauges (stage time is measured by the simulator)
};

// A setting of a stage that tools can switch live (the viewer lists them): a name, its choices
// ("off"/"on" for switches) and the current one.
struct StageOption {
  std::string name;
  std::vector<std::string> choices;
  std::string value;
};

// Contacts of points with something an implicit solve does not move (an obstacle), offered to
// implicit solvers so that they enter the solve instead of staying the explicit force of the
// step's start: vertex block descent evaluates them at every iterate (force and 3x3 stiffness per
// point), matrix-free CG adds their stiffness to its diagonal blocks.
class PointContacts {
 public:
  virtual ~PointContacts() = default;
  // The obstacle's placement at time t: the end of the step for the solve, its start when a
  // solver takes the stage's explicit force of the step's start back out of the forces. Ends
  // any lag (below): the terms are then exactly the stage's own forces.
  virtual void set_time(double t) = 0;
  // Lagged friction: the normal force and the normal of each point's contact are taken at
  // (x, v) and the current placement (the step's start), then the placement moves to t_next;
  // they are held for the solve until the next set_time (so sticking is a smooth, convex term
  // of the solve). Stages without friction only move the placement.
  virtual void lag(std::span<const std::uint32_t> /*points*/, const Vec3* /*x*/, const Vec3* /*v*/,
                   double t_next) {
    set_time(t_next);
  }
  // For each point i of `points` that the stage collides: adds the contact force at x[i], v[i]
  // into f[i] and its stiffness -d f / d x - (1/h) d f / d v (positive semi-definite) into
  // hessian[i], and sets touching[i] = 1 where a contact acts (when `touching` is not null:
  // solvers watch steps that start or end a contact, where the force jumps). Points are
  // independent: threads may run disjoint point sets at once.
  virtual void add_terms(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v,
                         Real inv_h, Vec3* f, Mat3* hessian, std::uint8_t* touching) const = 0;
  // The contact's elastic push on point p at x, at rest relative to the obstacle (no damper, no
  // friction): zero where p touches nothing. Solvers let a Newton step leave a contact whole
  // only when it does not move against this push (a point sliding off a sphere leaves it; one
  // pressed through a thin box or between a conditional obstacle's samples does not).
  virtual Vec3 push(std::uint32_t /*p*/, const Vec3& /*x*/) const { return {}; }
  // The thinnest contact region the stage has, m (a box's smallest side, a conditional
  // obstacle's threshold; +inf for a half-space): a point moving further than half of it in a
  // step could cross it unseen, so solvers test such a point's segment at that spacing.
  virtual Real thickness() const { return std::numeric_limits<Real>::infinity(); }
};

// Contacts between a point and a triangle of moving points (self-collision with primitive =
// "triangles"), offered to implicit solvers. A candidate is the particle and the triangle's
// three corners, found at the step's start within the contact radius plus the step's motion.
// Its energy is the penalty on the point-triangle distance d, E = k (s - d)^2 / 2 while d < s,
// the closest point q = sum w_j x_j found again at every evaluation, with the damper along the
// normal n = (x_p - q) / d: the force on the particle is F = n (k (s - d) - z n.(v_p - v_q)) and
// corner j takes -w_j F. Roles: 0 the particle (coefficient c = 1), 1 to 3 the corners
// (c = -w_j). A contact on an edge or a corner shared by several of the particle's candidates
// counts once (the lowest triangle), as in the explicit force. Friction stays explicit.
class TriangleContacts {
 public:
  virtual ~TriangleContacts() = default;
  // This step's candidates: {particle, corner, corner, corner}, sorted by particle.
  virtual std::span<const std::array<std::uint32_t, 4>> candidates() const = 0;
  // The forces at x, v of every candidate in contact, into f (all four points).
  virtual void accumulate(const Vec3* x, const Vec3* v, Vec3* f) const = 0;
  // Candidate e's point-triangle distance at x (unsigned: a point that crossed the face is
  // pushed on through it, so solvers keep each point's motion within a fraction of its
  // distances at the step's start; see implicit_vbd.hpp, "conservative bounds").
  virtual Real distance(std::size_t e, const Vec3* x) const = 0;
  // The contact radius s, m: a candidate acts while its distance is below it (solvers leave out
  // of their sweeps the candidates too far to act before they find them again).
  virtual Real radius() const = 0;
  // Whether candidate e acts at any distance this step (friction lagged from the step's start,
  // held wherever the points go): solvers keep it in their sweeps however far it is.
  virtual bool held(std::size_t /*e*/) const { return false; }
  // For each point i of `points`: the candidates entries[row[i]] .. entries[row[i + 1] - 1],
  // each `candidate * 4 + role`: the force on i into f[i] and the stiffness block
  // c^2 (k + z inv_h) n n^T (the energy's Gauss-Newton Hessian, with the damper through
  // v = (x - x_n) / h) into hessian[i]. Points are independent: threads may run disjoint sets.
  virtual void add_point_terms(std::span<const std::uint32_t> points, const std::uint32_t* row,
                               const std::uint32_t* entries, const Vec3* x, const Vec3* v,
                               Real inv_h, Vec3* f, Mat3* hessian) const = 0;
  // Linear solvers: keeps the normals of the contacts active at (x, v) ...
  virtual void linearise(const Vec3* x, const Vec3* v) = 0;
  // ... and adds (a k + b z) sum c c^T n n^T u over them into out (one thread) ...
  virtual void apply(Real a, Real b, const Vec3* u, Vec3* out) const = 0;
  // ... and their diagonal blocks (a k + b z) c_i^2 n n^T into diagonal.
  virtual void add_diagonal(Real a, Real b, Mat3* diagonal) const = 0;
};

class Stage {
 public:
  virtual ~Stage() = default;
  virtual std::string name() const = 0;  // also the profile's stage name
  virtual Phase phase() const = 0;
  virtual void apply(const Model& m, State& s, const StageContext& ctx) = 0;
  // A stage that only reads the state (a listener) and never hashes positions: the simulator
  // skips its O(points) finiteness check before such a stage (a step's fixed cost at audio rate).
  virtual bool reads_only() const { return false; }
  // Called after the model's structure changed (Simulator::edit_model) or after a reset:
  // drop anything sized or derived from the old model.
  virtual void model_changed(const Model&) {}
  // Stages that act like springs (contacts) add, per point, the stiffness and damping a point
  // may see through them at once (N/m, N.s/m), for the stability estimate (stability.hpp).
  virtual void stability_terms(std::span<const Real> /*inv_mass*/, std::span<Real> /*k_row*/,
                               std::span<Real> /*c_row*/) const {}
  // Live settings (between steps). set_option throws std::invalid_argument for an unknown name
  // or choice.
  virtual std::vector<StageOption> options() const { return {}; }
  virtual void set_option(const std::string& name, const std::string& /*value*/) {
    throw std::invalid_argument("stage '" + this->name() + "' has no option '" + name + "'");
  }
  // The links this stage's forces act through during the current step (contacts as conditional
  // links), when ctx.jacobians asked for them: implicit schemes add their Jacobian blocks (the
  // stage still adds the forces). Null: the stage's forces stay explicit.
  virtual const LinkPoolBase* implicit_links() const { return nullptr; }
  // Per-point contacts that implicit solvers take inside the solve, when ctx.jacobians asked for
  // them (the stage still adds its force at the step's start; solvers take it back out). Null:
  // the stage's forces stay explicit.
  virtual PointContacts* point_contacts() { return nullptr; }
  // Point-triangle contacts that implicit solvers take inside the solve, likewise (null: none).
  virtual TriangleContacts* triangle_contacts() { return nullptr; }
  // The potential energy of the stage's conservative forces at s (J): a contact's penalty
  // (1/2 k depth^2 for an obstacle, 1/2 k (s - d)^2 for a pair closer than its contact distance
  // s), none for dampers, friction, wind or velocity responses. The stage finds its contacts at
  // s again (one pass of its own detection, into its own scratch arrays: no allocation once
  // warm), so stats.csv's `contact` column is the energy of the state it is written with.
  // Default: 0 (a stage of no conservative force; the viewer's drag spring is the user's hand,
  // external work like a drive's, and keeps it).
  virtual double energy(const Model& /*m*/, const State& /*s*/) { return 0; }
  // Checks of the state the stage offers (self-collision: triangles that cross), run by the
  // simulator at the start of each step on x_n (`sampled`: this step's stats row is written):
  // counters into the profile. A non-empty answer stops the run as a blow-up at this step naming
  // the stage (a check the user asked to stop on, e.g. `check = "every_step"`).
  virtual std::string inspect(const Model& /*m*/, const State& /*s*/, Profile& /*profile*/,
                              bool /*sampled*/) {
    return {};
  }
  // Segments to draw over the scene at the state of the last step (contacts, cells...).
  virtual void overlay(const Model&, const State&, std::vector<OverlaySegment>& /*out*/) const {}
  // Solids to draw with the scene at time t (obstacles): appended to `out` at every snapshot.
  virtual void surfaces(double /*t*/, std::vector<SurfaceInstance>& /*out*/) const {}
  // Settings that make the stage's result doubtful under the simulation's settings `s`
  // (self-collision whose points can slip between a group's particles, or whose topological
  // exclusion large implicit steps fold through), one sentence each, naming the values and the
  // fixes: apps print them (validate, info, run) and the viewer shows them, with no
  // stage-specific code.
  virtual std::vector<std::string> warnings(const SimulationSettings& /*s*/) const { return {}; }
};

// What a stage's validation found (Stage factories and scene tables share one check, run without
// building the stage): the scene key to blame and why. An empty message: valid.
struct StageProblem {
  std::string key, message;
  explicit operator bool() const { return !message.empty(); }
};

// A validated stage description kept in the Model: it makes a fresh stage for each simulator
// built from the model (benchmarks' repeats, the viewer's reload), given that simulator's own
// copy of the model (stages may keep a reference to it: a Simulator never moves).
struct StageSpec {
  using Factory = std::function<std::unique_ptr<Stage>(const Model&)>;
  StageSpec() = default;
  StageSpec(std::string n, Phase p, Factory f) : name(std::move(n)), phase(p), make(std::move(f)) {}

  std::string name;
  Phase phase = Phase::forces;
  Factory make;
  // Optional: other forms of the same stage that tools switch to live (an obstacle's method).
  // They appear as one more option of the stage (Simulator::stage_options), named
  // `variant_option`, whose choices are `variants`; choosing one installs vary(choice) in
  // place of this spec (phases may differ: the scheme is checked first).
  std::string variant_option;
  std::vector<std::string> variants;
  std::string variant;  // the current choice
  std::function<StageSpec(const std::string&)> vary;
  // Every declared key of the stage's table with its resolved value as text (stage_keys.hpp:
  // visit_keys), in declaration order: `maille info` lists them, and a fingerprint of the model
  // that must change with every trajectory-changing parameter can hash them.
  std::vector<std::pair<std::string, std::string>> parameters;
  // A hash of what the stage is made from that the scene's text does not show (an obstacle's
  // mesh file contents); the checkpoint fingerprint includes it with the name and the variant.
  std::uint64_t fingerprint = 0;
};

}  // namespace maille
