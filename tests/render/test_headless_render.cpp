// The renderer, headless (EGL surfaceless, Mesa's llvmpipe): what comes out is checked pixel by
// pixel against what the camera should show.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>

#include "example_run.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/mesh.hpp"
#include "maille/render/headless.hpp"
#include "maille/render/image.hpp"
#include "maille/render/movie.hpp"
#include "maille/render/renderer.hpp"
#include "maille/render/snapshot_exchange.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/smooth_surface.hpp"

namespace maille::render {
namespace {

// One context for the whole suite: creating one costs more than a frame.
class HeadlessRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = new HeadlessContext(); }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  static HeadlessContext* context_;
};
HeadlessContext* HeadlessRender::context_ = nullptr;

constexpr int kWidth = 320, kHeight = 200;

// Cloth pixels: the surface's front (orange-red) and back (golden) are both far redder than
// blue; the background, grid and fixed points are grey (r = g = b within a few units).
bool is_cloth(Image::Pixel p) {
  return int(p.r) - int(p.b) > 60;
}

struct ClothPixels {
  int count = 0;
  int x0 = kWidth, y0 = kHeight, x1 = -1, y1 = -1;  // bounding box, inclusive
};
ClothPixels cloth_pixels(const Image& image) {
  ClothPixels c;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (is_cloth(image.at(x, y))) {
        ++c.count;
        c.x0 = std::min(c.x0, x);
        c.x1 = std::max(c.x1, x);
        c.y0 = std::min(c.y0, y);
        c.y1 = std::max(c.y1, y);
      }
  return c;
}

// Screen area the camera should give the surface: the sum of its projected triangles (the flag
// starts flat, so they do not overlap).
double projected_area(const Camera& camera, const RenderTopology& t, std::span<const Vec3> x) {
  double area = 0;
  for (std::size_t f = 0; f + 2 < t.triangles.size(); f += 3) {
    const auto a = camera.project(x[t.triangles[f]], kWidth, kHeight);
    const auto b = camera.project(x[t.triangles[f + 1]], kWidth, kHeight);
    const auto c = camera.project(x[t.triangles[f + 2]], kWidth, kHeight);
    if (!a || !b || !c) continue;
    area += std::abs((b->x - a->x) * (c->y - a->y) - (c->x - a->x) * (b->y - a->y)) / 2;
  }
  return area;
}

Scene flag_scene() {
  auto scene = load_scene(MAILLE_SOURCE_DIR "/examples/flag_in_wind.toml");
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().to_string());
  return std::move(scene.value());
}

RenderOptions surface_only() {
  RenderOptions o;
  o.links = o.points = o.contacts = o.grid = false;
  return o;
}

TEST_F(HeadlessRender, FlagCoversItsProjectedAreaAndIsFramed) {
  const Scene scene = flag_scene();
  OffscreenTarget target(kWidth, kHeight, 1);  // no multisampling: exact coverage
  Renderer renderer;
  renderer.set_model(scene.model);
  Camera camera;
  camera.frame(bounds_of(renderer.positions()), double(kWidth) / kHeight);
  target.bind();
  renderer.draw(camera, kWidth, kHeight, surface_only());
  const Image image = target.read();
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);

  // Not blank: the corner is background grey, and there is cloth.
  const auto corner = image.at(0, 0);
  EXPECT_NEAR(corner.r, corner.b, 12);
  EXPECT_GT(corner.r, 100);
  const ClothPixels c = cloth_pixels(image);
  const double expected = projected_area(camera, renderer.topology(), renderer.positions());
  ASSERT_GT(expected, 0.05 * kWidth * kHeight) << "the camera should make the flag large";
  EXPECT_NEAR(c.count, expected, 0.05 * expected);

  // Framed: the flag's box is inside the image, and the points' projected box matches it.
  EXPECT_GT(c.x0, 0);
  EXPECT_GT(c.y0, 0);
  EXPECT_LT(c.x1, kWidth - 1);
  EXPECT_LT(c.y1, kHeight - 1);
  double px0 = 1e9, px1 = -1e9, py0 = 1e9, py1 = -1e9;
  for (std::uint32_t i : renderer.topology().triangles) {
    const auto p = camera.project(renderer.positions()[i], kWidth, kHeight);
    ASSERT_TRUE(p);
    px0 = std::min(px0, p->x), px1 = std::max(px1, p->x);
    py0 = std::min(py0, p->y), py1 = std::max(py1, p->y);
  }
  EXPECT_NEAR(c.x0, px0, 2);
  EXPECT_NEAR(c.x1 + 1, px1, 2);
  EXPECT_NEAR(c.y0, py0, 2);
  EXPECT_NEAR(c.y1 + 1, py1, 2);
}

