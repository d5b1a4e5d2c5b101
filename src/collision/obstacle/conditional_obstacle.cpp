// The conditional obstacle stage (include/maille/obstacle.hpp): fixed points sampled on the
// obstacle's surface, each acting on the colliding particles through the `conditional` link's
// law (ConditionalSpringDamper: a spring-damper toward the threshold while closer than it).
//
// Rather than one link per (sample, particle) pair, which is what the method as first described
// would build and what costs P x S, the samples are binned in a hashed grid of cells one threshold
// wide: a particle meets only the samples of the 27 cells around it, and a particle away from
// the obstacle costs one box test. The forces are those of the links that method would build.
//
// Samples are laid on each facet of the obstacle's mesh (placed in the world at t = 0) on a
// triangular lattice no coarser than the threshold, shared vertices and edges merged, so no gap
// wider than the threshold opens between them. A moving obstacle moves rigidly: particles are
// brought into the obstacle's frame at t = 0 (distances unchanged), the samples never move.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "maille/limits.hpp"
#include "maille/links/conditional.hpp"
#include "maille/mat3.hpp"
#include "maille/obstacle.hpp"
#include "maille/profile.hpp"
#include "maille/state.hpp"
#include "obstacle_check.hpp"
#include "obstacle_surface.hpp"
#include "point_contact_stage.hpp"

namespace maille {

namespace {

// Samples per particle that can act at once, for the stability estimate: on a flat surface
// sampled at spacing s, a particle within s of it is within s of at most about 4 samples.
constexpr Real kSamplesAtOnce = 4;
struct CellKey {
  std::int64_t i, j, k;
  bool operator==(const CellKey&) const = default;
};
struct CellHash {  // unsigned arithmetic: wraps, never overflows (cells far from the origin)
  std::size_t operator()(const CellKey& c) const {
    return std::size_t(std::uint64_t(c.i) * 73856093ull ^ std::uint64_t(c.j) * 19349663ull ^
                       std::uint64_t(c.k) * 83492791ull);
  }
};

std::vector<Vec3> sample_surface(const TriMesh& mesh, const shapes::Affine& place, Real spacing,
                                 const std::string& name) {
  if (const std::string why = sampling_problem(mesh, place, spacing); !why.empty())
    throw std::invalid_argument("obstacle '" + name + "': " + why);
  std::vector<Vec3> world(mesh.vertices.size());
  for (std::size_t i = 0; i < world.size(); ++i) world[i] = place.to_world(mesh.vertices[i]);
  double reach = 0;
  for (const Vec3& x : world)
    reach = std::max({reach, double(std::abs(x.x)), double(std::abs(x.y)), double(std::abs(x.z))});
  // Merge coincident samples (shared edges and vertices) by a grid far finer than the spacing,
  // never finer than 2^-52 of the coordinates (x / snap stays within a 64-bit integer).
  std::unordered_map<CellKey, std::uint32_t, CellHash> seen;
  std::vector<Vec3> samples;
  const Real snap = std::max(spacing * Real(1e-6), Real(reach * 0x1p-52));
  auto add = [&](const Vec3& x) {
    const CellKey key{std::llround(x.x / snap), std::llround(x.y / snap), std::llround(x.z / snap)};
    if (seen.emplace(key, std::uint32_t(samples.size())).second) samples.push_back(x);
  };
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = world[t[0]], &b = world[t[1]], &c = world[t[2]];
    const Real longest = std::max({norm(b - a), norm(c - b), norm(a - c)});
    const auto divisions = std::uint64_t(std::ceil(longest / spacing));
    const Real inv = divisions > 0 ? Real(1) / Real(divisions) : 0;
    for (std::uint64_t i = 0; i <= divisions; ++i)
      for (std::uint64_t j = 0; i + j <= divisions; ++j)
        add(a + (b - a) * (Real(i) * inv) + (c - a) * (Real(j) * inv));
  }
  return samples;
}

class ConditionalObstacleStage final : public PointContactStage {
 public:
  ConditionalObstacleStage(const Model& m, Obstacle o)
      : o_(std::move(o)),
        set_(colliding_points(m, o_)),
        member_(m.points.size(), 0),
        surface_(o_, std::make_shared<const TriMesh>(obstacle_mesh(o_))) {
    for (std::uint32_t p : set_) member_[p] = 1;
    samples_ = sample_surface(*surface_.mesh(), o_.place, o_.threshold, o_.name);
    inv_cell_ = 1 / o_.threshold;
    lo_ = hi_ = samples_.front();
    for (std::uint32_t i = 0; i < samples_.size(); ++i) {
      const Vec3& x = samples_[i];
      lo_ = {std::min(lo_.x, x.x), std::min(lo_.y, x.y), std::min(lo_.z, x.z)};
      hi_ = {std::max(hi_.x, x.x), std::max(hi_.y, x.y), std::max(hi_.z, x.z)};
      cells_[key(x)].push_back(i);
    }
    lo_ -= Vec3{1, 1, 1} * o_.threshold, hi_ += Vec3{1, 1, 1} * o_.threshold;
    params_.stiffness = o_.stiffness;
    params_.damping = o_.damping;
    params_.threshold = o_.threshold;
    params_.rest_length = o_.threshold;  // continuous at the threshold, as [[contact]] does
  }

