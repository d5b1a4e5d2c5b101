// The fused grid step (issue 23): when every link of the model runs in the structured kernel
// (one pool, all on grid groups: a flag, a tablecloth, a net with nothing else linked), the
// scheme is one kick and one drift (leapfrog, symplectic Euler) and nothing else adds forces
// between the link pass and the integration (no force or response stage, no wind, no energy
// sample this step), the step is one pass over the points instead of five: each row of a grid
// is finished as soon as its link forces are summed (detail/structured_grid.hpp), with gravity
// and drag, the force check and the kick-drift update, while its positions and forces are still
// in the caches.
//
// It computes what the separate passes compute, point by point and in the same order (the
// formulas are shared: point_update.hpp), so a fused step gives the same bits as an unfused one
// and steps of both kinds may follow each other in any order (sampling steps, a stage added
// later, one or two threads). Its time is counted under link_forces.
#include <atomic>
#include <cmath>

#include "point_update.hpp"
#include "simulator_detail.hpp"
#include "stages.hpp"

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
  std::atomic<bool>* failed;
};

// Fields, the force check and the kick-drift of points first .. first + count - 1, whose link
// forces are in f: field_forces' point pass, check_forces, kick_drift, in that order. A row
// with a non-finite force is left at t_n and the step reported as the unfused one would.
void finish_points(const FusedRows& r, std::uint32_t first, std::uint32_t count) {
  Real bad = 0;
  for (std::uint32_t i = first; i < first + count; ++i) {
    r.f[i] += point_update::field_force(r.g, r.gamma, r.mass[i], r.inv_mass[i], r.v[i]);
    bad += r.f[i].x * 0 + r.f[i].y * 0 + r.f[i].z * 0;
  }
  if (!std::isfinite(bad)) {
    r.failed->store(true, std::memory_order_relaxed);
    return;
  }
  for (std::uint32_t i = first; i < first + count; ++i)
    point_update::kick_drift(r.x[i], r.v[i], r.f[i], r.inv_mass[i], r.kick, r.drift);
}

void finish_row(void* context, std::uint32_t first, std::uint32_t count) {
  finish_points(*static_cast<const FusedRows*>(context), first, count);
}

// The one pool whose links all run structured, or null when the model has other links.
const LinkPoolBase* only_grid_pool(const Model& m) {
  const LinkPoolBase* grid = nullptr;
  for (const auto& pool : m.links.pools()) {
    if (pool->size() == 0) continue;
    if (grid || pool->structured_links() != pool->size()) return nullptr;
    grid = pool.get();
  }
  return grid;
}

}  // namespace

bool Simulator::fused_grid_step(Real h) {
  if (!force_stages_.empty() || !response_stages_.empty()) return false;
  if (state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0) return false;
  if (model_.fields.wind.active() && !model_.surface.triangles.empty()) return false;
  const LinkPoolBase* pool = only_grid_pool(model_);
  if (!pool) return false;
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
    FusedRows rows{model_.points.mass.data(),
                   model_.points.inv_mass.data(),
                   model_.fields.gravity,
                   model_.fields.air_drag,
                   kd->kick,
                   kd->drift,
                   state_.x().data(),
                   state_.v().data(),
                   state_.f().data(),
                   &failed};
    const detail::StructuredGrid::RowHook hook{finish_row, &rows};
    const Vec3* x = rows.x;
    const Vec3* v = rows.v;
    if (threads_ > 1) {
#pragma omp parallel num_threads(threads_)
      pool->structured_forces(x, v, rows.f, &hook);
    } else {
      pool->structured_forces(x, v, rows.f, &hook);
    }
    // Points off the grids: no link forces, fields and the update only.
    std::uint32_t next = 0;
    auto rest = [&](std::uint32_t end) {
      for (std::uint32_t i = next; i < end; ++i) rows.f[i] = Vec3{};
      if (end > next) finish_points(rows, next, end - next);
    };
    for (const PointGrid& g : pool->structured_grids()) {
      rest(g.first);
      next = g.first + g.nx * g.ny;
    }
    rest(model_.points.size());
  }
  if (failed.load()) {
    check_forces(state_);  // names the module, as the unfused step does
    return true;
  }
  state_.history = kd->history_after;
  return true;
}

}  // namespace maille