TEST_F(HeadlessRender, FlagInWindStaysInViewThroughSnapshots) {
  const Scene scene = flag_scene();
  OffscreenTarget target(kWidth, kHeight, 4);
  Renderer renderer;
  renderer.set_model(scene.model);
  SimulationSettings settings = scene.settings;
  settings.threads = 1;
  Simulator sim(scene.model, settings);
  // The renderer gets positions only through the published snapshots, via the exchange.
  SnapshotExchange exchange;
  sim.on_publish([&](const Snapshot& s) { exchange.publish(s); });
  Camera camera;
  AutoFrame auto_frame;
  const int initial = [&] {
    auto_frame.update(camera, renderer.positions(), double(kWidth) / kHeight);
    target.bind();
    renderer.draw(camera, kWidth, kHeight, surface_only());
    return cloth_pixels(target.read()).count;
  }();
  ASSERT_GT(initial, 0);
  for (int frame = 0; frame < 4; ++frame) {
    sim.run_steps(800);  // 0.2 s
    sim.publish_now();
    bool fresh = false;
    const Snapshot* s = exchange.take(&fresh);
    ASSERT_TRUE(s && fresh);
    renderer.set_snapshot(*s);
    EXPECT_EQ(renderer.snapshot_info().step, sim.state().step);
    auto_frame.update(camera, renderer.positions(), double(kWidth) / kHeight);
    target.bind();
    renderer.draw(camera, kWidth, kHeight, RenderOptions{});
    const ClothPixels c = cloth_pixels(target.read());
    // The flag turns in the wind: it shows less of its face, never vanishes, stays in frame.
    EXPECT_GT(c.count, initial / 5) << "frame " << frame;
    EXPECT_LT(c.count, initial * 3 / 2) << "frame " << frame;
    EXPECT_GT(c.x0, 0);
    EXPECT_LT(c.x1, kWidth - 1);
    EXPECT_GT(c.y0, 0);
    EXPECT_LT(c.y1, kHeight - 1);
  }
}

// A stretched spring is drawn red, a compressed one blue; links coloured by strain.
// The model's points seen from the front (along -z), framed; links drawn wide, alone.
Camera facing(const Renderer& renderer) {
  Camera camera;
  camera.yaw = camera.pitch = 0;
  camera.frame(bounds_of(renderer.positions()), double(kWidth) / kHeight);
  return camera;
}
RenderOptions links_only() {
  RenderOptions o;
  o.grid = o.points = false;
  o.link_width = 6;
  return o;
}

