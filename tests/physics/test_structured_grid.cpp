// The structured grid kernel (detail/structured_grid.hpp) against the general path
// (Model::structured_grids = false). Each link's force is the same function of the same values
// on both paths, so forces are bit-identical link by link; only the order in which a point sums
// its links' forces differs (row by row and family by family instead of the CPU schedule's
// bands), a rounding difference of a few ulp of the largest link force per point and step. The
// stated bound on positions after N steps: |x_structured - x_general| <= kBound times the
// scene's size (its initial bounding box diagonal), kBound = 1e-9 (measured after 200 steps: at
// most 8.2e-13, on two_cloths, where contacts amplify rounding; below 1e-15 on the others).
// Why a bound and not bit-identity: reproducing the CPU schedule's order per point (bands,
// colours, chunks of 256) would need index arrays again; the bound is 1000 times the measured
// worst case, small against any physical tolerance, and tight enough to catch a wrong link.
// An implicit example (integrator = "implicit_euler": cloth_on_sphere_vbd, cloth_heap_vbd) is
// compared after one step against kImplicitBound: the solve's sweeps amplify the summation
// order's rounding by the system's condition (one step at 1/60 s: 1.9e-10 of the scene's size
// on cloth_on_sphere_vbd, 3.4e-9 on cloth_heap_vbd), and later steps' discrete decisions
// (a contact entered or not, the acceleration's fallback) turn that into millimetres within 20
// steps (0.3 of the scene's size after 200), chaos rather than a wrong link, which would move a
// point by its force times h^2 / m in the first step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "maille/builders.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage.hpp"

namespace maille {
namespace {

constexpr double kBound = 1e-9;
constexpr double kImplicitBound = 1e-6;  // after one step; 300 times the measured worst case

double extent(const Model& m) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Vec3& p : m.points.initial_position) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return std::max(norm(hi - lo), 1e-3);
}

std::vector<Vec3> run(Model m, SimulationSettings s, bool structured, std::uint64_t steps,
                      int threads = 1) {
  m.structured_grids = structured;
  s.threads = threads;
  s.backend = "cpu";  // gpu_cloth_512 asks for the GPU
  Simulator sim(std::move(m), s);
  EXPECT_TRUE(sim.run_steps(steps));
  return {sim.state().x().begin(), sim.state().x().end()};
}

double max_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, double(norm(a[i] - b[i])));
  return d;
}

std::size_t structured_links(const Model& m) {
  Model copy = m;
  copy.prepare();
  std::size_t n = 0;
  for (const auto& p : copy.links.pools()) n += p->structured_links();
  return n;
}

Model flag(std::uint32_t nx, std::uint32_t ny) {
  Model m;
  FlagParams p;
  p.nx = nx;
  p.ny = ny;
  p.material = {200, 0.02};
  p.shear_stiffness = 100;
  p.bending_stiffness = 20;
  build_flag(m, p, "flag");
  m.fields.wind.velocity = {4, 0, 1};
  m.fields.wind.turbulence = 0.3;
  return m;
}

SimulationSettings quick(double h = 1e-4) {
  SimulationSettings s;
  s.step = h;
  s.publish_every = kNeverEvery;
  s.sample_every = kNeverEvery;
  return s;
}

// Every example: positions after 200 steps (fewer for the largest) agree within the bound, and
// every example with a grid group runs its grid links structured.
TEST(StructuredGrid, AgreesWithTheGeneralPathOnEveryExample) {
  int grids = 0;
  for (const auto& entry : std::filesystem::directory_iterator(MAILLE_SOURCE_DIR "/examples")) {
    if (entry.path().extension() != ".toml") continue;
    auto loaded = load_scene(entry.path().string());
    ASSERT_TRUE(loaded) << entry.path() << ": " << loaded.error().to_string();
    const Scene& scene = loaded.value();
    const bool has_grid = !point_grids(scene.model).empty();
    if (!has_grid) continue;
    ++grids;
    EXPECT_GT(structured_links(scene.model), 0u) << entry.path().filename();
    const bool implicit = scene.settings.integrator == "implicit_euler";
    const std::uint64_t steps = implicit ? 1 : scene.model.points.size() > 50000 ? 20 : 200;
    const auto a = run(scene.model, scene.settings, true, steps);
    const auto b = run(scene.model, scene.settings, false, steps);
    const double d = max_difference(a, b), scale = extent(scene.model);
    EXPECT_LE(d, (implicit ? kImplicitBound : kBound) * scale)
        << entry.path().filename() << ": " << d << " m";
    RecordProperty(entry.path().stem().string(), std::to_string(d / scale));
    std::printf("%s: %.3g of the scene's size\n", entry.path().stem().string().c_str(), d / scale);
  }
  EXPECT_GE(grids, 10);
}

