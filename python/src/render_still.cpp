// A still of one snapshot, headless, like the last frame of `maille render --out still.png`:
// an EGL surfaceless context, the renderer, the camera framed on the points (AutoFrame), a PNG
// written whole or not at all.
#include "bindings.hpp"
#ifdef MAILLE_WITH_RENDER
#include "maille/render/camera.hpp"
#include "maille/render/frame_sink.hpp"
#include "maille/render/headless.hpp"
#include "maille/render/renderer.hpp"
#endif

namespace maille::python {

#ifdef MAILLE_WITH_RENDER

bool render_available() {
  return true;
}

void render_still(const Model& model, const Snapshot& snapshot, const std::filesystem::path& file,
                  const StillOptions& o) {
  render::HeadlessContext context;
  render::OffscreenTarget target(o.width, o.height, o.samples);
  render::Renderer renderer;
  renderer.set_model(model);
  renderer.set_snapshot(snapshot);
  renderer.set_overlay(snapshot.overlay);
  renderer.wait_for_bounds();
  const double aspect = double(o.width) / o.height;
  render::Camera camera;
  camera.yaw = o.yaw;
  camera.pitch = o.pitch;
  render::AutoFrame frame;
  frame.update(camera, renderer.bounds(), aspect);
  camera.frame(frame.box(), aspect);
  camera.zoom(o.zoom);
  render::RenderOptions options;
  options.links_on_surface = o.mesh;
  target.bind();
  renderer.draw(camera, o.width, o.height, options);
  const render::Image image = target.read();
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  const auto sink = render::png_still(file);
  sink->write(image);
  sink->finish();
}

#else

bool render_available() {
  return false;
}

void render_still(const Model&, const Snapshot&, const std::filesystem::path&,
                  const StillOptions&) {
  throw std::runtime_error("this maille module was built without rendering");
}

#endif

}  // namespace maille::python
