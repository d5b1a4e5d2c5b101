// The fused grid step: when every link of the model runs in the structured kernel
// (one pool, all on grid groups: a flag, a tablecloth, a net; other links of that pool only
// between points off the grids, like the default scene's pole, run after the rows), the
// scheme is one kick and one drift (leapfrog, symplectic Euler) and nothing else adds forces
// between the link pass and the integration (no force or response stage, no energy sample this
// step; the wind only on faces of those grids), the step is one pass over the points instead of
// five: each row of a grid is finished as soon as its link forces are summed
// (detail/structured_grid.hpp), with gravity and drag, the wind on its six faces per point
// (wind_rows.hpp: the cells above and below the row, computed while their corners are at t_n),
// the force check and the kick-drift update, while its positions and forces are still in the
// caches.
//
// It computes what the separate passes compute, point by point and in the same order (the
// formulas are shared: point_update.hpp, and the wind's rows, wind_grid.hpp), so a fused step
// gives the same bits as an unfused one and steps of both kinds may follow each other in any
// order (sampling steps, a stage added later, one or two threads). Its time, the wind's
// included, is counted under link_forces; the wind_faces counter as the wind stage counts it.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <span>

#include "maille/link_loops.hpp"
#include "point_update.hpp"
#include "simulator_detail.hpp"
#include "stages.hpp"
#include "wind_rows.hpp"

namespace maille {

namespace {

struct FusedRows {
  const Real* mass;
  const Real* inv_mass;
  Vec3 g;
  Real gamma, kick, drift;
  Vec3* x;
  Vec3* v;
  Vec3* f;
  std::span<const PointGrid> grids;  // the kernel's
  detail::WindRows* wind;            // null: no wind on faces
  std::atomic<bool>* failed;
};

// Fields, the wind, the force check and the kick-drift of points first .. first + count - 1,
// whose link forces are in f: field_forces' point pass and grid rows, check_forces, kick_drift,
// in that order. A row with a non-finite force is left at t_n and the step reported as the
// unfused one would.
void finish_points(const FusedRows& r, std::uint32_t first, std::uint32_t count,
                   const FaceGrid* faces = nullptr, std::uint32_t row = 0) {
  const std::uint32_t end = first + count;
  for (std::uint32_t i = first; i < end; ++i)
    r.f[i] += point_update::field_force(r.g, r.gamma, r.mass[i], r.inv_mass[i], r.v[i]);
  if (faces) r.wind->row(*faces, row, r.x, r.v, r.f);
  // 0, or NaN where a force is not finite: any order of the sum tells, so it runs over the
  // row's coordinates as one array (Vec3 has no padding) in vectors (a sum in order is one
  // dependent add per point; by point, the vectoriser gathers).
  const Real* c = &r.f[first].x;
  Real bad = 0;
#pragma omp simd reduction(+ : bad)
  for (std::uint32_t k = 0; k < 3 * count; ++k) bad += c[k] * 0;
  if (!std::isfinite(bad)) {
    r.failed->store(true, std::memory_order_relaxed);
    return;
  }
  for (std::uint32_t i = first; i < end; ++i)
    point_update::kick_drift(r.x[i], r.v[i], r.f[i], r.inv_mass[i], r.kick, r.drift);
}

const FaceGrid* wind_faces(const FusedRows& r, std::size_t g) {
  return r.wind ? r.wind->faces(g) : nullptr;
}

void start_strip(void* context, std::size_t g, std::uint32_t r0, std::uint32_t r1) {
  const auto& r = *static_cast<const FusedRows*>(context);
  if (const FaceGrid* faces = wind_faces(r, g)) r.wind->strip(*faces, r0, r1, r.x, r.v);
}

void finish_row(void* context, std::size_t g, std::uint32_t j) {
  const auto& r = *static_cast<const FusedRows*>(context);
  const PointGrid& grid = r.grids[g];
  finish_points(r, grid.first + j * grid.nx, grid.nx, wind_faces(r, g), j);
}

// The one pool with links, whose links run structured but for links with no end on its grids
// (the default scene's pole), or null.
const LinkPoolBase* only_grid_pool(const Model& m) {
  const LinkPoolBase* grid = nullptr;
  for (const auto& pool : m.links.pools()) {
    if (pool->size() == 0) continue;
    if (grid || pool->structured_links() == 0 || !pool->others_off_grids()) return nullptr;
    grid = pool.get();
  }
  return grid;
}

}  // namespace

bool Simulator::fused_grid_step(Real h) {
  if (!stages_of(Phase::forces).empty() || !stages_of(Phase::response).empty()) return false;
  if (state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0) return false;
  const LinkPoolBase* pool = only_grid_pool(model_);
  if (!pool) return false;
  const bool wind = model_.fields.wind.active() && !model_.surface.triangles.empty();
  if (wind && !detail::WindRows::covers(model_, pool->structured_grids())) return false;
  const std::optional<Integrator::KickDrift> kd = integrator_->kick_drift_step(state_, h);
  if (!kd) return false;
  const auto& ids = *ids_;
  {
    detail::Timed t(profile_, ids.drive);
    stages::drive(model_, state_, state_.time);
  }
  std::atomic<bool> failed{false};
  {
    detail::Timed t(profile_, ids.links);
    profile_.set_count(ids.active_links, 0);
    profile_.set_count(ids.wind_faces, 0);
    pool->reserve_threads(threads_);
    if (wind) {
      if (!wind_rows_) wind_rows_ = std::make_unique<detail::WindRows>();
      wind_rows_->begin(model_, pool->structured_grids(), state_.time, threads_);
    }
    FusedRows rows{model_.points.mass.data(),
                   model_.points.inv_mass.data(),
                   model_.fields.gravity,
                   model_.fields.air_drag,
                   kd->kick,
                   kd->drift,
                   state_.x().data(),
                   state_.v().data(),
                   state_.f().data(),
                   pool->structured_grids(),
                   wind ? wind_rows_.get() : nullptr,
                   &failed};
    const detail::StructuredGrid::RowHook hook{start_strip, finish_row, &rows};
    const Vec3* x = rows.x;
    const Vec3* v = rows.v;
    // Points off the grids, in the gaps between them: f cleared, then their links (all off the
    // grids) once the grids' rows are done, then their fields and update.
    auto off_grids = [&](auto&& run) {
      std::uint32_t next = 0;
      for (const PointGrid& g : pool->structured_grids()) {
        if (g.first > next) run(next, g.first - next);
        next = g.first + g.nx * g.ny;
      }
      if (model_.points.size() > next) run(next, std::uint32_t(model_.points.size()) - next);
    };
    off_grids([&](std::uint32_t first, std::uint32_t count) {
      std::fill(rows.f + first, rows.f + first + count, Vec3{});
    });
    if (threads_ > 1) {
#pragma omp parallel num_threads(threads_)
      {
        structured_forces(*pool, x, v, rows.f, &hook);
        other_forces(*pool, x, v, rows.f);
      }
    } else {
      structured_forces(*pool, x, v, rows.f, &hook);
      other_forces(*pool, x, v, rows.f);
    }
    off_grids([&](std::uint32_t first, std::uint32_t count) { finish_points(rows, first, count); });
  }
  if (wind) profile_.set_count(ids.wind_faces, wind_rows_->pushed());
  if (failed.load()) {
    check_forces(state_);  // names the module, as the unfused step does
    return true;
  }
  state_.history = kd->history_after;
  return true;
}

}  // namespace maille