// One and two threads split rows differently, but every point sums in the same order.
TEST(StructuredGrid, OneAndTwoThreadsAreBitIdentical) {
  const Model m = flag(70, 64);
  const auto one = run(m, quick(), true, 50, 1);
  const auto two = run(m, quick(), true, 50, 2);
  for (std::size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << "point " << i;
}

// A flag with holes: links touching a round hole are left out, so rows break into segments;
// extra links off the families (long diagonals) and a duplicate stay general.
TEST(StructuredGrid, HolesAndOtherLinks) {
  Model whole = flag(40, 30);
  Model m = whole;
  m.links = LinkSet{};
  const auto& pool = whole.links.pool<SpringDamper>();
  auto in_hole = [&](std::uint32_t p) {
    const int i = int(p % 40), j = int(p / 40);
    return (i - 20) * (i - 20) + (j - 15) * (j - 15) < 25 || (i == 7 && j > 3);
  };
  std::size_t kept = 0;
  for (std::size_t id = 0; id < pool.size(); ++id) {
    const LinkEnds e = pool.ends(id);
    if (in_hole(e.a) || in_hole(e.b)) continue;
    m.links.pool<SpringDamper>().add(e, pool.params(id));
    ++kept;
  }
  const auto& x = m.points.initial_position;
  m.links.pool<SpringDamper>().add({0, 82}, {50, norm(x[82] - x[0]), 0.01});     // (2, 2): off
  m.links.pool<SpringDamper>().add({100, 101}, {70, norm(x[101] - x[100]), 0});  // duplicate
  EXPECT_EQ(structured_links(m), kept);
  const auto a = run(m, quick(), true, 300);
  const auto b = run(m, quick(), false, 300);
  EXPECT_LE(max_difference(a, b), kBound * extent(m));
  // 1 and 2 threads still agree with holes.
  const auto two = run(m, quick(), true, 300, 2);
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], two[i]) << "point " << i;
}

// A kind defined only here, with the spring-damper's law but without `grid_stencil`: on a grid
// it runs through the general path (nothing structured), bit for bit as the built-in kind does
// on the general path.
struct TestOnlySpringDamper {
  static constexpr std::string_view keyword = "test_only_spring_damper";
  using Params = SpringDamper::Params;
  static constexpr auto fields = SpringDamper::fields;
  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                    const Params& p) {
    return SpringDamper::force(xa, xb, va, vb, p);
  }
  static Real energy(const Vec3& xa, const Vec3& xb, const Params& p) {
    return SpringDamper::energy(xa, xb, p);
  }
  static Real stiffness(const Params& p) { return SpringDamper::stiffness(p); }
  static Real damping(const Params& p) { return SpringDamper::damping(p); }
};

TEST(StructuredGrid, ATestOnlyKindOnAGridRunsThroughTheGeneralPath) {
  Model builtin = flag(24, 20);
  Model m = builtin;
  m.links = LinkSet{};
  const auto& pool = builtin.links.pool<SpringDamper>();
  for (std::size_t id = 0; id < pool.size(); ++id)
    m.links.pool<TestOnlySpringDamper>().add(pool.ends(id), pool.params(id));
  EXPECT_EQ(structured_links(m), 0u);
  EXPECT_EQ(structured_links(builtin), pool.size());
  const auto custom = run(m, quick(), true, 200);
  const auto general = run(builtin, quick(), false, 200);
  for (std::size_t i = 0; i < custom.size(); ++i) ASSERT_EQ(custom[i], general[i]) << i;
}

// Parameter edits between steps, as the viewer's sliders make them: one link in the middle of a
// uniform row (its row must stop using the row's first record), then every link scaled.
TEST(StructuredGrid, StiffnessEditsBetweenSteps) {
  const Model m = flag(32, 24);
  auto edited_run = [&](bool structured) {
    Model copy = m;
    copy.structured_grids = structured;
    SimulationSettings s = quick();
    s.threads = 1;
    Simulator sim(std::move(copy), s);
    sim.run_steps(50);
    sim.edit_parameters([](Model& model) {
      auto& p = model.links.pool<SpringDamper>();
      p.params_for_editing(40).stiffness *= 3;  // a horizontal link inside row 3 (id order)
      p.params_for_editing(41).rest_length *= Real(0.9);
    });
    sim.run_steps(50);
    sim.edit_parameters(
        [](Model& model) { model.links.find("spring_damper")->scale_param(0, Real(1.5)); });
    sim.run_steps(50);
    return std::vector<Vec3>(sim.state().x().begin(), sim.state().x().end());
  };
  const auto a = edited_run(true), b = edited_run(false);
  EXPECT_LE(max_difference(a, b), kBound * extent(m));
  const auto unedited = run(m, quick(), true, 150);
  EXPECT_GT(max_difference(a, unedited), 1e-6);  // the edits did something
}