TEST_F(HeadlessRender, LinksAreColouredByStrain) {
  for (const Real length : {Real(1.3), Real(0.7)}) {
    Model m;
    const auto a = m.points.add(PointKind::fixed, 1, {0, 0, 0});
    const auto b = m.points.add(PointKind::fixed, 1, {length, 0, 0});
    m.links.pool<SpringDamper>().add({a, b}, {100, 1, 0});
    OffscreenTarget target(kWidth, kHeight, 1);
    Renderer renderer;
    renderer.set_model(m);
    const Camera camera = facing(renderer);
    const RenderOptions o = links_only();
    target.bind();
    renderer.draw(camera, kWidth, kHeight, o);
    const Image image = target.read();
    int red = 0, blue = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const auto p = image.at(x, y);
        red += p.r > 200 && p.g < 60 && p.b < 60;
        blue += p.b > 200 && p.r < 60;
      }
    // A 6-pixel ribbon across most of the width.
    if (length > 1) {
      EXPECT_GT(red, 6 * kWidth / 2);
      EXPECT_EQ(blue, 0);
    } else {
      EXPECT_GT(blue, 6 * kWidth / 2);
      EXPECT_EQ(red, 0);
    }
  }
}

// --- Solids (obstacles): the snapshot's surfaces, placed, shaded, translucent ------------------

// A model with nothing drawn in the middle: two fixed points far in the corners, points hidden.
Model corners_model() {
  Model m;
  m.points.add(PointKind::fixed, 1, {-3, -3, -3});
  m.points.add(PointKind::fixed, 1, {3, 3, 3});
  return m;
}

RenderOptions solids_only() {
  RenderOptions o;
  o.surface = o.links = o.points = o.contacts = o.grid = false;
  return o;
}

// A sphere of radius 0.3 centred at (0.5, 0.2, 0): an icosphere scaled and moved by the
// instance's placement, reddish and half transparent.
Snapshot sphere_snapshot(const Model& m, std::shared_ptr<const TriMesh> mesh, float alpha) {
  Snapshot s;
  s.positions = m.points.initial_position;
  SurfaceInstance solid;
  solid.name = "obstacle:ball";
  solid.mesh = std::move(mesh);
  solid.direct = Mat3::identity() * Real(0.3);
  solid.translation = {0.5, 0.2, 0};
  solid.colour = {0.85f, 0.15f, 0.10f, alpha};
  s.surfaces.push_back(solid);
  return s;
}

Camera front_camera() {
  Camera c;
  c.yaw = c.pitch = 0;  // looking along -z, the light's key from the upper right
  c.distance = 4;
  return c;
}

Image draw_snapshot(Renderer& renderer, const Snapshot& s, const Camera& camera,
                    const RenderOptions& o) {
  OffscreenTarget target(kWidth, kHeight, 1);
  renderer.set_snapshot(s);
  target.bind();
  renderer.draw(camera, kWidth, kHeight, o);
  return target.read();
}

bool is_reddish(Image::Pixel p) {
  return int(p.r) - int(p.g) > 40;
}

// Conditional links are drawn (yellow) exactly while closer than their threshold: the GPU's
// compacting pass and indirect draw, against the CPU's active_contacts on the same positions.
// Three of four links are active at first; moving the points apart leaves one.
TEST_F(HeadlessRender, ActiveContactsAreDrawnAndOnlyThem) {
  Model m;
  std::vector<std::uint32_t> p;
  for (int k = 0; k < 8; ++k)
    p.push_back(m.points.add(PointKind::fixed, 1, {Real(k % 4), Real(k / 4) * Real(0.5), 0}));
  // Threshold 0.6: the vertical pairs (0.5 apart) are active, the long diagonal (3.04) is not.
  for (int k = 0; k < 3; ++k)
    m.links.pool<ConditionalSpringDamper>().add({p[std::size_t(k)], p[std::size_t(k) + 4]},
                                                {10, 0, Real(0.6), Real(0.6)});
  m.links.pool<ConditionalSpringDamper>().add({p[3], p[4]}, {10, 0, Real(0.6), Real(0.6)});
  Renderer renderer;
  renderer.set_model(m);
  const Camera camera = facing(renderer);
  const RenderOptions o = links_only();
  // Yellow pixels in each quarter of the picture's width (one per column of points).
  auto yellow_columns = [&](const std::vector<Vec3>& x) {
    Snapshot s;
    s.positions = x;
    renderer.set_snapshot(s);
    OffscreenTarget target(kWidth, kHeight, 1);
    target.bind();
    renderer.draw(camera, kWidth, kHeight, o);
    const Image image = target.read();
    std::array<int, 4> columns{};
    for (int y = 0; y < kHeight; ++y)
      for (int x0 = 0; x0 < kWidth; ++x0) {
        const auto px = image.at(x0, y);
        if (px.r > 200 && px.g > 170 && px.b < 80) ++columns[std::size_t(x0 * 4 / kWidth)];
      }
    return columns;
  };
  std::vector<Vec3> x = m.points.initial_position;
  const std::array<int, 4> before = yellow_columns(x);
  std::vector<std::uint32_t> active;
  active_contacts(renderer.topology(), x, active);
  ASSERT_EQ(active.size(), 6u);
  for (int c = 0; c < 3; ++c) EXPECT_GT(before[std::size_t(c)], 20) << "column " << c;
  EXPECT_EQ(before[3], 0) << "the diagonal link is beyond its threshold";
  // The first two columns' lower points move 0.2 m down: 0.7 apart, no longer in contact.
  x[0].y -= Real(0.2);
  x[1].y -= Real(0.2);
  const std::array<int, 4> after = yellow_columns(x);
  EXPECT_EQ(after[0], 0);
  EXPECT_EQ(after[1], 0);
  EXPECT_GT(after[2], 20);
  EXPECT_EQ(after[3], 0);
}

