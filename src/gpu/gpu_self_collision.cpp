// The self_collision stage on the GPU: see gpu_self_collision.hpp for the passes and the
// choices behind them.
#include "gpu_self_collision.hpp"

#include <epoxy/gl.h>

#include <algorithm>

#include "../collision/self/self_collision_view.hpp"
#include "gl_buffers.hpp"
#include "maille/self_collision.hpp"
#include "shaders.hpp"

namespace maille::gpu {

namespace {

// 2^-10: cells a little larger than s, so that rounding the cell coordinates in float never
// puts two particles closer than s two cells apart.
constexpr double kCellMargin = 1.0 + 1.0 / 1024;

enum Pass : unsigned { bounds, grid, zero, count, scan, scan_add, scatter, sort, contacts, passes };

std::vector<std::uint32_t> download(GLuint buffer, std::size_t count) {
  std::vector<std::uint32_t> out(count);
  if (count) glGetNamedBufferSubData(buffer, 0, GLsizeiptr(count * 4), out.data());
  return out;
}

}  // namespace

std::string GpuSelfCollision::check(const Stage& st) {
  const SelfCollisionView view = self_collision_view(st);
  if (!view.settings) return "stage '" + st.name() + "' is not the self-collision stage";
  if (view.settings->primitive != Primitive::points)
    return "stage '" + st.name() + "' with primitive = \"triangles\" has no GPU version (its " +
           "point-triangle and edge-edge contacts run on the CPU only; the GPU runs primitive = " +
           "\"points\"): run this scene with --backend cpu (or without it: --no-self-collision)";
  if (view.settings->broad_phase != BroadPhase::uniform)
    return "stage '" + st.name() + "' with broad_phase = \"" +
           std::string(to_string(view.settings->broad_phase)) +
           "\" has no GPU version (the GPU builds its own uniform grid; every broad phase finds "
           "the same pairs): use broad_phase = \"uniform\" or --backend cpu";
  return std::string();
}

GpuSelfCollision::GpuSelfCollision(const Model& m, const Stage& st, double max_invocations)
    : stage_(&st) {
  const SelfCollisionView view = self_collision_view(st);
  const SelfCollisionSettings& s = *view.settings;
  particles_ = std::uint32_t(view.particles.size());
  cell_ = float(std::max(s.radius, s.cell_size) * kCellMargin);
  // The CPU's budget, within what one dispatch reaches (the per-cell passes).
  cells_ = std::uint32_t(std::min(std::max(8.0 * particles_, 4096.0), max_invocations - 1));

  glCreateBuffers(GLsizei(buffers_.size()), buffers_.data());
  auto buffer = [&](Buf b) { return buffers_[unsigned(b) - kBufferCount]; };
  upload(buffer(Buf::sc_particle),
         std::vector<std::uint32_t>(view.particles.begin(), view.particles.end()));
  const ExclusionRows rows = self_collision_exclusion_rows(m, view.particles, s.topological_radius);
  upload(buffer(Buf::sc_excluded_offset), rows.offset);
  upload(buffer(Buf::sc_excluded), rows.partner);
  upload(buffer(Buf::sc_slot), std::vector<std::uint32_t>(2 * std::size_t(particles_)));
  upload(buffer(Buf::sc_order), std::vector<std::uint32_t>(particles_));
  upload(buffer(Buf::sc_contacts), std::vector<std::uint32_t>(particles_));
  SelfGrid empty{};
  empty.lo_x = empty.lo_y = empty.lo_z = 0xffffffffu;
  upload(buffer(Buf::sc_grid), std::vector<SelfGrid>{empty});
  // The scan's levels, one after the other in sc_cell_start: the cells + 1 counts, then the
  // totals of their blocks of kScanBlock, then those of the totals' blocks... up to one block.
  std::uint32_t size = cells_ + 1, offset = 0;
  for (;;) {
    level_offset_.push_back(offset);
    level_size_.push_back(size);
    if (size <= kScanBlock) break;
    offset += size;
    size = (size + kScanBlock - 1) / kScanBlock;
  }
  upload(buffer(Buf::sc_cell_start),
         std::vector<std::uint32_t>(level_offset_.back() + level_size_.back()));

  kernels_.reserve(passes);
  for (const KernelSource& k : self_collision_kernels())  // in Pass order
    kernels_.emplace_back("gpu self-collision " + k.name, k.source);
  Kernel& k = kernels_[contacts];
  k.set("u_radius", float(s.radius));
  k.set("u_stiffness", float(s.stiffness));
  k.set("u_damping", float(s.damping));
  k.set("u_friction", float(s.friction));
  k.set("u_slip", float(kSelfCollisionSlip));
  kernels_[grid].set("u_cell", cell_);
  kernels_[grid].set("u_budget", cells_);
}

GpuSelfCollision::~GpuSelfCollision() {
  kernels_.clear();
  glDeleteBuffers(GLsizei(buffers_.size()), buffers_.data());
}

void GpuSelfCollision::bind() const {
  for (unsigned k = 0; k < kSelfBufferCount; ++k)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBufferCount + k, buffers_[k]);
}

