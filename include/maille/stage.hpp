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
// One virtual call per stage per step in the force pass; implicit solvers call a stage's
// PointContacts per point where they probe one point (VBD's bisection and coarse step). Stages are
// installed by code (Simulator::add_stage) or by scene tables through StageRegistry
// (stage_registry.hpp).
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

#include "maille/contact_set.hpp"
#include "maille/names.hpp"
#include "maille/snapshot.hpp"
#include "maille/vec3.hpp"

namespace maille {
struct SimulationSettings;
}

namespace maille {

struct Model;
struct State;
class Profile;
class ContactSet;

enum class Phase : std::uint8_t { forces, response, after_integration };

// The arrays of the step's contact set (contact_set.hpp) a contact stage fills: bits.
enum class ContactKinds : std::uint8_t {
  none = 0,
  pairs = 1,      // point-point pairs, as conditional links (ContactSet::pairs)
  stencils = 2,   // point-triangle and edge-edge candidates (ContactSet::stencils)
  obstacles = 4,  // a point-obstacle stage (ContactSet::obstacles)
};
constexpr ContactKinds operator|(ContactKinds a, ContactKinds b) {
  return ContactKinds(std::uint8_t(a) | std::uint8_t(b));
}
constexpr bool has(ContactKinds set, ContactKinds kind) {
  return (std::uint8_t(set) & std::uint8_t(kind)) != 0;
}
template <>
struct NameTable<Phase> {
  static constexpr std::string_view what = "phase";
  static constexpr std::array<Name<Phase>, 3> names{{
      {Phase::forces, "forces", "in the force pass, adding forces"},
      {Phase::response, "response", "after the force pass: rewrites forces or velocities"},
      {Phase::after_integration, "after_integration", "after the update, with new positions"},
  }};
};

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
  bool jacobians = false;      // the scheme is implicit: contact stages find_contacts()
  Profile* profile = nullptr;  // counters and gauges (stage time is measured by the simulator)
};

// A setting of a stage that tools can switch live (the viewer lists them): a name, its choices
// ("off"/"on" for switches) and the current one.
struct StageOption {
  std::string name;
  std::vector<std::string> choices;
  std::string value;
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
  // What a user can do where the stage cannot run (a backend with no version of it), appended
  // to that refusal: " (or without it: --no-self-collision)". Empty: nothing to add.
  virtual std::string refusal_hint() const { return {}; }
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
  // Contact stages (obstacles, self-collision, [[contact]] through the broad phase): under an
  // implicit scheme (ctx.jacobians) the simulator calls find_contacts() in place of apply().
  // The stage finds the step's contacts once, at its reach plus the step's motion margin, and
  // puts its typed arrays into `set` (contact_set.hpp) without adding any force: the solver
  // evaluates them itself, at the step's start for its right-hand side and at every iterate
  // inside the solve. apply() stays the explicit force pass of the explicit schemes.
  bool finds_contacts() const { return contacts_found() != ContactKinds::none; }
  // What find_contacts() puts into the set (a backend that reads the set on a device refuses
  // what it cannot read, by name, before the run starts).
  virtual ContactKinds contacts_found() const { return ContactKinds::none; }
  virtual void find_contacts(const Model& /*m*/, State& /*s*/, const StageContext& /*ctx*/,
                             ContactSet& /*set*/) {}
  // The same search again inside the step, at a solver's iterate s (x, and v = (x - x_n) / h),
  // into the arrays already in the set (a point went past its TriangleContacts::drift_limit()).
  // `moved` empty: everywhere. Otherwise only around those points (sorted global ids): a stage
  // that keeps a drift limit L adds to its arrays, keeping what they hold, every pair with one
  // of them (a point of the pair, a corner of its face or edge) within its contact distance
  // plus 4 L at s (docs/implicit.md, "Intersection-free cloth: what holds"). False when the
  // stage has nothing to search again (the default: obstacles' contacts are evaluated
  // wherever the points are).
  virtual bool find_contacts_again(const Model& /*m*/, State& /*s*/, const StageContext& /*ctx*/,
                                   std::span<const std::uint32_t> /*moved*/) {
    return false;
  }
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

// What a stage is to the step, said once per stage: its name (its profile column ns_<name>,
// options, refusals, `disabled_stages`) and the phase it runs at. The stage reports it
// (Stage::name, Stage::phase), the scene table that makes it declares it
// (StageTableEntry::stage) and builds its StageSpec from it.
struct StageInfo {
  std::string_view name;
  Phase phase = Phase::forces;
};

// A validated stage description kept in the Model: it makes a fresh stage for each simulator
// built from the model (benchmarks' repeats, the viewer's reload), given that simulator's own
// copy of the model (stages may keep a reference to it: a Simulator never moves).
struct StageSpec {
  using Factory = std::function<std::unique_ptr<Stage>(const Model&)>;
  StageSpec() = default;
  StageSpec(std::string n, Phase p, Factory f) : name(std::move(n)), phase(p), make(std::move(f)) {}
  StageSpec(StageInfo info, Factory f)
      : StageSpec(std::string(info.name), info.phase, std::move(f)) {}

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
