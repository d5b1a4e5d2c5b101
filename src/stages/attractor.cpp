// [[attractor]]: a point that pulls the free points of some groups by an inverse-square law (a
// point mass's gravity; a negative strength repels), softened within `softening` so that a point
// passing through it meets a finite force (Plummer's softening):
//
//   f_i = m_i mu (p - x_i) / (|p - x_i|^2 + eps^2)^(3/2),   U_i = -m_i mu / sqrt(|p - x_i|^2 +
//   eps^2)
//
// mu = G M (m^3/s^2): a point at distance r on a circular orbit has the period
// 2 pi sqrt(r^3 / mu) (tests/physics/test_attractor.cpp checks it, and the energy).
//
// The whole stage is this file: settings, keys, the stage, its table and its registration
// (src/stages/: every file registers itself through cmake/RegisterFolder.cmake), the pattern
// docs/README.md's recipe "A stage" follows.
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "maille/limits.hpp"
#include "maille/model.hpp"
#include "maille/stage.hpp"
#include "maille/stage_keys.hpp"
#include "maille/stage_registry.hpp"
#include "maille/state.hpp"

namespace maille {

namespace {

constexpr StageInfo kAttractorStage{"attractor:", Phase::forces};  // + the attractor's name

struct Attractor {
  std::string name = "attractor";
  Vec3 position{};
  Real strength = 0;   // mu = G M, m^3/s^2; < 0 repels
  Real softening = 0;  // eps, m
  std::vector<std::string> groups;
};

std::span<const StageKey<Attractor>> attractor_keys() {
  using A = Attractor;
  static const std::array<StageKey<A>, 5> keys{
      stage_name<&A::name>({.doc = "names the stage (`attractor:NAME`) and its stats columns"}),
      vector<&A::position>("position", {.unit = "m", .doc = "p", .required = true}),
      number<&A::strength>(
          "strength", Bound::any, -limits::max_stiffness, limits::max_stiffness,
          {.unit = "m³/s²",
           .doc = "μ = G M: a circular orbit of radius r has period 2π √(r³/μ); < 0 repels",
           .required = true}),
      number<&A::softening>("softening", Bound::non_negative, 0, 2 * limits::max_coordinate,
                            {.unit = "m",
                             .doc = "ε: the pull is m μ r / (r² + ε²)^(3/2), finite at the "
                                    "point (0: the bare inverse square)"}),
      acted_groups<&A::groups>("groups", {.doc = "whose free points it pulls"}),
  };
  return keys;
}

// The free points of the groups (none named: every free point).
std::vector<std::uint32_t> pulled_points(const Model& m, const Attractor& a) {
  std::vector<std::uint8_t> in(m.points.size(), a.groups.empty() ? 1 : 0);
  for (const auto& name : a.groups)
    if (const Group* g = m.group(name))
      for (std::uint32_t p = g->first; p < g->first + g->count; ++p) in[p] = 1;
  std::vector<std::uint32_t> out;
  for (std::uint32_t p = 0; p < m.points.size(); ++p)
    if (in[p] && m.points.inv_mass[p] > 0) out.push_back(p);
  return out;
}

class AttractorStage final : public Stage {
 public:
  AttractorStage(const Model& m, Attractor a) : a_(std::move(a)) { model_changed(m); }

  std::string name() const override { return std::string(kAttractorStage.name) + a_.name; }
  Phase phase() const override { return kAttractorStage.phase; }
  void model_changed(const Model& m) override { points_ = pulled_points(m, a_); }

  void apply(const Model& m, State& s, const StageContext&) override {
    const auto x = s.x();
    const auto f = s.f();
    for (const std::uint32_t i : points_) {
      const Vec3 d = a_.position - x[i];
      const Real r2 = dot(d, d) + a_.softening * a_.softening;
      if (!(r2 > 0)) continue;  // on the bare point: no direction to pull along
      f[i] += d * (m.points.mass[i] * a_.strength / (r2 * std::sqrt(r2)));
    }
  }

  double energy(const Model& m, const State& s) override {
    const auto x = s.x();
    double e = 0;
    for (const std::uint32_t i : points_) {
      const Vec3 d = a_.position - x[i];
      const Real r2 = dot(d, d) + a_.softening * a_.softening;
      if (r2 > 0) e -= double(m.points.mass[i] * a_.strength / std::sqrt(r2));
    }
    return e;
  }

  // An unsoftened pull has no stiffness bound: the stability estimate cannot see it, so the run
  // says so rather than call any step stable.
  std::vector<std::string> warnings(const SimulationSettings&) const override {
    if (a_.softening > 0) return {};
    return {
        "no softening: the stability estimate leaves the attractor out (its stiffness "
        "m |strength| / r^3 grows without bound near it); give 'softening', or a step well "
        "below sqrt(r^3 / |strength|) for the closest approach r"};
  }

  // The pull's stiffness is largest at the point itself: |df/dx| <= m |mu| / eps^3 (radially
  // m mu (eps^2 - 2 r^2) / (r^2 + eps^2)^(5/2), across m mu / (r^2 + eps^2)^(3/2)). An unsoftened
  // attractor has no bound: the estimate leaves it out (its docs row says so).
  void stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                       std::span<Real>) const override {
    if (!(a_.softening > 0)) return;
    const Real per_mass = std::abs(a_.strength) / (a_.softening * a_.softening * a_.softening);
    for (const std::uint32_t i : points_) k_row[i] += per_mass / inv_mass[i];
  }

 private:
  Attractor a_;
  std::vector<std::uint32_t> points_;
};

StageSpec attractor_table(SceneTable& t, const Model& m) {
  Attractor a;
  read_key(t, a, attractor_keys(), "name");
  for (const StageSpec& other : m.stages)
    if (other.name == std::string(kAttractorStage.name) + a.name)
      t.fail("name", "another attractor is named '" + a.name + "'");
  read_key(t, a, attractor_keys(), "groups");
  for (const auto& g : a.groups) {
    const Group* group = m.group(g);
    if (!group) t.fail("groups", "no group named '" + g + "'");
  }
  read_keys(t, a, attractor_keys());
  if (pulled_points(m, a).empty()) t.fail("groups", "no free point to pull");
  StageSpec spec{{}, kAttractorStage.phase, [a](const Model& model) {
                   return std::make_unique<AttractorStage>(model, a);
                 }};
  spec.name = std::string(kAttractorStage.name) + a.name;
  visit_keys(attractor_keys(), a, [&](const StageKey<Attractor>& k, std::string v) {
    spec.parameters.emplace_back(std::string(k.key), std::move(v));
  });
  return spec;
}

}  // namespace

void register_stage_attractor(StageRegistry& r) {
  r.add({.table = "attractor",
         .array = true,
         .description = "a point pulling free points by an inverse-square law (softened)",
         .parse = attractor_table,
         .keys = describe_keys(attractor_keys(), Attractor{}),
         .stage = kAttractorStage});
}

}  // namespace maille
