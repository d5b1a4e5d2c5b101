// Self-collision: gather the colliding particles, find close pairs with the chosen broad phase
// (cell size tuned by measurement when "auto"), remove topological neighbours, and apply the
// conditional spring-damper per pair. See include/maille/self_collision.hpp.
#include "maille/self_collision.hpp"

#include "self_collision_engine.hpp"

namespace maille {

// 1 for every point of the named groups (all groups when none is named); the groups exist
// (resolve_self_collision checked them).
std::vector<std::uint8_t> group_mask(const Model& m, const std::vector<std::string>& groups) {
  std::vector<std::uint8_t> in(m.points.size(), 0);
  auto mark = [&](const Group& g) {
    for (std::uint32_t p = g.first; p < g.first + g.count; ++p) in[p] = 1;
  };
  if (groups.empty())
    for (const Group& g : m.groups) mark(g);
  for (const auto& name : groups)
    if (const Group* g = m.group(name)) mark(*g);
  return in;
}

// The free points of the named groups, sorted.
std::vector<std::uint32_t> colliding_points(const Model& m, const std::vector<std::uint8_t>& in) {
  std::vector<std::uint32_t> set;
  for (std::uint32_t p = 0; p < m.points.size(); ++p)
    if (in[p] && m.points.inv_mass[p] > 0) set.push_back(p);
  return set;
}

// Half the shortest link touching the set, at rest (the initial positions): close enough that
// neighbours never touch at rest, far enough that particles cannot slip between two others.
// 0 when no link touches the set.
Real default_radius(const Model& m, const std::vector<std::uint8_t>& in) {
  Real shortest = std::numeric_limits<Real>::max();
  for (const auto& pool : m.links.pools()) {
    if (pool->conditional()) continue;
    for (const LinkEnds& e : pool->slot_ends())
      if ((in[e.a] && m.points.inv_mass[e.a] > 0) || (in[e.b] && m.points.inv_mass[e.b] > 0))
        shortest = std::min(shortest,
                            norm(m.points.initial_position[e.b] - m.points.initial_position[e.a]));
  }
  if (shortest == std::numeric_limits<Real>::max() || shortest <= 0) return 0;
  return shortest / 2;
}

// Points can slip between a group's particles when the contact distance is below half their
// spacing: two particles a spacing apart leave a gap a point of the same group passes through
// without coming within s of either (the 24 x 24 cloth, 3.5 cm apart, with s = 1.2 cm
// folded through itself). The spacing is a particle's nearest linked neighbour at rest, the
// largest over the group. Nothing to say for primitive = "triangles", which closes the gaps.
std::vector<std::string> leak_warnings(const Model& m, const SelfCollisionSettings& s) {
  std::vector<std::string> out;
  if (s.primitive == Primitive::triangles) return out;
  std::vector<const Group*> groups;
  for (const Group& g : m.groups)
    if (s.groups.empty() || std::find(s.groups.begin(), s.groups.end(), g.name) != s.groups.end())
      groups.push_back(&g);
  const auto& x0 = m.points.initial_position;
  std::vector<Real> nearest(m.points.size(), std::numeric_limits<Real>::max());
  for (const auto& pool : m.links.pools()) {
    if (pool->conditional()) continue;
    for (const LinkEnds& e : pool->slot_ends()) {
      const Real d = norm(x0[e.b] - x0[e.a]);
      nearest[e.a] = std::min(nearest[e.a], d);
      nearest[e.b] = std::min(nearest[e.b], d);
    }
  }
  for (const Group* g : groups) {
    Real spacing = 0;
    for (std::uint32_t p = g->first; p < g->first + g->count; ++p)
      if (m.points.inv_mass[p] > 0 && nearest[p] < std::numeric_limits<Real>::max())
        spacing = std::max(spacing, nearest[p]);
    if (!(s.radius < spacing / 2 * (1 - 1e-9))) continue;  // (spacings carry rounding)
    std::ostringstream w;
    w.precision(4);
    w << "radius " << s.radius << " m is below half the rest spacing of group '" << g->name << "' ("
      << spacing << " m): points can slip between its particles and the cloth pass "
      << "through itself; set radius >= " << spacing / 2
      << " m, or primitive = \"triangles\" (docs/scene-format.md, [self_collision])";
    out.push_back(w.str());
  }
  return out;
}

// Vertex block descent at steps above 1/240 s with a topological exclusion: nothing but
// bending keeps a cell from folding over the neighbours the exclusion skips, and an unconverged
// solve at large steps finds those folds (cloth_on_sphere with particle contacts a spacing
// thick crossed in 40 triangle pairs at 1/60 s with 10 sweeps, none at 1/240 s). The thin
// layer of particle-face contacts with no exclusion crossed in none (docs/implicit.md).
std::string fold_warning(const SimulationSettings& sim, const SelfCollisionSettings& s) {
  constexpr double kSafeStep = 1.0 / 240;
  if (sim.integrator != kImplicitEuler || sim.implicit.solver != ImplicitSolver::vbd ||
      s.topological_radius == 0 || sim.step <= kSafeStep * (1 + 1e-9))
    return {};
  std::ostringstream w;
  w.precision(4);
  w << "topological_radius = " << s.topological_radius
    << " under implicit_euler (solver = \"vbd\") at h = " << sim.step
    << " s: the exclusion leaves a cell free to fold over its neighbours, which steps above "
    << kSafeStep << " s let the solve do; use a thin layer: primitive = \"triangles\", "
    << "topological_radius = 0 and a radius a quarter to a third of the spacing "
    << "(docs/implicit.md, \"Self-collision at large steps\")";
  return w.str();
}

SelfCollisionEngine::SelfCollisionEngine(const Model& m, SelfCollisionSettings s)
    : impl_(std::make_unique<SelfCollision>(m, std::move(s))) {}
SelfCollisionEngine::~SelfCollisionEngine() = default;
SelfCollisionEngine::SelfCollisionEngine(SelfCollisionEngine&&) noexcept = default;

std::vector<std::pair<std::uint32_t, std::uint32_t>> SelfCollisionEngine::close_pairs(const Vec3* x,
                                                                                      int threads) {
  return impl_->close_pairs(x, threads);
}
SelfCollisionStats SelfCollisionEngine::apply(const Vec3* x, const Vec3* v, Vec3* f, int threads) {
  return impl_->apply(x, v, f, threads);
}
bool SelfCollisionEngine::motion_bounds(const Vec3* x, Real share, std::vector<Real>& bound) const {
  return impl_->motion_bounds(x, share, bound);
}
const SelfCollisionSettings& SelfCollisionEngine::settings() const {
  return impl_->settings();
}
std::size_t SelfCollisionEngine::particles() const {
  return impl_->particles();
}
std::size_t SelfCollisionEngine::exclusion_bytes() const {
  return impl_->exclusion_bytes();
}
const std::vector<SelfCollisionEngine::TuneRecord>& SelfCollisionEngine::last_tuning() const {
  return impl_->tuning();
}
void SelfCollisionEngine::set_broad_phase(BroadPhase b) {
  impl_->set_broad_phase(b);
}
void SelfCollisionEngine::set_exclusion(Exclusion e) {
  impl_->set_exclusion(e);
}
void SelfCollisionEngine::set_cell_size(Real c) {
  impl_->set_cell_size(c);
}

std::uint64_t self_collision_exclusion_bytes(const Model& m,
                                             std::span<const std::uint32_t> particles,
                                             int topological_radius) {
  if (topological_radius == 0 || particles.empty()) return 0;
  const std::vector<std::uint32_t> set(particles.begin(), particles.end());
  const std::uint64_t row =
      collision::TopologicalExclusion::sampled_row_bound(m, set, topological_radius);
  const std::uint64_t n = set.size(), points = m.points.size();
  std::uint64_t link_ends = 0;
  for (const auto& pool : m.links.pools())
    if (!pool->conditional()) link_ends += 2 * pool->size();
  return 4 * (row * n + (n + 1)) +       // the rows and their offsets
         4 * (link_ends + 2 * points) +  // the adjacency (CSR) and the search's marks
         4 * points + 16 * n;            // the local index, each particle's grid cell
}

ExclusionRows self_collision_exclusion_rows(const Model& m,
                                            std::span<const std::uint32_t> particles,
                                            int topological_radius) {
  const std::vector<std::uint32_t> set(particles.begin(), particles.end());
  const collision::TopologicalExclusion rows(m, set, topological_radius, false);
  return {rows.row_offsets(), rows.row_entries()};
}

}  // namespace maille