TEST_F(HeadlessRender, SolidIsPlacedShadedAndTranslucent) {
  const Model model = corners_model();
  const auto mesh = std::make_shared<const TriMesh>(icosphere(4));
  Renderer renderer;
  renderer.set_model(model);
  const Camera camera = front_camera();
  const Image half =
      draw_snapshot(renderer, sphere_snapshot(model, mesh, 0.5f), camera, solids_only());
  const Image opaque =
      draw_snapshot(renderer, sphere_snapshot(model, mesh, 1.0f), camera, solids_only());
  Snapshot bare = sphere_snapshot(model, mesh, 0.5f);
  bare.surfaces.clear();
  const Image background = draw_snapshot(renderer, bare, camera, solids_only());

  // Where the placement puts it: the tinted disc is centred on the projected centre and has
  // the projected radius (perspective: the silhouette's half-angle is asin(r / d)).
  const auto centre = camera.project({0.5, 0.2, 0}, kWidth, kHeight);
  ASSERT_TRUE(centre);
  const double d = std::hypot(0.5, 0.2, 4.0);
  const double radius_px = std::tan(std::asin(0.3 / d)) * (kHeight / 2.0) /
                           std::tan(camera.fov_y * std::numbers::pi / 360);
  int count = 0;
  double sx = 0, sy = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      if (is_reddish(half.at(x, y))) {
        ++count;
        sx += x + 0.5;
        sy += y + 0.5;
      }
  const double disc = std::numbers::pi * radius_px * radius_px;
  EXPECT_NEAR(count, disc, 0.05 * disc);
  ASSERT_GT(count, 0);
  EXPECT_NEAR(sx / count, centre->x, 1.0);
  EXPECT_NEAR(sy / count, centre->y, 1.0);

  // Blended: at the centre, half-transparent is neither the opaque colour nor the background,
  // and the background shows through (it is greyer than the opaque solid).
  const int cx = int(centre->x), cy = int(centre->y);
  const auto h = half.at(cx, cy), o = opaque.at(cx, cy), b = background.at(cx, cy);
  EXPECT_NEAR(b.r, b.b, 20) << "background grey";
  EXPECT_TRUE(is_reddish(o));
  EXPECT_GT(std::abs(int(h.g) - int(o.g)) + std::abs(int(h.b) - int(o.b)), 40);
  EXPECT_LT(int(h.r) - int(h.g), int(o.r) - int(o.g));
  EXPECT_GT(int(h.r) - int(h.g), int(b.r) - int(b.g) + 40);

  // Shaded: lit from the upper right, the upper-right side is brighter than the lower-left.
  const int off = int(radius_px * 0.6);
  const auto lit = opaque.at(cx + off, cy - off), dark = opaque.at(cx - off, cy + off);
  EXPECT_GT(int(lit.r), int(dark.r) + 30);

  // A snapshot without surfaces draws none, and leaves no mesh on the GPU.
  EXPECT_EQ(renderer.solid_meshes(), 0u);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) ASSERT_FALSE(is_reddish(background.at(x, y)));
}

