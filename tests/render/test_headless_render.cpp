// The renderer, headless (EGL surfaceless, Mesa's llvmpipe): what comes out is checked pixel by
// pixel against what the camera should show.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "maille/links/conditional.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/render/headless.hpp"
#include "maille/render/image.hpp"
#include "maille/render/renderer.hpp"
#include "maille/render/snapshot_exchange.hpp"
#include "maille/scene.hpp"

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
TEST_F(HeadlessRender, LinksAreColouredByStrain) {
  for (const Real length : {Real(1.3), Real(0.7)}) {
    Model m;
    const auto a = m.points.add(PointKind::fixed, 1, {0, 0, 0});
    const auto b = m.points.add(PointKind::fixed, 1, {length, 0, 0});
    m.links.pool<SpringDamper>().add({a, b}, {100, 1, 0});
    OffscreenTarget target(kWidth, kHeight, 1);
    Renderer renderer;
    renderer.set_model(m);
    Camera camera;
    camera.yaw = camera.pitch = 0;
    camera.frame(bounds_of(renderer.positions()), double(kWidth) / kHeight);
    RenderOptions o;
    o.grid = o.points = false;
    o.link_width = 6;
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

}  // namespace
}  // namespace maille::render
