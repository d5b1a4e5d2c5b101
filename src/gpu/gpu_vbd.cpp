// Implicit Euler by vertex block descent on the GPU: see gpu_vbd.hpp for the passes.
#include "gpu_vbd.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "gl_buffers.hpp"
#include "maille/shared_laws.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

enum Pass : unsigned {
  begin_pass,
  sweep_pass,
  residual_pass,
  decide,
  accelerate,
  health,
  lag_pass,
  first_touch,
  bounds_pass,
  passes
};

std::uint32_t float_bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

float bits_float(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// Whether link_laws.glsl has the block of `law` (a kind runs under the GPU's VBD then).
bool has_block(std::string_view law) {
  return shared::link_laws.find("mat3 " + std::string(law) + "_block(") != std::string_view::npos;
}

}  // namespace

VbdColours vbd_colours(const Model& m) {
  VbdColours out;
  VbdGraph(m).colour(out);
  return out;
}

std::string vbd_refuses(const Model& m, std::span<const Stage* const> stages, double max_block) {
  const std::string how = "implicit_euler with solver = \"vbd\" on the GPU backend";
  for (const Stage* st : stages) {
    // Pairs and stencils: found on the host, uploaded every step.
    if (uploaded_contacts(st->contacts_found())) continue;
    if (vbd_obstacle_count({&st, 1}) == 0)
      return "stage '" + st->name() + "' has no implicit terms on the GPU (" + how +
             " runs the model's links, gravity, air drag, wind, self-collision, [[contact]] and " +
             "obstacles with " +
             "method = \"geometric\"; facet and conditional obstacles enter only the CPU's " +
             "solve): run this scene with --backend cpu";
  }
  if (const std::uint32_t o = vbd_obstacle_count(stages); o > kVbdMaxObstacles)
    return std::to_string(o) + " geometric obstacles: " + how + " takes at most " +
           std::to_string(kVbdMaxObstacles) + ": run this scene with --backend cpu";
  if (const double held = 16.0 * m.points.size() * vbd_obstacle_count(stages); held > max_block)
    return "the geometric obstacles' held friction needs a " + std::to_string(held / (1 << 20)) +
           " MiB storage buffer (16 bytes per point and obstacle), more than this driver's " +
           "limit of " + std::to_string(max_block / (1 << 20)) + " MiB: run this scene with " +
           "--backend cpu";
  for (const auto& pool : m.links.pools())
    if (pool->size() > 0 && !has_block(pool->shared_law()))
      return "link kind '" + std::string(pool->keyword()) + "' has no Jacobian block in " +
             "include/maille/detail/link_laws.glsl (" + std::string(pool->shared_law()) +
             "_block), which " + how + " needs: run this scene with --backend cpu";
  if (const std::uint32_t c = vbd_colours(m).count(); c > kVbdMaxColours)
    return "the model's links need " + std::to_string(c) + " colours (conditional links " +
           "included, as if all were active), more than the " + std::to_string(kVbdMaxColours) +
           " that " + how + " dispatches per sweep: run this scene with --backend cpu";
  return {};
}

GpuVbd::GpuVbd(double max_block) : contacts_(max_block) {
  glCreateBuffers(GLsizei(kVbdBufferCount), buffers_.data());
  kernels_.resize(passes);
  kernels_[begin_pass] = Kernel("gpu vbd begin", vbd_begin_shader());
  kernels_[decide] = Kernel("gpu vbd decide", vbd_decide_shader());
  kernels_[accelerate] = Kernel("gpu vbd accelerate", vbd_accelerate_shader());
  kernels_[health] = Kernel("gpu vbd health", vbd_health_shader());
  kernels_[lag_pass] = Kernel("gpu vbd obstacle lag", vbd_lag_shader());
  kernels_[first_touch] = Kernel("gpu vbd first touch", vbd_first_touch_shader());
  kernels_[bounds_pass] = Kernel("gpu vbd bounds", vbd_bounds_shader());
}

GpuVbd::~GpuVbd() {
  if (kernels_.empty()) return;  // forgotten: the context took the objects with it
  kernels_.clear();
  glDeleteBuffers(GLsizei(kVbdBufferCount), buffers_.data());
}

void GpuVbd::forget() {
  for (Kernel& k : kernels_) k.forget();
  kernels_.clear();
  obstacles_.forget();
  contacts_.forget();
}