  std::string name() const override { return obstacle_stage_name(o_); }
  Phase phase() const override { return obstacle_phase(o_.method); }

  // Each sample within the threshold is a conditional spring: 1/2 k (d - threshold)^2.
  double energy(const Model&, const State& s) override {
    const shapes::Affine now = o_.motion.at(shapes::Affine{}, s.time);
    double e = 0;
    for (const std::uint32_t p : set_)
      e += near_samples(s.x()[p], Vec3{}, now, s.time, nullptr).energy;
    return e;
  }

  void scan(const State& s, const StageContext& ctx, Vec3* f) override {
    // The rigid motion since t = 0 (x_now = R x_0 + d): particles go back by its inverse.
    const shapes::Affine now = o_.motion.at(shapes::Affine{}, ctx.t);
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    std::uint64_t contacts = 0;
    Real deepest = 0;
    for (std::uint32_t p : set_) {
      const Near near = near_samples(x[p], v[p], now, ctx.t, nullptr);
      if (near.nearest2 >= o_.threshold * o_.threshold) continue;
      ++contacts;
      deepest = std::max(deepest, o_.threshold - std::sqrt(near.nearest2));
      if (f) f[p] += near.force;
    }
    count(ctx, o_.name, contacts, deepest);
  }

  void stability_terms(std::span<const Real>, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    for (std::uint32_t p : set_) {
      k_row[p] += kSamplesAtOnce * o_.stiffness;
      c_row[p] += kSamplesAtOnce * o_.damping;
    }
  }

  void surfaces(double t, std::vector<SurfaceInstance>& out) const override {
    surface_.add(o_, t, out);
  }

  // Implicit solvers take the samples' springs into the solve: at each iterate, a point's force
  // is the one apply() would give there, and its stiffness the conditional law's block (definite
  // mode), so VBD and matrix-free CG hold the cloth at large steps as a stiff contact would.
  void set_time(double t) override {
    time_ = t;
    now_ = o_.motion.at(shapes::Affine{}, t);
  }
  // The band around the samples where a point is in contact is at least a threshold deep.
  Real thickness() const override { return o_.threshold; }
  void add_terms(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v, Real inv_h,
                 Vec3* f, Mat3* hessian, std::uint8_t* touching) const override {
    for (const std::uint32_t p : points) {
      if (!member_[p]) continue;
      Mat3 stiffness;
      const Near near = near_samples(x[p], v[p], now_, time_, &stiffness, inv_h);
      if (near.nearest2 >= o_.threshold * o_.threshold) continue;
      f[p] += near.force;
      hessian[p] += stiffness;
      if (touching) touching[p] = 1;
    }
  }

