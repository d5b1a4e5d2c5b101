// Implicit Euler by vertex block descent on the GPU: the CPU solver's formulation
// (src/integrators/implicit_vbd.hpp) with the model's links, gravity, air drag, wind, geometric
// obstacles (their contacts inside the solve: gpu_vbd_obstacles.hpp) and the contact set's pairs
// and stencils (found on the host, uploaded: gpu_vbd_contacts.hpp), colour by colour in compute
// shaders. Per step (GpuBackend::implicit_step):
//   lag         per point, with obstacles that have friction: their normal force and normal at
//               x_n, v_n (placed at t), held for the solve (placed at t + h)
//   begin       per point: x_n, y = x_n + h v_n + h^2 f_ext / m (f_ext = m g + the wind's face
//               forces at t, as the CPU takes them: explicit, at the step's start), the paper's
//               adaptive guess x = x_n + h v_n + h^2 a~ (State memory "implicit_euler.vbd": v at
//               the last step's start), v = (x - x_n) / h; prev1 = x; with obstacles, the
//               guess stops at the first one it enters (first touch)
//   sweep       per colour, one dispatch over its points: g_i = m/h^2 (y - x) - gamma m v + the
//               links' forces, H_i = m (1/h^2 + gamma/h) I + the links' blocks (the shared laws'
//               <law>_block: J_x + J_v / h, definite mode), gathered over the point's adjacency,
//               + the obstacles' forces and blocks (obstacle_laws.glsl); x += H^-1 g,
//               v += H^-1 g / h (v = (x - x_n) / h without the float cancellation of the
//               difference), or, for a step that starts or leaves a contact, the CPU's rules;
//               the sweep's largest |g| (work-group reduction, then atomicMax on its bits)
//   decide      one invocation: the CPU's fallback, on the device (no read-back per sweep): a
//               sweep from the third on whose largest |g| rose turns the acceleration off
//   accelerate  per point, while on: x = w (x - prev2) + prev2 (Chebyshev, w from the host's
//               recurrence), v by the same increment over h, but for points touching an
//               obstacle and jumps over half the thinnest one; the previous iterates rotate
//   first touch with obstacles: the result stops at the first one it went through
//   health      per point: the non-finite flag (the backend's health buffer)
//   residual    per point, when the step measures: the largest |g| at the result, over m g of
//               the heaviest free point (the CPU's solver_residual)
// Colours: greedy over the free points in index order, each taking the smallest colour none of
// its coloured neighbours holds (the CPU's rule), over the graph of every link of the model,
// conditional links included (always, since the device does not search candidates): computed
// on the host at load, and again each step that has contacts, with their points as neighbours
// (gpu_vbd_contacts.hpp). Fixed and driven points are never in a colour, so they stay put.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "../integrators/implicit_vbd.hpp"
#include "gpu_layout.hpp"
#include "gpu_vbd_contacts.hpp"
#include "gpu_vbd_obstacles.hpp"
#include "kernel.hpp"
#include "maille/backend.hpp"
#include "maille/contact_set.hpp"
#include "maille/integrator.hpp"
#include "maille/model.hpp"
#include "maille/stage.hpp"
#include "maille/state.hpp"
#include "non_copyable.hpp"
#include "shaders.hpp"

namespace maille::gpu {

// The CPU solver's State memory slot (kVbdMemory) and fallback factor (kFallbackGrowth).
using maille::kFallbackGrowth;
using maille::kVbdMemory;

// More colours than this would mean as many dispatches per sweep (conditional links between
// many points, all coloured as if active): such models are refused by name.
inline constexpr std::uint32_t kVbdMaxColours = 64;

// Free points by colour, the CPU's greedy rule over every link of the model (no pairs).
VbdColours vbd_colours(const Model& m);

// Why the GPU's VBD cannot run this model with these stages ("" when it can): a stage that is
// neither a geometric obstacle nor one whose contacts are pairs and stencils (facet and
// conditional obstacles have no implicit terms on the device), more than kVbdMaxObstacles
// obstacles, a link kind whose shared law has no <law>_block, more colours than kVbdMaxColours,
// obstacles whose held friction (16 bytes per point and obstacle) exceeds `max_block`, the
// driver's largest storage block (bytes).
std::string vbd_refuses(const Model& m, std::span<const Stage* const> stages, double max_block);

// Whether a stage's contacts are the GPU's VBD's to upload: pairs and stencils, nothing else.
inline bool uploaded_contacts(ContactKinds kinds) {
  return kinds != ContactKinds::none &&
         (std::uint8_t(kinds) & ~std::uint8_t(ContactKinds::pairs | ContactKinds::stencils)) == 0;
}

class GpuVbd : NonCopyable {
 public:
  // The context must be current; `max_block`: the driver's largest storage block, bytes.
  explicit GpuVbd(double max_block);
  ~GpuVbd();
  void forget();  // the context is gone: nothing to delete

  // Colours, buffers and kernels for the model and its geometric obstacles among `stages`
  // (vbd_refuses accepted them); the guess's memory from `memory` (a State's stage memory: the
  // kVbdMemory slot, when it has one of this model's size).
  void load(const Model& m, std::span<const StageMemory> memory, const std::vector<KindLaw>& kinds,
            std::span<const Stage* const> stages);
  // One step from t, from the device's x, v (the backend's buffers bound, the wind's face
  // forces at t computed when `wind`); x, v at t + h after it.
  // `contacts`: the step's point pairs (Backend::implicit_step), uploaded with their colours.
  DeviceImplicitStep step(const Model& m, const ImplicitSettings& settings, double t, Real h,
                          std::uint64_t step, bool wind, bool measure, const ContactSet& contacts);
  // The guess's memory into s (once the device has one).
  void download_memory(State& s) const;

 private:
  void bind() const;
  void arrange();  // colours_' order and merit slots to the device

  std::uint32_t points_ = 0;
  VbdColours colours_;
  std::vector<std::uint32_t> slot_;  // [colours + 1]: each colour's first merit slot
  bool history_ = false;             // vbd_vlast holds v at the last step's start
  bool prev_swapped_ = false;
  float heaviest_ = 0, gravity_ = 0;
  std::array<unsigned, kVbdBufferCount> buffers_{};
  std::string source_;  // the sweep's, for the model's kinds
  std::vector<Kernel> kernels_;
  GpuVbdObstacles obstacles_;
  GpuVbdContacts contacts_;
  bool contacts_in_colours_ = false;  // colours_ holds the last step's contacts
};

// The kernels' sources (gpu_vbd_shaders.cpp).
std::string vbd_begin_shader();
std::string vbd_sweep_shader(const std::vector<KindLaw>& kinds, bool residual);
std::string vbd_decide_shader();
std::string vbd_accelerate_shader();
std::string vbd_lag_shader();
std::string vbd_first_touch_shader();
std::string vbd_health_shader();
std::string vbd_bounds_shader();

}  // namespace maille::gpu