// A structural edit: links added on the grid and off it, points added; the pools are prepared
// again (the grids found again) and the paths still agree.
TEST(StructuredGrid, EditModelPreparesAgain) {
  const Model m = flag(30, 20);
  auto edited_run = [&](bool structured) {
    Model copy = m;
    copy.structured_grids = structured;
    Simulator sim(std::move(copy), quick());
    sim.run_steps(40);
    sim.edit_model([](Model& model) {
      const auto& x = model.points.initial_position;
      auto& p = model.links.pool<SpringDamper>();
      p.add({35, 95}, {30, norm(x[95] - x[35]), 0});  // (0, 2) from point 35: a grid family
      const auto extra = model.points.add(PointKind::free, 0.01, x[599] + Vec3{0, 0, 0.05});
      p.add({599, extra}, {40, Real(0.05), 0});
    });
    EXPECT_EQ(sim.model().links.pools()[0]->structured_links() > 0, structured);
    sim.run_steps(60);
    return std::vector<Vec3>(sim.state().x().begin(), sim.state().x().end());
  };
  const auto a = edited_run(true), b = edited_run(false);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_LE(max_difference(a, b), kBound * extent(m));
}

// The fused grid step (simulator_fused.cpp): a lone flag without wind, leapfrog. Sampling
// energies every step keeps every step unfused; the two runs are identical bit for bit, with a
// driven pole and on one and two threads, and stay within the bound of the general path.
std::vector<Vec3> fused_run(const Model& m, int sample_every, int threads, const char* scheme,
                            std::uint64_t steps, std::vector<Vec3>* v = nullptr) {
  SimulationSettings s = quick();
  s.integrator = scheme;
  s.sample_every = sample_every;
  s.threads = threads;
  Simulator sim(m, s);
  EXPECT_TRUE(sim.run_steps(steps));
  if (v) v->assign(sim.state().v().begin(), sim.state().v().end());
  return {sim.state().x().begin(), sim.state().x().end()};
}

TEST(StructuredGrid, FusedStepIsBitIdenticalToTheUnfusedStep) {
  Model m = flag(48, 40);
  m.fields.wind = {};
  m.fields.air_drag = Real(0.05);
  // A shaken pole: its points are driven.
  for (std::uint32_t j = 0; j < 40; ++j) {
    const std::uint32_t p = j * 48;
    m.points.set_kind(p, PointKind::driven);
    Drive d;
    d.point = p;
    d.path.origin = m.points.initial_position[p];
    d.path.amplitude = {0, 0, Real(0.02)};
    d.path.frequency = 3;
    m.drives.push_back(d);
  }
  for (const char* scheme : {"leapfrog", "symplectic_euler"}) {
    std::vector<Vec3> v_fused, v_unfused, v_two;
    const auto fused = fused_run(m, kNeverEvery, 1, scheme, 300, &v_fused);
    const auto unfused = fused_run(m, 1, 1, scheme, 300, &v_unfused);
    const auto two = fused_run(m, 7, 2, scheme, 300, &v_two);
    for (std::size_t i = 0; i < fused.size(); ++i) {
      ASSERT_EQ(fused[i], unfused[i]) << scheme << " point " << i;
      ASSERT_EQ(v_fused[i], v_unfused[i]) << scheme << " point " << i;
      ASSERT_EQ(fused[i], two[i]) << scheme << " point " << i << " (2 threads)";
      ASSERT_EQ(v_fused[i], v_two[i]) << scheme << " point " << i << " (2 threads)";
    }
    Model general = m;
    general.structured_grids = false;
    const auto g = fused_run(general, kNeverEvery, 1, scheme, 300);
    EXPECT_LE(max_difference(fused, g), kBound * extent(m)) << scheme;
  }
}

// The fused grid step with gusty wind on the flags' faces (wind_rows.hpp): two flags (two
// grids; 70 points per row: two tiles of the wind's rows, 33 and 12 rows: two strips each on two
// threads) and a rope hung beside them (links of the same pool between points off the grids, as
// the default scene's pole: they run after the rows), the unfused step every step against the
// fused step, and two threads against one, bit for bit, with the same wind_faces count. A face
// off the grids, or a link from the rope to a flag, keeps the step unfused.
struct WindRun {
  std::vector<Vec3> x, v;
  std::uint64_t wind_faces = 0;
  double field_stage_ns = 0;  // the last step's field_forces stage: 0 when it was fused
};

WindRun windy_run(const Model& m, int sample_every, int threads, const char* scheme) {
  SimulationSettings s = quick();
  s.integrator = scheme;
  s.sample_every = sample_every;
  s.threads = threads;
  Simulator sim(m, s);
  EXPECT_TRUE(sim.run_steps(301));  // the last one (step 300) fused where sample_every allows
  WindRun r;
  r.x.assign(sim.state().x().begin(), sim.state().x().end());
  r.v.assign(sim.state().v().begin(), sim.state().v().end());
  for (const auto& c : sim.profile().counters())
    if (c.name == "wind_faces") r.wind_faces = c.last;
  for (const auto& st : sim.profile().stages())
    if (st.name == "field_forces") r.field_stage_ns = st.last_ns;
  return r;
}

