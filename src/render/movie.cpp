#include "maille/render/movie.hpp"

#include <cmath>
#include <stdexcept>

#include "maille/clock.hpp"
#include "maille/render/headless.hpp"
#include "maille/simulator.hpp"

namespace maille::render {

MovieReport render_movie(const Scene& scene, const MovieSettings& s, FrameSink& sink,
                         const std::function<bool(std::uint64_t, std::uint64_t)>& progress) {
  if (s.width <= 0 || s.height <= 0 || !(s.fps > 0) || !(s.zoom > 0))
    throw std::invalid_argument("render: width, height, fps and zoom must be > 0");
  SimulationSettings settings = scene.settings;
  settings.publish_every = kNeverEvery;  // frames are published explicitly, at frame times
  if (s.threads > 0) settings.threads = s.threads;
  const double duration = s.duration > 0 ? s.duration : settings.duration;

  MovieReport report;
  HeadlessContext context;
  report.gl = context.description();
  OffscreenTarget target(s.width, s.height, s.samples);
  Renderer renderer;
  renderer.set_model(scene.model);

  Simulator sim(scene.model, settings);
  for (const auto& [stage, option, value] : s.stage_options)
    sim.set_stage_option(stage, option, value);  // std::invalid_argument names what is unknown
  sim.set_overlays(!s.stage_options.empty());
  // A GPU backend runs in this context: frames are drawn from its position buffer, only the
  // pixels written come back (overlays read the host state, so they need the positions there).
  sim.set_device_snapshots(s.stage_options.empty());
  // The only path from the physics to the renderer: a published snapshot.
  sim.on_publish([&](const Snapshot& snapshot) {
    renderer.set_snapshot(snapshot);
    renderer.set_overlay(snapshot.overlay);
  });

  // A stop asked for inside a step that lasts minutes (an implicit solver at accepted keys)
  // abandons it: the state of the last whole step stays.
  if (s.stop_requested) sim.on_stop_request(s.stop_requested);

  const double aspect = double(s.width) / s.height;
  Camera framed;
  framed.yaw = s.yaw;
  framed.pitch = s.pitch;
  AutoFrame auto_frame;
  const auto total = static_cast<std::uint64_t>(std::floor(duration * s.fps + 1e-9)) + 1;
  const std::uint64_t first_rendered = s.last_frame_only ? total - 1 : 0;
  for (std::uint64_t k = 0; k < total; ++k) {
    // Frame k shows the state at the step nearest to k / fps.
    const auto step = static_cast<std::uint64_t>(std::llround(double(k) / s.fps / settings.step));
    auto t0 = WallClock::now();
    while (sim.steps_taken() < step) {
      if (!sim.step()) {
        if (sim.blow_up())
          report.blow_up = sim.blow_up()->message;
        else
          report.interrupted = true;  // a stop request abandoned the step
        break;
      }
      if (s.stop_requested && s.stop_requested()) {
        report.interrupted = true;
        break;
      }
    }
    report.simulate_seconds += seconds_since(t0);
    if (report.blow_up || report.interrupted) break;
    sim.publish_now();
    renderer.wait_for_bounds();
    auto_frame.update(framed, renderer.bounds(), aspect);
    // A still has no motion to smooth: frame everything seen so far at once.
    if (s.last_frame_only && k == first_rendered) framed.frame(auto_frame.box(), aspect);
    if (k >= first_rendered) {
      t0 = WallClock::now();
      Camera camera = framed;
      camera.zoom(s.zoom);
      target.bind();
      renderer.draw(camera, s.width, s.height, s.options);
      const Image image = target.read();
      report.render_seconds += seconds_since(t0);
      t0 = WallClock::now();
      sink.write(image);
      report.output_seconds += seconds_since(t0);
      ++report.frames;
    }
    if (progress && !progress(k + 1, total)) {
      report.interrupted = true;
      break;
    }
  }
  report.steps = sim.steps_taken();
  report.simulated = sim.time();
  const auto t0 = WallClock::now();
  if (report.frames > 0) sink.finish();
  report.output_seconds += seconds_since(t0);
  return report;
}

}  // namespace maille::render