// Meshes are uploaded once per pointer, however many instances and snapshots show them, and
// freed with the first snapshot that no longer holds them.
TEST_F(HeadlessRender, SolidMeshesAreUploadedOncePerPointer) {
  const Model model = corners_model();
  Renderer renderer;
  renderer.set_model(model);
  const auto ball = std::make_shared<const TriMesh>(icosphere(2));
  const auto box = std::make_shared<const TriMesh>(tessellate(shape_kind("cube"), 4));
  Snapshot s = sphere_snapshot(model, ball, 0.5f);
  s.surfaces.push_back(s.surfaces[0]);  // a second instance of the same mesh
  s.surfaces[1].translation = {-0.5, 0, 0};
  for (int i = 0; i < 3; ++i) renderer.set_snapshot(s);
  EXPECT_EQ(renderer.solid_meshes(), 1u);
  s.surfaces[1].mesh = box;
  renderer.set_snapshot(s);
  EXPECT_EQ(renderer.solid_meshes(), 2u);
  s.surfaces.erase(s.surfaces.begin());  // the ball's stage is gone
  renderer.set_snapshot(s);
  EXPECT_EQ(renderer.solid_meshes(), 1u);
  // Framing keeps the closed solids in view: the box's placed corners are inside the bounds.
  const Bounds b = renderer.bounds();
  EXPECT_LE(b.lo.x, -0.5 - 0.3 + 1e-9);
  renderer.set_model(model);  // a reload drops the old scene's solids
  EXPECT_EQ(renderer.solid_meshes(), 0u);
}

