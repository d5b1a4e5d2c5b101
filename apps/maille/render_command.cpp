// `maille render`: a scene's run drawn into frames, a movie or stills (docs/rendering.md).
#include "commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <unistd.h>

#include "command_support.hpp"
#include "maille/clock.hpp"
#include "maille/interrupt.hpp"
#include "maille/io.hpp"
#include "maille/limits.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#ifdef MAILLE_WITH_RENDER
#include <cstdlib>
#include <memory>

#include "maille/render/movie.hpp"
#endif

namespace maille::app {

#ifdef MAILLE_WITH_RENDER
namespace {

// A one-line progress bar on stderr, redrawn in place, only when stderr is a terminal (logs and
// tests get the summary line alone).
class ProgressBar {
 public:
  ProgressBar() : tty_(isatty(STDERR_FILENO) == 1), t0_(WallClock::now()) {}
  ~ProgressBar() {
    if (drawn_) std::fputc('\n', stderr);
  }
  void update(std::uint64_t done, std::uint64_t total) {
    if (!tty_ || total == 0) return;
    const double elapsed = seconds_since(t0_);
    if (done < total && elapsed - last_ < 0.1) return;  // at most 10 redraws per second
    last_ = elapsed;
    constexpr int kWidth = 30;
    const double f = double(done) / double(total);
    const int filled = static_cast<int>(f * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '=');
    if (filled < kWidth)
      bar += '>' + std::string(static_cast<std::size_t>(kWidth - filled - 1), ' ');
    const double left = done > 0 ? elapsed * double(total - done) / double(done) : 0;
    std::fprintf(stderr, "\r[%s] %3d%% frame %llu/%llu, %.0f s left ", bar.c_str(),
                 static_cast<int>(f * 100), static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(total), left);
    std::fflush(stderr);
    drawn_ = true;
  }

 private:
  bool tty_;
  bool drawn_ = false;
  WallClock::time_point t0_;
  double last_ = -1;
};

// "yaw,pitch[,zoom]" in degrees, degrees and a distance factor.
std::string camera_text(const std::vector<double>& v) {
  std::ostringstream s;
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str();
}

// yaw, pitch[, zoom] as CLI11 split them (2 or 3 values: it refuses others).
bool set_camera(const std::vector<double>& v, render::MovieSettings& m) {
  if (v.size() < 2 || v.size() > 3) return false;
  const double zoom = v.size() == 3 ? v[2] : m.zoom;
  // Finite angles, a pitch that keeps the up vector defined, a zoom that frames something.
  if (!std::isfinite(v[0]) || !(std::abs(v[0]) <= 3600) || !(std::abs(v[1]) <= 89) ||
      !(zoom > 0.001 && zoom <= 1000))
    return false;
  m.yaw = v[0];
  m.pitch = v[1];
  m.zoom = zoom;
  return true;
}

}  // namespace

int render(const RenderCommandOptions& o) {
  interrupt::at_once(kLoadingInterrupted);
  auto scene = load_or_report(o.scene, o.sets);
  if (!scene) return bad_input;
  interrupt::counted();  // the movie's loop polls them (its simulator is built inside it)
  if (o.no_self_collision) scene->settings.disabled_stages.push_back("self_collision");
  if (!o.backend.empty()) scene->settings.backend = o.backend;
  if (o.gpu_device) scene->settings.backend_options.device = *o.gpu_device;
  render::MovieSettings m;
  for (const auto& text : o.stage_options) {
    const auto dot = text.find('.'), eq = text.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
      std::cerr << "--stage-option: expected STAGE.OPTION=VALUE, got '" << text << "'\n";
      return usage;
    }
    m.stage_options.push_back(
        {text.substr(0, dot), text.substr(dot + 1, eq - dot - 1), text.substr(eq + 1)});
  }
  m.width = o.width;
  m.height = o.height;
  m.fps = o.fps;
  m.duration = o.duration ? *o.duration : scene->settings.duration;
  m.samples = o.samples;
  m.options.links_on_surface = o.mesh;
  m.options.smooth = o.smooth;
  m.options.smooth_lod = o.lod;
  if (o.threads) m.threads = *o.threads;
  if (!set_camera(o.camera, m)) {
    std::cerr << "--camera: expected yaw,pitch[,zoom] (yaw within +-3600 degrees, pitch within "
                 "+-89 degrees, zoom in (0.001, 1000]), got '"
              << camera_text(o.camera) << "'\n";
    return usage;
  }
  const std::filesystem::path out(o.out);
  const std::string ext = out.extension().string();
  // Usage errors before anything is opened: the frame count and the video's even size.
  if (!steps_for(m.duration, scene->settings.step, "the duration")) return usage;
  if (const double frames = std::floor(m.duration * m.fps) + 1; frames > 1e7) {
    std::cerr << "error: " << m.duration << " s at " << m.fps << " frames per second is " << frames
              << " frames, more than the limit of 1e7\n";
    return usage;
  }
  if (ext == ".mp4" && (m.width % 2 || m.height % 2)) {
    std::cerr << "error: an MP4 video needs an even width and height (got " << m.width << "x"
              << m.height << ")\n";
    return usage;
  }
  try {
    std::unique_ptr<render::FrameSink> sink;
    if (ext == ".mp4") {
      if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
      sink = render::ffmpeg_video(out, m.width, m.height, m.fps);
    } else if (ext == ".png") {
      if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
      sink = render::png_still(out);
      m.last_frame_only = true;
    } else {
      sink = render::png_sequence(out);
    }
    // Ctrl-C inside a long implicit step abandons it (render_movie's stop request).
    m.stop_requested = [] { return interrupt::received() > 0; };
    const auto t0 = WallClock::now();
    render::MovieReport r;
    {
      ProgressBar bar;
      r = render::render_movie(*scene, m, *sink, [&](std::uint64_t done, std::uint64_t total) {
        bar.update(done, total);
        return interrupt::received() == 0;
      });
    }
    const double wall = seconds_since(t0);
    const double per_frame = r.frames ? 1e3 / double(r.frames) : 0.0;
    std::printf(
        "maille: render %s: %llu frames %dx%d (%.4g s simulated) in %.3g s wall: %.3g ms per "
        "frame drawing and reading back, %.3g ms writing, simulation %.3g s; %s\n",
        scene->name.c_str(), static_cast<unsigned long long>(r.frames), m.width, m.height,
        r.simulated, wall, r.render_seconds * per_frame, r.output_seconds * per_frame,
        r.simulate_seconds, sink->describe().c_str());
    std::printf("maille: OpenGL: %s\n", r.gl.c_str());
    if (r.blow_up) {
      std::cerr << "error: " << *r.blow_up << '\n';
      return blow_up;
    }
    if (r.interrupted) {
      std::cerr << "interrupted; the frames written so far are complete\n";
      return interrupted;
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "error: " << e.what() << '\n';
    return usage;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return output_error;
  }
  return ok;
}
#endif

}  // namespace maille::app
