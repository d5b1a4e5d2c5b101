// Compute backends: where the bulk of a step runs.
//
// The Simulator stays the only simulator: it keeps the order of a step, the scheme's
// bookkeeping (SchemeHistory), the health verdicts, the energy samples and the publishing. A
// backend holds its own copy of the state on its device and runs the heavy parts there; the
// Simulator calls it at this seam (src/core/simulator_backend.cpp):
//   load       model, state and the installed stages (those refuses() accepted), after
//              construction, reset, restore, edits, stages added, host-side changes
//   drive      driven points' positions and velocities at t (paths are evaluated on the host:
//              a handful of points)
//   evaluate   every force of the step at the device's x and v (links, gravity, drag, wind)
//   integrate  one kick and one drift (Integrator::kick_drift_step), flagging non-finite values
//   health     the first step whose integration left a non-finite value (a reduction on the
//              device, read back at the sampling and publishing cadence)
//   download   x, v and f into the host State, only when someone needs them (frames, energy
//              samples, edits, the end of a run)
// or, for a scheme the backend steps whole on its device (steps(scheme): implicit Euler by
// vertex block descent on the GPU), in place of integrate:
//   implicit_step  the whole implicit step from t to t + h (the forces it needs, the solve, the
//              solver's counters; the residual when asked, at the sampling cadence)
// The CPU path is the Simulator's own (the reference every backend is tested against): "cpu"
// has no Backend object. A backend is one type implementing this interface and one
// registration (BackendRegistry::add); the GPU's is src/gpu/.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "maille/integrator.hpp"
#include "maille/model.hpp"
#include "maille/names.hpp"
#include "maille/registry.hpp"
#include "maille/stage.hpp"
#include "maille/state.hpp"

namespace maille {

struct BackendOptions {
  int device = -1;  // which device (for "gpu": an EGL device index); -1: the platform's default
  // Run in the OpenGL context current on the calling thread (any window system's: the viewer's
  // hidden window shares the window's objects) rather than in one of the backend's own; the
  // caller guarantees one is current. A device >= 0 still makes its own context on that device.
  bool use_current_context = false;
};

// What a device's implicit step reports (the stats columns of the CPU's implicit solvers).
struct DeviceImplicitStep {
  std::uint64_t iterations = 0;  // solver_iterations: VBD sweeps
  std::uint64_t colours = 0;     // vbd_colours
  // vbd_acceleration_resets and solver_residual (the largest force imbalance over free points
  // after the step, over m g of the heaviest free point, as the CPU defines it): read back from
  // the device only when the step was asked to measure; otherwise unset.
  std::optional<std::uint64_t> acceleration_resets;
  std::optional<double> residual;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string_view name() const = 0;
  // The device and driver, and the limits that matter, for logs and `maille info`.
  virtual std::string describe() const = 0;
  // Why this set-up cannot run here (empty: it can), naming the link kind, the stage or the
  // scheme that has no version on this backend.
  virtual std::string refuses(const Model& m, const Integrator& scheme,
                              std::span<const Stage* const> stages) const = 0;
  // `stages`: the simulator's installed stages, in their phases' order; the backend may keep
  // the pointers until the next load (the simulator loads again whenever they change). The
  // default (none) is for callers that drive a backend by hand on a bare model.
  virtual void load(const Model& m, const State& s, std::span<const Stage* const> stages = {}) = 0;
  virtual void drive(const Model& m, double t) = 0;
  virtual void evaluate(const Model& m, double t) = 0;
  virtual void integrate(Real kick, Real drift, std::uint64_t step) = 0;
  // Whether this backend steps `scheme` whole on its device (refuses() accepts it then): the
  // simulator calls implicit_step in place of evaluate + integrate. A later device solver is
  // one more answer here and its step below.
  virtual bool steps(const Integrator& scheme) const {
    static_cast<void>(scheme);
    return false;
  }
  // One step of `scheme` from t to t + h on the device, from the device's x and v (driven points
  // already at t): x, v at t + h on the device. `step`: the step count after it (the health
  // flag's value). `measure`: read back the residual and the counters that need the device.
  // `contacts`: the step's point pairs, found on the host at x_n by the stages that put pairs
  // into the contact set (Stage::contacts_found; empty when none), for the device to upload.
  virtual DeviceImplicitStep implicit_step(const Model& m, const Integrator& scheme, double t,
                                           Real h, std::uint64_t step, bool measure,
                                           const ContactSet& contacts) {
    static_cast<void>(m), static_cast<void>(t), static_cast<void>(h), static_cast<void>(step),
        static_cast<void>(measure), static_cast<void>(contacts);
    throw std::logic_error("backend " + std::string(name()) + " does not step " +
                           std::string(scheme.name()));
  }
  // The first step (the step count after it) whose integration produced a non-finite position
  // or velocity; 0 while there is none. Waits for the device.
  virtual std::uint64_t first_non_finite() = 0;
  // x, v and f of the device into s (size checked by the caller); waits for the device.
  virtual void download(State& s) = 0;
  virtual void finish() = 0;  // waits until every submitted step has run (timing)
  // The OpenGL buffer holding the device's positions (3 floats per point), when it lives in a
  // context the caller shares (BackendOptions::use_current_context, or a context that was
  // current when the backend started); 0 otherwise. Renderers draw from it without a copy
  // back (Simulator::set_device_snapshots).
  virtual std::uint32_t gl_positions() const { return 0; }
};

// The backends the engine ships, by name ([simulation] backend, --backend). A program may
// register more under other names; scene files name these (the gpu entry exists once the
// program called gpu::register_backend(), and a scene naming it elsewhere is refused when the
// simulator starts).
enum class BackendKind : std::uint8_t { cpu, gpu };
template <>
struct NameTable<BackendKind> {
  static constexpr std::string_view what = "backend";
  static constexpr std::array<Name<BackendKind>, 2> names{{
      {BackendKind::cpu, "cpu",
       "the reference: every stage, every scheme, double precision, OpenMP threads"},
      {BackendKind::gpu, "gpu",
       "OpenGL 4.5 compute shaders (float): link forces, gravity, drag, wind, leapfrog, "
       "symplectic Euler and implicit Euler by vertex block descent, driven points, conditional "
       "contacts, self-collision (points), geometric obstacles; under VBD, obstacles, "
       "self-collision (points and triangles) and [[contact]] inside the solve"},
  }};
};

struct BackendEntry {
  std::string name, doc;
  std::function<std::unique_ptr<Backend>(const BackendOptions&)> make;  // empty for "cpu" (the
                                                                        // Simulator's own path)
};

class BackendRegistry : public Registry<BackendEntry, &BackendEntry::name> {
 public:
  using Entry = BackendEntry;
  using Factory = decltype(Entry::make);
  BackendRegistry() : Registry("backend registry") {}
  // The process's registry: "cpu" always, others as the program registers them (apps call
  // e.g. maille::gpu::register_backend() first thing).
  static BackendRegistry& global();
};

}  // namespace maille
