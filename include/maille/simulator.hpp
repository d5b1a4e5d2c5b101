// The simulator: owns a model and its state, and advances them one step at a time.
//
// step(), as a table of contents (src/core/simulator.cpp):
//   [forces]        drive (scripted fixed points at t), clear forces,
//                   link forces (every link pool, in kind order), field forces (gravity, air
//                   drag, wind on faces), then plugged-in force stages (collisions), in order
//   integrate       the scene's scheme (may re-run the force stages: RK4, implicit)
//   after hooks     stages that need the new positions (grids, signatures)
//   health          non-finite values every step, runaway energy at the sampling cadence
//   publish         every k steps: a snapshot of positions for renderers and writers
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "maille/energy.hpp"
#include "maille/integrator.hpp"
#include "maille/model.hpp"
#include "maille/profile.hpp"
#include "maille/snapshot.hpp"
#include "maille/stability.hpp"
#include "maille/state.hpp"

namespace maille {

struct SimulationSettings {
  std::string integrator = "leapfrog";  // a name from IntegratorRegistry
  double step = 1e-3;                   // h, s, > 0
  double duration = 5;                  // s, > 0 (used by apps; step() ignores it)
  int publish_every = 10;               // steps between snapshots, >= 1
  int sample_every = 0;                 // steps between energy samples; 0: publish_every
  int threads = 0;                      // 0: all cores when the scene is large, else 1
  double runaway_factor = 1e3;          // blow-up when energy exceeds this times its scale
  ImplicitSettings implicit;            // used by implicit_euler only
};

// A stage that adds forces (or rewrites them) after the field forces: the extension point for
// collisions. One virtual call per stage per step, never per brick.
class ForceStage {
 public:
  virtual ~ForceStage() = default;
  virtual std::string name() const = 0;
  virtual void apply(const Model& m, State& s, Profile& profile) = 0;
  // True for stages that rewrite forces or velocities after the fact (inverse dynamics on
  // facets): schemes that evaluate forces at intermediate states (RK4, velocity Verlet, Newton
  // iterations) refuse them, because the rewrite would be applied to states that are not
  // the step's.
  virtual bool rewrites_state() const { return false; }
};

// A stage run after integration, with the new positions.
class AfterIntegrationStage {
 public:
  virtual ~AfterIntegrationStage() = default;
  virtual std::string name() const = 0;
  virtual void apply(const Model& m, State& s, Profile& profile) = 0;
};

struct BlowUp {
  std::uint64_t step = 0;
  double time = 0;
  std::string module;   // brick kind or stage where it started, e.g. "spring_damper"
  std::string message;  // full human-readable report
};

struct EnergySample {
  std::uint64_t step = 0;
  double time = 0;
  Energies energies;
};

class Simulator : private ForceEvaluator {
 public:
  // Throws std::invalid_argument for an unknown integrator, a model the integrator cannot
  // handle (e.g. a link kind without Jacobian under implicit_euler) or settings out of range.
  Simulator(Model model, SimulationSettings settings);
  ~Simulator() override;

  // Advances one step. Returns false (and does nothing) once a blow-up has been detected.
  bool step();
  bool run_steps(std::uint64_t n);  // false when stopped by a blow-up

  // Throws std::invalid_argument when the stage rewrites state and the scheme cannot take it.
  void add_force_stage(std::unique_ptr<ForceStage> stage);
  void add_after_integration(std::unique_ptr<AfterIntegrationStage> stage);
  void on_publish(SnapshotListener listener);
  // Energies are sampled every sample_every steps at t_n, between the force pass and the
  // integration; listeners get the sample at the end of that step, with its complete timings.
  void on_sample(std::function<void(const EnergySample&, const Profile&)> listener);

  const Model& model() const { return model_; }
  Model& model_for_editing() { return model_; }  // between steps only
  const State& state() const { return state_; }
  State& state_for_editing() { return state_; }  // between steps only
  const SimulationSettings& settings() const { return settings_; }
  const Integrator& integrator() const { return *integrator_; }
  const Profile& profile() const { return profile_; }
  const std::optional<BlowUp>& blow_up() const { return blow_up_; }
  const StabilityEstimate& stability() const { return stability_; }
  int threads() const { return threads_; }

  void set_step(double h);  // between steps; the scheme re-primes
  void reset();             // back to the model's initial state
  Energies energies();      // energies of the current state (synchronised velocities)
  void publish_now();       // a snapshot of the current state, outside the cadence

 private:
  void evaluate(State& s) override;  // ForceEvaluator: every force stage, timed
  void drive(double t);
  void sample_energies();
  void check_health();
  void publish();
  void fail(std::string module, std::string detail);
  double energy_scale() const;

  Model model_;
  SimulationSettings settings_;
  State state_;
  std::unique_ptr<Integrator> integrator_;
  std::vector<std::unique_ptr<ForceStage>> force_stages_;
  std::vector<std::unique_ptr<AfterIntegrationStage>> after_stages_;
  std::vector<SnapshotListener> publish_listeners_;
  std::vector<std::function<void(const EnergySample&, const Profile&)>> sample_listeners_;
  Profile profile_;
  StabilityEstimate stability_;
  std::optional<BlowUp> blow_up_;
  std::optional<EnergySample> pending_sample_;
  Snapshot snapshot_;
  std::vector<Vec3> scratch_velocity_;
  double energy_scale_ = 0;
  int threads_ = 1;
  struct StageIds;
  std::unique_ptr<StageIds> ids_;
};

}  // namespace maille
