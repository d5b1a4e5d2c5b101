// The simulator: owns a model and its state, and advances them one step at a time.
//
// step(), as a table of contents (src/core/simulator.cpp):
//   [forces]        drive (scripted fixed points at t), clear forces,
//                   link forces (every link pool, in kind order), field forces (gravity, air
//                   drag, wind on faces), then Phase::forces stages (collisions), in order;
//                   non-finite forces are caught here and blamed on the stage that made them
//   [response]      Phase::response stages (rewrite forces or velocities: facets)
//   integrate       the scene's scheme (may re-run the force pass: RK4, Verlet, Newton)
//   [after]         driven points at t + h, Phase::after_integration stages
//   health          non-finite values and a kinetic-energy bound every step; the full runaway
//                   check at the sampling cadence and whenever the bound trips
//   publish         every k steps: a snapshot of positions for renderers and writers
//
// With a compute backend other than the CPU (settings.backend, backend.hpp), the same order runs
// with the forces, the integration and the health flag on the device (simulator_backend.cpp);
// the host copy of the state is brought up to date only when it is needed.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "maille/backend.hpp"
#include "maille/energy.hpp"
#include "maille/integrator.hpp"
#include "maille/model.hpp"
#include "maille/profile.hpp"
#include "maille/snapshot.hpp"
#include "maille/stability.hpp"
#include "maille/stage.hpp"
#include "maille/state.hpp"

namespace maille {

namespace detail {
class ThreadChooser;  // src/core/follow_cores.hpp
class WindRows;       // src/core/wind_rows.hpp
}  // namespace detail

// A publish_every or sample_every that no run reaches: "never" (runs that publish or sample
// explicitly, benchmarks). Also the largest cadence a scene may ask for.
inline constexpr int kNeverEvery = 1 << 30;

struct SimulationSettings {
  std::string integrator = "leapfrog";  // a name from IntegratorRegistry
  double step = 1e-3;                   // h, s, > 0
  double duration = 5;                  // s, > 0 (used by apps; step() ignores it)
  int publish_every = 10;               // steps between snapshots, >= 1
  int sample_every = 0;                 // steps between energy samples; 0: publish_every
  int threads = 0;              // 0: chosen during the run, from the free cores and timed steps
                                // (Simulator::CoreSampling)
  double runaway_factor = 1e3;  // blow-up when energy exceeds this times its scale
  ImplicitSettings implicit;    // used by implicit_euler only
  std::vector<std::string> disabled_stages;  // scene stages not to install (by name)
  std::string backend = "cpu";               // a name from BackendRegistry::global()
  BackendOptions backend_options;            // which device, for backends that have several
};

// Convenience bases for the two common phases (see stage.hpp for the phases).
class ForceStage : public Stage {
 public:
  Phase phase() const override { return Phase::forces; }
};
class AfterIntegrationStage : public Stage {
 public:
  Phase phase() const override { return Phase::after_integration; }
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
  // handle (e.g. a link kind without Jacobian under implicit_euler), a scene stage the scheme
  // cannot run, or settings out of range. Installs the model's stages (Model::stages).
  Simulator(Model model, SimulationSettings settings);
  ~Simulator() override;

  // Advances one step. Returns false (and does nothing) once a blow-up has been detected, and
  // when a stop was requested during the step (interrupted()).
  bool step();
  bool run_steps(std::uint64_t n);  // false when stopped by a blow-up

  // Installs a stage at its phase. Throws std::invalid_argument when it is a response stage
  // (rewrites forces or velocities) and the scheme evaluates forces at intermediate states.
  void add_stage(std::unique_ptr<Stage> stage);
  // Uninstalls a stage added by add_stage (a listener that stops listening: the viewer's sound
  // turned off or rebuilt); no effect when `stage` is not installed.
  void remove_stage(const Stage* stage);
  void on_publish(SnapshotListener listener);
  // A stop request, polled inside long steps: between the implicit solvers' iterations (VBD
  // sweeps, CG and Newton iterations), where one step may last minutes. When it answers true
  // the step is abandoned: the state goes back to the step's start (positions, velocities,
  // time, the scheme's history, the stages' memory: the state of the last whole step), step()
  // returns false and interrupted() is true until the next step. Called on the stepping thread.
  void on_stop_request(std::function<bool()> poll) { stop_poll_ = std::move(poll); }
  bool interrupted() const { return interrupted_; }

