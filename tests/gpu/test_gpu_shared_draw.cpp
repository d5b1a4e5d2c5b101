// Drawing straight from the GPU backend's buffers (the renderer draws from the GPU's position
// buffer, nothing read back): device snapshots leave the positions on the device, the snapshot
// exchange hands them from a physics thread's context to a drawing one in the same share group
// with fences, and the renderer draws, lights (normals) and frames (bounds) them without reading
// them back. Checked against the host path on the same positions: the same floats, the same
// normals, the same box, the same pixels.
#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <thread>

#include "gpu/gpu_test_support.hpp"
#include "maille/render/camera.hpp"
#include "maille/render/gl_transfer.hpp"
#include "maille/render/headless.hpp"
#include "maille/render/renderer.hpp"
#include "maille/render/snapshot_exchange.hpp"
#include "maille/render/topology.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

using SharedDraw = test::GpuTest;

SimulationSettings gpu_settings(const Scene& scene, bool current_context) {
  SimulationSettings settings = scene.settings;
  settings.backend = "gpu";
  settings.threads = 1;
  settings.publish_every = 10;
  settings.backend_options.use_current_context = current_context;
  return settings;
}

std::vector<float> read_buffer(std::uint32_t buffer, std::size_t points) {
  std::vector<float> out(points * 3);
  glGetNamedBufferSubData(buffer, 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
  return out;
}

// The host state's positions as the GPU stores them (float), and back as Vec3.
std::vector<Vec3> as_float(std::span<const Vec3> x) {
  std::vector<Vec3> out;
  for (const Vec3& p : x) out.push_back({Real(float(p.x)), Real(float(p.y)), Real(float(p.z))});
  return out;
}

void expect_floats_equal(const std::vector<float>& device, std::span<const Vec3> host) {
  ASSERT_EQ(device.size(), host.size() * 3);
  for (std::size_t i = 0; i < host.size(); ++i)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(device[3 * i + std::size_t(k)], float(host[i][k])) << "point " << i;
}

render::Image draw(render::Renderer& r, const render::Camera& camera) {
  render::OffscreenTarget target(160, 120, 1);
  target.bind();
  render::RenderOptions o;
  o.grid = false;  // the grid's height follows bounds read a frame late on the device path
  r.draw(camera, 160, 120, o);
  return target.read();
}

// On the renderer's own thread and context (as `maille render` shares it): snapshots carry the
// backend's buffer, not positions, and that buffer holds the state's positions exactly.
TEST_F(SharedDraw, DeviceSnapshotsLeaveThePositionsOnTheDevice) {
  render::HeadlessContext context;
  const Scene scene = test::example_scene("flag_in_wind");
  Simulator sim(scene.model, gpu_settings(scene, true));
  sim.set_device_snapshots(true);
  Snapshot last;
  std::vector<float> published;
  sim.on_publish([&](const Snapshot& s) {
    last = s;
    if (s.device.gl_buffer) published = read_buffer(s.device.gl_buffer, s.device.count);
  });
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(sim.step());
  EXPECT_TRUE(last.positions.empty()) << "positions were downloaded to publish";
  ASSERT_NE(last.device.gl_buffer, 0u);
  EXPECT_EQ(last.device.count, scene.model.points.size());
  EXPECT_EQ(last.point_count(), scene.model.points.size());
  EXPECT_EQ(last.step, 30u);
  expect_floats_equal(published, sim.state().x());  // state() downloads: the same floats

  // Host-side changes are not on the device yet: the next snapshot carries host positions.
  sim.reset();
  sim.publish_now();
  EXPECT_EQ(last.device.gl_buffer, 0u);
  EXPECT_EQ(last.positions.size(), scene.model.points.size());
}

// A backend in a context of its own has no buffer to share: host positions, as before.
TEST_F(SharedDraw, OwnContextPublishesHostPositions) {
  const Scene scene = test::example_scene("flag_in_wind");
  Simulator own(scene.model, gpu_settings(scene, false));
  own.set_device_snapshots(true);
  Snapshot mine;
  own.on_publish([&](const Snapshot& s) { mine = s; });
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(own.step());
  EXPECT_EQ(mine.device.gl_buffer, 0u);
  EXPECT_EQ(mine.positions.size(), scene.model.points.size());
}

// A physics thread steps in a context shared with the drawing one and publishes device
// snapshots into the exchange while the drawing thread takes and draws them. At the end the
// drawn buffer holds the final state, and the picture, the normals and the box are the ones the
// host path gives for the same positions.
TEST_F(SharedDraw, ExchangeHandsDevicePositionsToAnotherContext) {
  render::HeadlessContext drawing;
  render::HeadlessContext physics(-1, &drawing);
  physics.release();
  drawing.make_current();

  const Scene scene = test::example_scene("flag_in_wind");
  const std::size_t n = scene.model.points.size();
  render::SnapshotExchange exchange(render::make_gl_transfer());
  std::atomic<bool> done{false};
  std::vector<Vec3> final_x;
  std::string failure;
  std::thread worker([&] {
    try {
      physics.make_current();
      Simulator sim(scene.model, gpu_settings(scene, true));
      sim.set_device_snapshots(true);
      sim.on_publish([&](const Snapshot& s) { exchange.publish(s); });
      for (int i = 0; i < 400; ++i)
        if (!sim.step()) throw std::runtime_error("the run stopped");
      const auto x = sim.state().x();
      final_x.assign(x.begin(), x.end());
    } catch (const std::exception& e) {
      failure = e.what();
    }
    physics.release();
    done = true;
  });

  render::Renderer renderer;
  renderer.set_model(scene.model);
  render::Camera camera;
  camera.frame(render::bounds_of(scene.model.points.initial_position), 160.0 / 120);
  int drawn = 0;
  while (!done) {  // draws while the physics runs: fences order the two contexts
    bool fresh = false;
    if (const Snapshot* s = exchange.take(&fresh); s && fresh) {
      ASSERT_TRUE(s->positions.empty());
      renderer.set_snapshot(*s);
      draw(renderer, camera);
      ++drawn;
    }
  }
  worker.join();
  ASSERT_TRUE(failure.empty()) << failure;
  const Snapshot* s = exchange.take();
  ASSERT_NE(s, nullptr);
  ASSERT_NE(s->device.gl_buffer, 0u);
  EXPECT_EQ(s->step, 400u);
  renderer.set_snapshot(*s);
  expect_floats_equal(read_buffer(s->device.gl_buffer, n), final_x);
  EXPECT_TRUE(renderer.draws_device_positions());
  EXPECT_GT(drawn, 0);

  // The box, once the reduction is in (a draw polls it): that of the float positions, exactly.
  const render::Image device_image = draw(renderer, camera);
  glFinish();
  draw(renderer, camera);
  const render::Bounds expected = render::bounds_of(as_float(final_x));
  const render::Bounds box = renderer.bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(box.lo[k], expected.lo[k]);
    EXPECT_EQ(box.hi[k], expected.hi[k]);
  }
  // Normals: the CPU's area-weighted normals within float rounding of unit vectors built from
  // O(1) sums (a few ulps: 1e-5 leaves a margin of about 10).
  std::vector<float> cpu_normals;
  surface_normals(renderer.topology(), as_float(final_x), cpu_normals);
  const std::vector<float> gpu_normals = renderer.normals();
  ASSERT_EQ(gpu_normals.size(), cpu_normals.size());
  for (std::size_t i = 0; i < cpu_normals.size(); ++i)
    ASSERT_NEAR(gpu_normals[i], cpu_normals[i], 1e-5) << "component " << i;

  // The same positions through the host path: the same pixels (the same floats reach the same
  // shaders, normals from the same pass).
  Snapshot host;
  host.positions = as_float(final_x);
  renderer.set_snapshot(host);
  EXPECT_FALSE(renderer.draws_device_positions());
  const render::Image host_image = draw(renderer, camera);
  ASSERT_EQ(host_image.rgb.size(), device_image.rgb.size());
  EXPECT_EQ(std::memcmp(host_image.rgb.data(), device_image.rgb.data(), host_image.rgb.size()), 0);
}

}  // namespace
}  // namespace maille