void GpuVbd::load(const Model& m, std::span<const StageMemory> memory,
                  const std::vector<KindLaw>& kinds, std::span<const Stage* const> stages) {
  points_ = m.points.size();
  obstacles_.load(m, stages);
  contacts_.load(m, colours_);
  contacts_in_colours_ = false;
  const std::size_t n3 = 3 * std::size_t(points_);
  for (Buf b : {Buf::vbd_xn, Buf::vbd_y, Buf::vbd_prev1, Buf::vbd_prev2})
    upload(buffers_[unsigned(b) - unsigned(Buf::vbd_xn)], std::vector<float>(n3, 0.0f));
  // The guess's memory, when the state has one for this model (a resumed or handed-over run).
  std::vector<float> last(n3, 0.0f);
  history_ = false;
  for (const StageMemory& mem : memory)
    if (mem.stage == kVbdMemory && mem.values.size() == n3) {
      for (std::size_t k = 0; k < n3; ++k) last[k] = float(mem.values[k]);
      history_ = true;
    }
  upload(buffers_[unsigned(Buf::vbd_vlast) - unsigned(Buf::vbd_xn)], last);
  arrange();
  prev_swapped_ = false;
  heaviest_ = 0;
  for (const std::uint32_t i : colours_.order)
    heaviest_ = std::max(heaviest_, float(m.points.mass[i]));
  gravity_ = float(norm(m.fields.gravity));
  const std::string source = vbd_sweep_shader(kinds, false);
  if (source != source_) {
    kernels_[sweep_pass] = Kernel("gpu vbd sweep", source);
    kernels_[residual_pass] = Kernel("gpu vbd residual", vbd_sweep_shader(kinds, true));
    source_ = source;
  }
}

void GpuVbd::arrange() {
  upload(buffers_[unsigned(Buf::vbd_order) - unsigned(Buf::vbd_xn)], colours_.order);
  // Each colour's dispatch writes one merit slot per work group, after the 8 solver words.
  slot_.assign(colours_.count() + 1, 0u);
  for (std::uint32_t c = 0; c < colours_.count(); ++c)
    slot_[c + 1] = slot_[c] + (colours_.row[c + 1] - colours_.row[c] + kGroupSize - 1) / kGroupSize;
  upload(buffers_[unsigned(Buf::vbd_state) - unsigned(Buf::vbd_xn)],
         std::vector<std::uint32_t>(8 + std::size_t(slot_.back()), 0u));
}

void GpuVbd::bind() const {
  for (unsigned k = 0; k < kVbdBufferCount; ++k) {
    unsigned b = k;
    const unsigned p1 = unsigned(Buf::vbd_prev1) - unsigned(Buf::vbd_xn);
    const unsigned p2 = unsigned(Buf::vbd_prev2) - unsigned(Buf::vbd_xn);
    if (prev_swapped_ && (k == p1 || k == p2)) b = k == p1 ? p2 : p1;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unsigned(Buf::vbd_xn) + k, buffers_[b]);
  }
  obstacles_.bind();
  contacts_.bind();
}