  // Implicit steps that ended unconverged: the nonlinear step's force imbalance (stats.csv's
  // solver_residual, in units of the heaviest free point's weight m g) above
  // kUnconvergedResidual for kUnconvergedSteps steps in a row or more (a single step above it
  // is an impact). Set from the first such run of steps on, counting every step above the
  // bound since. The run goes on (the step is stable, not accurate); programs warn.
  static const double kUnconvergedResidual;  // simulator.cpp: why these values
  static const int kUnconvergedSteps;
  struct Unconverged {
    std::uint64_t first_step = 0;  // the first step of the first run of unconverged steps
    double first_time = 0;         // s, at its end
    std::uint64_t steps = 0;       // steps above the bound from there on
    double worst = 0;              // the largest residual, m g
  };
  const std::optional<Unconverged>& unconverged() const { return unconverged_; }
  // Energies are sampled every sample_every steps at t_n, between the force pass and the
  // integration; listeners get the sample at the end of that step, with its complete timings.
  void on_sample(std::function<void(const EnergySample&, const Profile&)> listener);

  const Model& model() const { return model_; }
  // The current state; with a device backend, brought back from the device first when stale.
  const State& state() const {
    sync_host();
    return state_;
  }
  const SimulationSettings& settings() const { return settings_; }
  // The step count and the time of the state: never a download, unlike state().
  std::uint64_t steps_taken() const { return state_.step; }
  double time() const { return state_.time; }
  const Integrator& integrator() const { return *integrator_; }
  const Profile& profile() const { return profile_; }
  const std::optional<BlowUp>& blow_up() const { return blow_up_; }
  const StabilityEstimate& stability() const { return stability_; }
  int threads() const { return threads_; }

  // The default thread count (settings.threads = 0, on the CPU, with more than one core)
  // follows the cores free during the run and the work: between steps, every `interval` of
  // wall-clock time, `free_cores` is asked; with one core free the run takes one thread, with
  // more it times a few steps on one thread and on the free cores and keeps the faster (again
  // when the answer changes and every `retrial`: src/core/follow_cores.hpp, ThreadChooser).
  // Fewer threads when another program takes a core, more when it frees one and they pay.
  // Results do not change (every pass sums in an order set by the model, never by the threads:
  // test physics.FollowCores). By default the answer comes from /proc/stat (FreeCoreSampler: a
  // core is taken when another task was runnable in each of the last 4 samples); tests pass
  // their own to make a core busy or free on cue. Without effect when follows_cores() is false.
  struct CoreSampling {
    std::function<int()> free_cores;  // the cores free now; null: /proc/stat
    double interval = 0.25;           // s of wall-clock time between two questions; 0: every step
    int trial_steps = 6;              // steps timed per thread count; 0: the free cores, as told
    double retrial = 10;              // s of wall-clock time between trials at one free count
  };
  void set_core_sampling(CoreSampling sampling);
  // Which steps time their stages into profile() (two clock reads per stage, a quarter of a
  // small model's step at audio rate): every step (the default), or only the steps that sample
  // energies (sample_every), whose stats rows keep complete timings; the profile's totals then
  // sum those steps only. docs/sound.md, "A lean step".
  enum class StageTiming { every_step, sampled_steps };
  void set_stage_timing(StageTiming timing) { stage_timing_ = timing; }
  StageTiming stage_timing() const { return stage_timing_; }
  // Steps between two health checks (non-finite positions or velocities, the kinetic bound of
  // a runaway): 1 (the default) checks every step, so a blow-up is reported at the step it
  // starts; n > 1 checks the steps that are multiples of n, so it is found within n steps (a
  // pass over every point less per step; `maille play`, whose every sample is checked finite).
  void set_health_every(int n) { health_every_ = n < 1 ? 1 : n; }
  bool follows_cores() const { return follows_cores_; }
  // The compute backend, or nullptr on the CPU path.
  const Backend* backend() const { return backend_.get(); }
  void wait();  // until every submitted step has run (a device backend runs asynchronously)
  std::uint64_t frames_published() const { return snapshot_.frame; }