  Vec3 push(std::uint32_t p, const Vec3& x) const override {
    if (!member_[p]) return {};
    const Vec3 at_rest = o_.motion.moves() ? o_.motion.velocity_at(x, time_) : Vec3{};
    const Near near = near_samples(x, at_rest, now_, time_, nullptr);
    return near.nearest2 < o_.threshold * o_.threshold ? near.force : Vec3{};
  }

 private:
  struct Near {
    Vec3 force;       // world force of every sample within the threshold, N
    Real nearest2;    // squared distance to the nearest of them (threshold^2 when none), m^2
    Real energy = 0;  // the samples' springs' energy, J
  };

  // The samples' forces on a point at x, v with the obstacle placed by `now` (its motion at t),
  // and their stiffness -df/dx - (1/h) df/dv in the world when `stiffness` is not null.
  Near near_samples(const Vec3& x, const Vec3& v, const shapes::Affine& now, double t,
                    Mat3* stiffness, Real inv_h = 0) const {
    const bool moves = o_.motion.moves();
    Near out{{}, o_.threshold * o_.threshold};
    const Vec3 xb = moves ? transpose_times(now.direct, x - now.translation) : x;
    if (xb.x < lo_.x || xb.y < lo_.y || xb.z < lo_.z || xb.x > hi_.x || xb.y > hi_.y ||
        xb.z > hi_.z)
      return out;  // away from the obstacle: one box test
    const Vec3 vr = moves ? transpose_times(now.direct, v - o_.motion.velocity_at(x, t)) : v;
    Vec3 force;
    Mat3 block;
    const CellKey c = key(xb);
    for (std::int64_t dk = -1; dk <= 1; ++dk)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
        for (std::int64_t di = -1; di <= 1; ++di) {
          const auto it = cells_.find({c.i + di, c.j + dj, c.k + dk});
          if (it == cells_.end()) continue;
          for (std::uint32_t si : it->second) {
            const Vec3& xs = samples_[si];
            if (!ConditionalSpringDamper::is_active(xs, xb, params_)) continue;
            out.nearest2 = std::min(out.nearest2, norm2(xb - xs));
            out.energy += ConditionalSpringDamper::energy(xs, xb, params_);
            force -= ConditionalSpringDamper::force(xs, xb, Vec3{}, vr, params_);
            if (stiffness) {
              const LinkJacobian j = ConditionalSpringDamper::jacobian(xs, xb, Vec3{}, vr, params_,
                                                                       JacobianMode::definite);
              block += j.dx + j.dv * inv_h;
            }
          }
        }
    out.force = moves ? now.direct * force : force;
    if (stiffness) *stiffness = moves ? now.direct * block * transpose(now.direct) : block;
    return out;
  }

  CellKey key(const Vec3& x) const {
    return {std::int64_t(std::floor(x.x * inv_cell_)), std::int64_t(std::floor(x.y * inv_cell_)),
            std::int64_t(std::floor(x.z * inv_cell_))};
  }

  Obstacle o_;
  std::vector<std::uint32_t> set_;
  std::vector<std::uint8_t> member_;  // [points]: 1 for the colliding points (set_)
  ObstacleSurface surface_;
  std::vector<Vec3> samples_;  // world positions at t = 0
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> cells_;
  Vec3 lo_, hi_;  // the samples' box grown by the threshold
  Real inv_cell_ = 1;
  ConditionalSpringDamper::Params params_;
  double time_ = 0;     // the implicit solve's time (set_time)
  shapes::Affine now_;  // the rigid motion at time_
};

}  // namespace

std::unique_ptr<Stage> make_conditional_obstacle_stage(const Model& m, const Obstacle& o) {
  return std::make_unique<ConditionalObstacleStage>(m, o);
}

}  // namespace maille