// A scene with obstacles through the real path (simulator -> snapshot -> exchange -> renderer,
// auto-framed): the ball shows its colour, blended, and is fully in view; without the
// snapshot's surfaces its pixels are background again.
TEST_F(HeadlessRender, SceneObstacleIsDrawnThroughSnapshots) {
  auto loaded = load_scene(MAILLE_SOURCE_DIR "/examples/cloth_on_sphere.toml");
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  const Scene& scene = loaded.value();
  SimulationSettings settings = scene.settings;
  settings.threads = 1;
  Simulator sim(scene.model, settings);
  SnapshotExchange exchange;
  sim.on_publish([&](const Snapshot& s) { exchange.publish(s); });
  sim.publish_now();
  const Snapshot* s = exchange.take();
  ASSERT_TRUE(s);
  ASSERT_EQ(s->surfaces.size(), 2u);  // the ball and the ground

  Renderer renderer;
  renderer.set_model(scene.model);
  renderer.set_snapshot(*s);
  Camera camera;
  AutoFrame frame;
  frame.update(camera, renderer.bounds(), double(kWidth) / kHeight);
  const Image with = draw_snapshot(renderer, *s, camera, RenderOptions{});
  Snapshot without = *s;
  without.surfaces.clear();
  const Image bare = draw_snapshot(renderer, without, camera, RenderOptions{});

  // The ball: centre (0, 0.2, 0), radius 0.3, in the geometric method's blue-grey.
  const auto* ball = &s->surfaces[0];
  if (ball->name != "obstacle:ball") ball = &s->surfaces[1];
  ASSERT_EQ(ball->name, "obstacle:ball");
  const auto c = camera.project(ball->translation, kWidth, kHeight);
  ASSERT_TRUE(c);
  for (const Vec3 edge : {Vec3{0.3, 0, 0}, Vec3{-0.3, 0, 0}, Vec3{0, 0.3, 0}, Vec3{0, -0.3, 0}}) {
    const auto e = camera.project(ball->translation + edge, kWidth, kHeight);
    ASSERT_TRUE(e);
    EXPECT_GT(e->x, 0);
    EXPECT_LT(e->x, kWidth);
    EXPECT_GT(e->y, 0);
    EXPECT_LT(e->y, kHeight);
  }
  const auto p = with.at(int(c->x), int(c->y)), q = bare.at(int(c->x), int(c->y));
  // The background is a little bluish toward the bottom (b - r up to ~15): the ball is far more.
  EXPECT_GT(int(p.b) - int(p.r), int(q.b) - int(q.r) + 20) << "the ball's blue tint";
  EXPECT_LT(std::abs(int(q.b) - int(q.r)), 20) << "no ball: background grey";
  // Translucent: the ground behind the ball's lower half shows through it (with an opaque
  // ball, removing the ground would change nothing there). Grid off: only the ground differs.
  RenderOptions no_grid;
  no_grid.grid = false;
  Snapshot ball_only = *s;
  std::erase_if(ball_only.surfaces,
                [](const SurfaceInstance& x) { return x.name != "obstacle:ball"; });
  const Image both = draw_snapshot(renderer, *s, camera, no_grid);
  const Image alone = draw_snapshot(renderer, ball_only, camera, no_grid);
  const auto top = camera.project(ball->translation + Vec3{0, 0.3, 0}, kWidth, kHeight);
  ASSERT_TRUE(top);
  const int y = int(c->y + 0.6 * (c->y - top->y));
  const auto u = both.at(int(c->x), y), v = alone.at(int(c->x), y);
  EXPECT_GT(
      std::abs(int(u.r) - int(v.r)) + std::abs(int(u.g) - int(v.g)) + std::abs(int(u.b) - int(v.b)),
      10);
  EXPECT_GT(int(v.b) - int(v.r), 20) << "still the ball's tint";
}

// `maille render`'s driver carries the snapshots' solids to the picture: the ball and the
// ground change a good part of the frame, and nothing else does.
class KeepFrames final : public FrameSink {
 public:
  void write(const Image& frame) override { frames.push_back(frame); }
  void finish() override {}
  std::string describe() const override { return "memory"; }
  std::vector<Image> frames;
};

TEST(RenderMovie, DrawsTheScenesObstacles) {
  auto loaded = load_scene(MAILLE_SOURCE_DIR "/examples/cloth_on_sphere.toml");
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  MovieSettings m;
  m.width = 160;
  m.height = 100;
  m.samples = 1;
  m.duration = 0.01;  // the first frame only: the cloth still flat above the ball
  m.threads = 1;
  KeepFrames with, without;
  render_movie(loaded.value(), m, with);
  m.options.solids = false;
  render_movie(loaded.value(), m, without);
  ASSERT_EQ(with.frames.size(), 1u);
  ASSERT_EQ(without.frames.size(), 1u);
  const Image &a = with.frames[0], &b = without.frames[0];
  int changed = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const auto p = a.at(x, y), q = b.at(x, y);
      changed += std::abs(int(p.r) - int(q.r)) + std::abs(int(p.b) - int(q.b)) > 20;
    }
  EXPECT_GT(changed, a.width * a.height / 10);
}