  // Edits, between steps only. Structural edits (points, links, faces, stages) go through
  // edit_model, which re-prepares the pools, resizes the state (new points start at their
  // initial position and velocity), rebuilds the scheme's buffers and the stages and
  // re-estimates stability; the scheme's history in the State is kept. Parameter edits (link
  // parameters, fields, masses) go through edit_parameters, which re-prepares nothing; a
  // structural change made there is detected and handled as by edit_model. Both validate the
  // edited model (check_model: ends, faces, drives, groups, masses, link parameters) and refuse
  // with std::invalid_argument, leaving model and state exactly as they were.
  void edit_model(const std::function<void(Model&)>& edit);
  // Parameter values written in place at audio rate (`maille play`'s controls, live.hpp): only
  // values validated beforehand (audio::ParameterTable: every row is a model read from the
  // scene and checked), so nothing is copied, checked or re-estimated here; nothing allocated.
  template <class Edit>
  void tune_parameters(Edit&& edit) {
    sync_host();
    host_ahead_ = true;
    edit(model_);
    model_.links.parameters_changed();
  }
  void edit_parameters(const std::function<void(Model&)>& edit);
  // Replaces the whole state (a checkpoint, a copy from another simulator of the same model).
  // Throws std::invalid_argument when its size does not match the model.
  void restore(State state, std::uint64_t frames_published = 0);
  // Between steps only (positions, velocities); a device backend is reloaded before the next
  // step.
  State& state_for_editing() {
    sync_host();
    host_ahead_ = true;
    return state_;
  }

  // Switches scheme between steps: velocities are first synchronised to the time of x (a
  // staggered scheme's half-step velocity is converted), then the new scheme starts afresh.
  // Throws std::invalid_argument (and changes nothing) when the scheme refuses the model or a
  // stage.
  void set_integrator(const std::string& name);
  // Implicit Euler's solver and its settings, between steps (the viewer switches them live):
  // the scheme is rebuilt around the current state (its history, VBD's included, is in the
  // State). Throws std::invalid_argument (and changes nothing) when the new scheme refuses.
  void set_implicit(const ImplicitSettings& implicit);
  void set_step(double h);  // between steps; leapfrog re-centres its kick by itself
  void reset();             // back to the model's initial state
  // Energies of the current state (synchronised velocities). Runs the force stages only, never
  // the response stages (which rewrite state).
  Energies energies();
  // The full runaway check now (apps call it at the end of a run): false, with blow_up() set,
  // when the energy ran away since the last check.
  bool check_energy();
  void publish_now();  // a snapshot of the current state, outside the cadence

  // Stages' live settings, by stage name (the viewer's panel), and their overlays in snapshots.
  struct StageOptions {
    std::string stage;
    std::vector<StageOption> options;
  };
  std::vector<StageOptions> stage_options() const;
  // Every installed stage's warnings (Stage::warnings), each prefixed by the stage's name.
  std::vector<std::string> stage_warnings() const;
  // Throws std::invalid_argument for an unknown stage, option or choice.
  void set_stage_option(const std::string& stage, const std::string& option,
                        const std::string& value);
  void set_overlays(bool on) { overlays_ = on; }
  // Snapshots leave the positions on the device when the backend offers them in a shared
  // OpenGL context (Backend::gl_positions): Snapshot::device is set and `positions` stays
  // empty, nothing is downloaded to publish. Stage overlays, which read the host state, are
  // then left out. Off by default, and without effect on the CPU or a backend in a context of
  // its own.
  void set_device_snapshots(bool on) { device_snapshots_ = on; }

 private:
  struct Installed {
    std::unique_ptr<Stage> stage;
    Phase phase = Phase::forces;  // stage->phase(), kept beside it: the list is ordered by it
    int profile_id = 0;
    bool from_model = false;  // made from Model::stages (rebuilt by edit_model)
    int spec = -1;            // its index in Model::stages when from_model
  };
  // The installed stages of one phase, in install order (a range of stages_).
  std::span<Installed> stages_of(Phase p);
  std::span<const Installed> stages_of(Phase p) const;