void expect_same_bits(const WindRun& a, const WindRun& b, const std::string& what) {
  ASSERT_EQ(a.x.size(), b.x.size());
  for (std::size_t i = 0; i < a.x.size(); ++i) {
    ASSERT_EQ(a.x[i], b.x[i]) << what << " point " << i;
    ASSERT_EQ(a.v[i], b.v[i]) << what << " point " << i;
  }
  EXPECT_EQ(a.wind_faces, b.wind_faces) << what;
}

Model two_windy_flags() {
  Model m = flag(70, 33);
  FlagParams p;
  p.origin = {0, 0, 1};
  p.nx = 20;
  p.ny = 12;
  build_flag(m, p, "small");
  RopeParams r;
  r.start = {-0.5, 1, 0};
  r.end = {-0.5, 0, 0.3};
  r.points = 12;
  build_rope(m, r, "rope");
  m.fields.air_drag = Real(0.05);
  return m;
}

TEST(StructuredGrid, FusedStepWithGustyWindIsBitIdenticalToTheUnfusedStep) {
  const Model m = two_windy_flags();
  for (const char* scheme : {"leapfrog", "symplectic_euler"}) {
    const WindRun fused = windy_run(m, kNeverEvery, 1, scheme);
    const WindRun unfused = windy_run(m, 1, 1, scheme);
    const WindRun two = windy_run(m, kNeverEvery, 2, scheme);
    const WindRun mixed = windy_run(m, 7, 2, scheme);
    EXPECT_EQ(fused.field_stage_ns, 0) << scheme << ": the step was not fused";
    EXPECT_GT(unfused.field_stage_ns, 0) << scheme;
    // Every face of both flags pushed: 2 (nx - 1)(ny - 1) each.
    EXPECT_EQ(fused.wind_faces, 2u * 69 * 32 + 2u * 19 * 11) << scheme;
    expect_same_bits(fused, unfused, std::string(scheme) + " fused / unfused");
    expect_same_bits(fused, two, std::string(scheme) + " 1 / 2 threads");
    expect_same_bits(fused, mixed, std::string(scheme) + " fused / mixed, 2 threads");
  }
  Model calm = m;  // the wind did something
  calm.fields.wind = {};
  EXPECT_GT(max_difference(windy_run(calm, kNeverEvery, 1, "leapfrog").x,
                           windy_run(m, kNeverEvery, 1, "leapfrog").x),
            1e-4);
}

TEST(StructuredGrid, AFaceOrALinkOffTheGridsKeepsTheWindyStepUnfused) {
  Model loose = two_windy_flags();
  loose.surface.triangles.push_back({0, 2, 2 * 70});  // a face across grid cells: a loose face
  Model tied = two_windy_flags();
  const auto rope_end = std::uint32_t(tied.points.size() - 1);
  tied.links.pool<SpringDamper>().add({rope_end, 69}, {50, Real(0.5), 0});
  for (const Model* m : {&loose, &tied}) {
    const WindRun a = windy_run(*m, kNeverEvery, 1, "leapfrog");
    const WindRun b = windy_run(*m, 1, 1, "leapfrog");
    EXPECT_GT(a.field_stage_ns, 0);
    expect_same_bits(a, b, m == &loose ? "loose face" : "rope tied to a flag");
  }
}

// A force stage that adds nothing: with it the step is never fused, and nothing else changes.
class NothingStage final : public Stage {
 public:
  std::string name() const override { return "nothing"; }
  Phase phase() const override { return Phase::forces; }
  void apply(const Model&, State&, const StageContext&) override {}
};

// A blow-up inside a fused step is reported as the unfused step reports it: same step, same
// module; and before it, the same bits.
TEST(StructuredGrid, FusedStepReportsABlowUpAsTheUnfusedStep) {
  Model m = flag(20, 16);
  m.fields.wind = {};
  auto blow_up = [&](bool fused) {
    SimulationSettings s = quick(5e-2);  // far beyond the stable step
    Simulator sim(m, s);
    if (!fused) sim.add_stage(std::make_unique<NothingStage>());
    EXPECT_FALSE(sim.run_steps(2000));
    return std::pair{sim.state().step, sim.blow_up() ? sim.blow_up()->module : std::string()};
  };
  const auto fused = blow_up(true), unfused = blow_up(false);
  EXPECT_EQ(fused.first, unfused.first);
  EXPECT_EQ(fused.second, unfused.second);
  EXPECT_FALSE(fused.second.empty());
}

}  // namespace
}  // namespace maille