TEST(RenderTopology, SolidNormalsAreSmoothOnSpheresAndSharpOnCubes) {
  // An icosphere: every corner's normal is close to its radial direction.
  const TriMesh sphere = icosphere(3);
  const std::vector<float> v = solid_vertices(sphere);
  ASSERT_EQ(v.size(), sphere.triangles.size() * 18);
  double worst = 1;
  for (std::size_t i = 0; i < v.size(); i += 6) {
    const Vec3 p{v[i], v[i + 1], v[i + 2]}, n{v[i + 3], v[i + 4], v[i + 5]};
    worst = std::min(worst, double(dot(p / norm(p), n)));
  }
  EXPECT_GT(worst, 0.999);
  // A cube: every corner's normal is its face's (the edges stay sharp), pointing out.
  const TriMesh cube = tessellate(shape_kind("cube"), 8);
  const std::vector<float> w = solid_vertices(cube);
  for (std::size_t f = 0; f < cube.triangles.size(); ++f) {
    const auto& t = cube.triangles[f];
    Vec3 face =
        cross(cube.vertices[t[1]] - cube.vertices[t[0]], cube.vertices[t[2]] - cube.vertices[t[0]]);
    face = face / norm(face);
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = (3 * f + std::size_t(k)) * 6;
      EXPECT_GT(dot(face, Vec3{w[i + 3], w[i + 4], w[i + 5]}), 0.9999) << "face " << f;
    }
  }
}

TEST(RenderTopology, RestLengthsContactsAndPointStyles) {
  Model m;
  const auto a = m.points.add(PointKind::fixed, 1, {0, 0, 0});
  const auto b = m.points.add(PointKind::free, 1, {2, 0, 0});
  const auto c = m.points.add(PointKind::driven, 1, {2, 1, 0});
  m.links.pool<SpringDamper>().add({a, b}, {10, Real(1.5), 0});  // rest length parameter
  m.links.pool<Damper>().add({b, c}, {1});                       // none: initial distance
  m.links.pool<ConditionalSpringDamper>().add({a, c}, {10, 0, Real(3), Real(3)});
  const RenderTopology t = make_topology(m);
  ASSERT_EQ(t.link_rest.size(), 2u);
  EXPECT_FLOAT_EQ(t.link_rest[0], 1.5f);
  EXPECT_FLOAT_EQ(t.link_rest[1], 1.0f);
  ASSERT_EQ(t.contact_threshold.size(), 1u);
  EXPECT_FLOAT_EQ(t.contact_threshold[0], 3.0f);
  EXPECT_EQ(t.point_style[a], std::uint32_t(PointStyle::fixed));
  EXPECT_EQ(t.point_style[b], std::uint32_t(PointStyle::free));
  EXPECT_EQ(t.point_style[c], std::uint32_t(PointStyle::driven));
  std::vector<std::uint32_t> active;
  active_contacts(t, m.points.initial_position, active);  // |ac| = sqrt(5) < 3
  EXPECT_EQ(active, (std::vector<std::uint32_t>{a, c}));
}

// A full disk (/dev/full behind the temporary's name): an error naming the cause, no
// temporary left, and the PNG already there kept (stb's own writer ignored fwrite errors).
TEST(WritePng, FullDiskIsAnErrorAndKeepsThePreviousFile) {
  const auto dir = std::filesystem::temp_directory_path() / "maille_test_png_full";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto file = dir / "still.png";
  { std::ofstream(file) << "previous"; }
  std::filesystem::create_symlink("/dev/full", dir / "still.png.tmp");
  Image image;
  image.width = 64;
  image.height = 48;
  image.rgb.assign(64 * 48 * 3, 200);
  try {
    write_png(image, file);
    FAIL() << "write_png succeeded on a full disk";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  std::ifstream in(file);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "previous");
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(dir / "still.png.tmp")));
  write_png(image, dir / "ok.png");  // and a good write still works
  EXPECT_GT(std::filesystem::file_size(dir / "ok.png"), 8u);
}

TEST(RenderCamera, ProjectAndRayAgree) {
  Camera camera;
  camera.target = {1, 2, 3};
  camera.distance = 4;
  camera.yaw = 40;
  camera.pitch = 25;
  const Vec3 p{1.5, 2.2, 2.6};
  const auto px = camera.project(p, 640, 480);
  ASSERT_TRUE(px);
  const Ray r = camera.ray(px->x, px->y, 640, 480);
  const Vec3 to_p = p - r.origin;
  // p lies on the ray through its own pixel.
  EXPECT_LT(norm(cross(to_p, r.direction)), 1e-9);
  EXPECT_NEAR(camera.project(camera.target, 640, 480)->x, 320, 1e-9);
  EXPECT_NEAR(camera.project(camera.target, 640, 480)->y, 240, 1e-9);
}