  void evaluate(State& s) override;  // ForceEvaluator: every force-phase stage, timed
  void evaluate_keeping_contacts(State& s) override;
  bool find_contacts_again(State& s, std::span<const std::uint32_t> moved) override;
  // The force pass; `find`: contact stages find the step's set (implicit schemes).
  void evaluate_stages(State& s, bool find);
  // The first stage of a list that needs a finite state (not reads_only), or null.
  static const Stage* first_checked(std::span<const Installed> stages);
  bool stop_requested() override;
  bool failed() const override { return blow_up_.has_value(); }
  const ContactSet& contacts() const override { return contacts_; }
  void respond();  // response stages, once per step, before integration
  // Response stages of a scheme that solves (ResponseTiming::after_solve;
  // simulator_response.cpp): the step's start is kept, then the stages answer the solved motion.
  void keep_step_start();
  void respond_to_solved_motion();
  void build_integrator(const std::string& name);
  void install_model_stages();
  void add_installed(std::unique_ptr<Stage> stage, bool from_model, int spec = -1);
  void switch_variant(std::size_t spec, const std::string& value);
  void check_stage(Stage& stage) const;
  void restimate_stability();
  void model_structure_changed();
  void apply_or_restore(Model previous);
  StageContext context(const State& s) const;
  void sample_energies();
  // The model's energies at the current state (velocity: scratch_velocity_) with every stage's
  // contact energy added (Stage::energy).
  Energies all_energies();
  // Every installed stage, in step order (backends and the stability estimate take them so).
  std::vector<const Stage*> installed_stages() const {
    std::vector<const Stage*> out;
    for (const Installed& st : stages_) out.push_back(st.stage.get());
    return out;
  }
  bool runaway(double kinetic_plus_elastic);
  void check_forces(State& s);
  // The structured grid's fused step where it applies (simulator_fused.cpp): false when not.
  bool fused_grid_step(Real h);
  void check_health();
  std::string blame_forces(State& s);
  void publish();
  void fail(std::string module, std::string detail);
  // Device backends (simulator_backend.cpp).
  void make_backend();
  // Throws std::invalid_argument when the backend refuses the scheme, the installed stages or
  // `extra` (a stage about to be installed).
  void check_backend(const Integrator& scheme, const Stage* extra = nullptr) const;
  bool step_on_backend();
  void implicit_step_on_backend(Real h);  // a step the backend makes whole (Backend::steps)
  void find_contacts_for_backend();  // the step's pairs and stencils on the host, for the device
  void sync_host() const;            // the device's x, v, f into state_ when the device is ahead
  void check_backend_health();
  double energy_scale() const;
  // simulator_threads.cpp: the default thread count follows the free cores.
  void follow_cores();
  void use_threads(int threads);
  void keep_to_usable_threads();
  bool stage_input_finite(const State& s, const Stage& next);
  bool advance_or_stop(Real h);  // the scheme's advance, undone when a stop came during it
  void keep_for_stop();
  void note_convergence();
  bool inspect_stages(bool sampled);  // Stage::inspect; false: a stage stopped the run

  Model model_;
  SimulationSettings settings_;
  mutable State state_;  // mutable: with a device backend, the host copy is refreshed lazily
  std::unique_ptr<Integrator> integrator_;
  // Every installed stage in step order: by phase (forces, response, after_integration), then
  // in install order; stages_of(phase) is a phase's range.
  std::vector<Installed> stages_;
  std::vector<SnapshotListener> publish_listeners_;
  std::vector<std::function<void(const EnergySample&, const Profile&)>> sample_listeners_;
  Profile profile_;
  StabilityEstimate stability_;
  std::optional<BlowUp> blow_up_;
  std::optional<EnergySample> pending_sample_;
  Snapshot snapshot_;
  std::vector<Vec3> scratch_velocity_;
  // The step's start and the solve's result, for response stages after a solve.
  std::vector<Vec3> start_x_, start_v_, solved_x_, solved_v_;
  // A stop request polled inside the step, and the step's start to go back to (implicit
  // schemes, whose steps are long enough to be worth stopping).
  std::function<bool()> stop_poll_;
  bool interrupted_ = false;
  State step_start_;
  std::optional<Unconverged> unconverged_;
  Unconverged streak_;       // the current run of steps above the bound
  int residual_gauge_ = -1;  // the scheme's solver_residual gauge, once it has registered it
  ContactSet contacts_;      // the step's contacts (implicit schemes), found by the last evaluate
  // The implicit solvers' stats columns when a backend steps the scheme (registered once).
  struct DeviceSolverIds {
    int iterations = -1, residual = -1, colours = -1, resets = -1, refreshes = -1;
  };
  DeviceSolverIds device_ids_;
  double energy_scale_ = 0;
  int threads_ = 1;
  int cores_ = 1;          // those OpenMP may use (omp_get_num_procs)
  int free_at_start_ = 1;  // the cores free when the simulator was built
  StageTiming stage_timing_ = StageTiming::every_step;  // the lean step's cadences
  int health_every_ = 1;
  bool follows_cores_ = false;  // the thread count is the default: it follows the free cores
  CoreSampling core_sampling_;
  std::unique_ptr<detail::ThreadChooser> chooser_;  // built at the first step
  std::unique_ptr<detail::WindRows> wind_rows_;     // the fused step's wind, at its first
  bool overlays_ = false;
  bool device_snapshots_ = false;
  struct StageIds;
  std::unique_ptr<StageIds> ids_;
  std::unique_ptr<Backend> backend_;
  mutable bool device_ahead_ = false;  // the device has steps the host copy has not
  bool host_ahead_ = true;             // the host changed the model or the state: reload
};

// "implicit_euler (vbd) ended 12 steps unconverged, the first at step 40 (t = 0.6667 s): ..."
// with what to change; "" when none did.
std::string unconverged_text(const Simulator& sim);

}  // namespace maille