void GpuSelfCollision::evaluate(double) {
  const SelfCollisionView view = self_collision_view(*stage_);
  // Triangles (accepted under VBD, whose solve takes their stencils) have no explicit pass here.
  if (!view.enabled || particles_ == 0 || view.settings->primitive != Primitive::points) return;
  bind();
  kernels_[bounds].run(particles_);
  kernels_[grid].run(1);
  kernels_[zero].run(cells_ + 1);
  kernels_[count].run(particles_);
  // Up the levels: each block's exclusive sums, its total one level up; then back down, each
  // level's scanned totals added to the blocks they stand for.
  Kernel& up = kernels_[scan];
  const std::size_t top = level_size_.size() - 1;
  for (std::size_t l = 0; l <= top; ++l) {
    up.set("u_in", level_offset_[l]);
    up.set("u_sums", l < top ? level_offset_[l + 1] : 0u);
    up.set_flag("u_has_sums", l < top);
    up.run(level_size_[l], (level_size_[l] + kScanBlock - 1) / kScanBlock);
  }
  Kernel& down = kernels_[scan_add];
  for (std::size_t l = top; l-- > 0;) {
    down.set("u_in", level_offset_[l]);
    down.set("u_sums", level_offset_[l + 1]);
    down.run(level_size_[l]);
  }
  kernels_[scatter].run(particles_);
  kernels_[sort].run(cells_);
  kernels_[contacts].set_flag("u_exclude", view.settings->exclusion != Exclusion::none);
  kernels_[contacts].run(particles_);
}

SelfCollisionDebug GpuSelfCollision::debug() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  auto buffer = [&](Buf b) { return buffers_[unsigned(b) - kBufferCount]; };
  SelfCollisionDebug d;
  d.particles = download(buffer(Buf::sc_particle), particles_);
  d.contacts = download(buffer(Buf::sc_contacts), particles_);
  const std::vector<std::uint32_t> slots = download(buffer(Buf::sc_slot), 2 * particles_);
  for (std::uint32_t a = 0; a < particles_; ++a) d.cell_of.push_back(slots[2 * a]);
  d.cell_start = download(buffer(Buf::sc_cell_start), std::size_t(cells_) + 1);
  d.order = download(buffer(Buf::sc_order), particles_);
  SelfGrid g{};
  glGetNamedBufferSubData(buffer(Buf::sc_grid), 0, sizeof g, &g);
  d.origin = {g.origin_x, g.origin_y, g.origin_z};
  d.cell = g.cell;
  d.dims = {g.nx, g.ny, g.nz};
  d.budget = cells_;
  return d;
}

}  // namespace maille::gpu