DeviceImplicitStep GpuVbd::step(const Model& m, const ImplicitSettings& settings, double t, Real h,
                                std::uint64_t step, bool wind, bool measure,
                                const ContactSet& contacts) {
  // The step's contacts and the colours that keep them apart (the links' alone once none is
  // left).
  GpuVbdContacts::Counts counts;
  if (!contacts.pairs().empty() || !contacts.stencils().empty() || contacts_in_colours_) {
    counts = contacts_.update(contacts, colours_);
    arrange();
    contacts_in_colours_ = counts.any();
  }
  const bool bounded = counts.any();
  for (const Pass p : {begin_pass, sweep_pass, residual_pass, accelerate, bounds_pass}) {
    kernels_[p].set_flag("u_contacts", bounded);
    kernels_[p].set_flag("u_guarded", bounded && counts.guarded);
  }
  bind();
  // The obstacles: placed at t for the lag (at x_n, v_n), at t + h for the solve.
  const std::uint32_t obstacles = obstacles_.count();
  const float thinnest = obstacles_.thinnest();
  const bool thin = obstacles > 0 && std::isfinite(thinnest);
  for (const Pass p : {sweep_pass, residual_pass, lag_pass, first_touch}) {
    kernels_[p].set("u_obstacles", obstacles);
    kernels_[p].set("u_placed", p == lag_pass ? 0u : obstacles);
    kernels_[p].set("u_thinnest", thinnest);
  }
  kernels_[accelerate].set("u_thinnest", thinnest);
  if (obstacles > 0) {
    obstacles_.place(t, t + double(h));
    kernels_[lag_pass].run(points_);
  }
  const float rho = float(settings.acceleration);
  const bool accelerating = rho > 0;
  const std::uint32_t start[5] = {accelerating ? 1u : 0u, 0u,
                                  float_bits(std::numeric_limits<float>::infinity()), 0u, 0u};
  glNamedBufferSubData(buffers_[unsigned(Buf::vbd_state) - unsigned(Buf::vbd_xn)], 0, sizeof(start),
                       start);

  Kernel& bounds = kernels_[bounds_pass];
  if (bounded) bounds.run(points_);  // at x_n, for the guess
  Kernel& begin = kernels_[begin_pass];
  begin.set("u_gravity", m.fields.gravity);
  begin.set("u_h", float(h));
  begin.set_flag("u_wind", wind);
  begin.set_flag("u_history", history_);
  begin.run(points_);
  history_ = true;
  Kernel& touch = kernels_[first_touch];
  touch.set("u_h", float(h));
  if (thin) {  // the guess: stops at the first obstacle it enters
    touch.set_flag("u_through_only", false);
    touch.run(points_);
  }

  Kernel& sweep = kernels_[sweep_pass];
  sweep.set("u_h", float(h));
  sweep.set("u_drag", float(m.fields.air_drag));
  Kernel& acc = kernels_[accelerate];
  acc.set("u_h", float(h));
  Real omega = 1;
  for (int k = 1; k <= settings.iterations; ++k) {
    if (bounded) bounds.run(points_);  // at the sweep's start, as the CPU takes them
    for (std::uint32_t c = 0; c < colours_.count(); ++c) {
      sweep.set("u_first", colours_.row[c]);
      sweep.set("u_slot", slot_[c]);
      sweep.run(colours_.row[c + 1] - colours_.row[c]);
    }
    if (!accelerating) continue;
    kernels_[decide].set("u_k", GLuint(k));
    kernels_[decide].set("u_slots", slot_.back());
    kernels_[decide].set("u_growth", float(kFallbackGrowth));
    kernels_[decide].run(1);
    // The CPU's recurrence (law::chebyshev_omega), in double on the host.
    omega = law::chebyshev_omega(k, Real(rho), omega);
    acc.set("u_omega", float(omega));
    acc.set_flag("u_extrapolate", k >= 2);
    acc.run(points_);
    prev_swapped_ = !prev_swapped_;  // this sweep's x is prev1 now, the last prev1 is prev2
    bind();
  }
  if (thin) {  // the result: stops at the first obstacle it went through
    touch.set_flag("u_through_only", true);
    touch.run(points_);
  }
  kernels_[health].set("u_step", GLuint(std::min<std::uint64_t>(step, 0xfffffffeu)));
  kernels_[health].run(points_);

  DeviceImplicitStep out;
  out.iterations = std::uint64_t(settings.iterations);
  out.colours = colours_.count();
  if (measure) {
    Kernel& res = kernels_[residual_pass];
    res.set("u_first", GLuint(0));
    res.set("u_h", float(h));
    res.set("u_drag", float(m.fields.air_drag));
    res.run(GLuint(colours_.order.size()));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::uint32_t state[5] = {};
    glGetNamedBufferSubData(buffers_[unsigned(Buf::vbd_state) - unsigned(Buf::vbd_xn)], 0,
                            sizeof(state), state);
    out.acceleration_resets = state[3];
    const double g = gravity_ > 0 ? double(gravity_) : 9.81;
    out.residual = heaviest_ > 0 ? double(bits_float(state[4])) / (double(heaviest_) * g) : 0.0;
  }
  return out;
}

void GpuVbd::download_memory(State& s) const {
  if (!history_) return;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<float> tmp(3 * std::size_t(points_));
  glGetNamedBufferSubData(buffers_[unsigned(Buf::vbd_vlast) - unsigned(Buf::vbd_xn)], 0,
                          GLsizeiptr(tmp.size() * sizeof(float)), tmp.data());
  std::vector<double>& last = s.memory(std::string(kVbdMemory));
  last.assign(tmp.begin(), tmp.end());
}

}  // namespace maille::gpu