// --- smooth surfaces ----------------------------------------------------------------------------

// The cloth of `name` after `steps` steps, as a snapshot.
Snapshot curved_snapshot(const char* name, std::uint64_t steps, Scene& scene) {
  Snapshot s;
  s.positions = test::run_example(name, steps, scene);
  return s;
}

// The compute shader evaluates the same math as the CPU (smooth_math.glsl, compiled twice): the
// vertices it writes agree with SmoothSurface::evaluate to float rounding. Both evaluate in
// float with the same operations; a GPU may contract or reorder them, so allow 1e-5 of the
// cloth's size on positions (a few hundred float ulps) and 1e-4 on unit normals.
TEST_F(HeadlessRender, SmoothSurfaceOnTheGpuMatchesTheCpu) {
  for (const char* name : {"flag_in_wind", "drum_membrane"}) {
    Scene scene;
    const Snapshot s = curved_snapshot(name, 1500, scene);
    OffscreenTarget target(kWidth, kHeight, 1);
    Renderer renderer;
    renderer.set_model(scene.model);
    renderer.set_snapshot(s);
    Camera camera;
    camera.frame(bounds_of(renderer.positions()), double(kWidth) / kHeight);
    RenderOptions o = surface_only();
    o.smooth = true;
    o.smooth_lod = 3;
    target.bind();
    renderer.draw(camera, kWidth, kHeight, o);
    const std::vector<float> gpu = renderer.smooth_vertices();
    SmoothMesh cpu;
    renderer.smooth_surface().evaluate(s.positions, 3, cpu);
    ASSERT_EQ(gpu.size(), cpu.vertices.size()) << name;
    const double size = bounds_of(renderer.positions()).diagonal();
    double worst_position = 0, worst_normal = 0;
    for (std::size_t k = 0; k < gpu.size(); ++k) {
      const double e = std::abs(double(gpu[k]) - double(cpu.vertices[k]));
      if (k % 6 < 3)
        worst_position = std::max(worst_position, e / size);
      else
        worst_normal = std::max(worst_normal, e);
    }
    EXPECT_LT(worst_position, 1e-5) << name;
    EXPECT_LT(worst_normal, 1e-4) << name;
  }
}

// Smoothing rounds the cloth between particles; it must not change what it covers much: the
// silhouette of a waving flag drawn smooth covers the flat drawing's area within 3 % (the
// patches bulge by a fraction of a cell's sag, the extrapolated border by less).
TEST_F(HeadlessRender, SmoothSilhouetteKeepsTheFlatArea) {
  Scene scene;
  const Snapshot s = curved_snapshot("flag_in_wind", 3000, scene);
  OffscreenTarget target(kWidth, kHeight, 1);
  Renderer renderer;
  renderer.set_model(scene.model);
  renderer.set_snapshot(s);
  Camera camera;
  camera.yaw = 0, camera.pitch = 10;  // facing the flag's plane (x, y)
  camera.frame(bounds_of(renderer.positions()), double(kWidth) / kHeight);
  RenderOptions o = surface_only();
  target.bind();
  renderer.draw(camera, kWidth, kHeight, o);
  const int flat = cloth_pixels(target.read()).count;
  o.smooth = true;
  o.smooth_lod = 6;
  target.bind();
  renderer.draw(camera, kWidth, kHeight, o);
  const int smooth = cloth_pixels(target.read()).count;
  ASSERT_GT(flat, kWidth * kHeight / 20);
  EXPECT_NEAR(smooth, flat, 0.03 * flat);
}

}  // namespace
}  // namespace maille::render
