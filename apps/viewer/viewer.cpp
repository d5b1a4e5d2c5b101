#include "viewer.hpp"

// libepoxy first: it declares OpenGL itself and GLFW must not include the system GL header.
#include <epoxy/gl.h>
// clang-format off
#include <GLFW/glfw3.h>
// clang-format on
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <memory>

#include "maille/render/gl_transfer.hpp"
#include "maille/render/headless.hpp"
#include "maille/render/image.hpp"
#include "maille/render/renderer.hpp"
#include "maille/scene.hpp"
#include "panels.hpp"
#include "physics_thread.hpp"
#include "scene_files.hpp"
#include "sound.hpp"

namespace maille::viewer {

namespace {

using Clock = std::chrono::steady_clock;

std::filesystem::path timestamped_png() {
  char name[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(name, sizeof name, "maille-%Y%m%d-%H%M%S.png", std::localtime(&now));
  return name;
}

class Viewer {
 public:
  // `physics_context`: a hidden window sharing `window`'s objects, for the physics thread (a GPU
  // backend's positions are then drawn without a copy); nullptr: none could be made.
  Viewer(GLFWwindow* window, GLFWwindow* physics_context, const ViewerOptions& o)
      : window_(window),
        physics_context_(physics_context),
        options_(o),
        examples_(list_scenes(o.examples)) {
    options_render_.smooth = o.smooth;
    options_render_.smooth_lod = o.lod;
  }

  bool open(const std::filesystem::path& path) {
    Result<Scene> loaded = load_scene(path);
    if (!loaded) {
      load_error_ = loaded.error().to_string();
      return false;
    }
    try {
      // Sound stops before the physics that plays it goes, and starts again on the new scene.
      const bool sound_was_on = sound_.on();
      sound_.stop();
      // The old physics stops before its exchange goes: it publishes into it until joined.
      physics_.reset();
      exchange_ = std::make_unique<render::SnapshotExchange>(
          physics_context_ ? render::make_gl_transfer() : nullptr);
      scene_ = std::move(loaded.value());
      if (!options_.backend.empty()) scene_.settings.backend = options_.backend;
      physics_ = std::make_unique<PhysicsThread>(scene_.model, scene_.settings, *exchange_,
                                                 !options_.paused, shared_context());
      if (sound_was_on) sound_.start(scene_, *physics_);
    } catch (const std::exception& e) {
      load_error_ = path.string() + ": " + e.what();
      return false;
    }
    load_error_.clear();
    renderer_.set_model(scene_.model);
    tuning_ = Tuning::from(scene_);
    auto_frame_.reset();
    tuning_.auto_frame = true;
    grabbed_.reset();
    watch_ = FileWatch(path);
    return true;
  }

  // One frame: input, panels, drawing. Returns false when the window should close.
  bool frame(bool screenshot_now, const std::filesystem::path& screenshot_file) {
    glfwPollEvents();
    if (glfwWindowShouldClose(window_)) return false;
    if (watch_.changed()) open(watch_.file());

    bool fresh = false;
    if (const Snapshot* s = exchange_->take(&fresh);
        s && fresh && s->point_count() == renderer_.positions().size()) {
      renderer_.set_snapshot(*s);
      stage_overlay_ = s->overlay;  // contacts, cells: drawn with the drag spring on top
    }
    if (renderer_.draws_device_positions()) ++device_frames_;

    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    if (width <= 0 || height <= 0) return true;  // minimised
    const double aspect = double(width) / height;
    if (tuning_.auto_frame) auto_frame_.update(camera_, renderer_.bounds(), aspect);

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const PanelRequests r = draw_panels(scene_, *physics_, tuning_, sound_, options_render_,
                                        examples_, load_error_, frame_ms_);
    handle_keys(r.screenshot);
    handle_mouse(width, height);
    if (r.frame_scene) frame_scene();
    if (r.reload) open(scene_.source);
    if (r.open) open(*r.open);

    const auto t0 = Clock::now();
    std::vector<render::OverlaySegment> overlay = stage_overlay_;
    for (const auto& seg : drag_overlay()) overlay.push_back(seg);
    renderer_.set_overlay(overlay);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    renderer_.draw(camera_, width, height, options_render_);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glFinish();
    frame_ms_ = 0.9 * frame_ms_ +
                0.1 * std::chrono::duration<double, std::milli>(Clock::now() - t0).count();

    if (screenshot_now || screenshot_requested_) {
      const auto file = screenshot_file.empty() ? timestamped_png() : screenshot_file;
      try {
        render::write_png(render::read_framebuffer(0, width, height), file);
        std::cout << "maille-viewer: screenshot " << file.string() << '\n';
      } catch (const std::exception& e) {
        std::cerr << "maille-viewer: " << e.what() << '\n';
        screenshot_failed_ = true;
      }
      screenshot_requested_ = false;
    }
    glfwSwapBuffers(window_);
    return true;
  }

  bool screenshot_failed() const { return screenshot_failed_; }
  int device_frames() const { return device_frames_; }  // drawn from a GPU's buffers
  PhysicsThread& physics() { return *physics_; }
  Sound& sound() { return sound_; }
  const Scene& scene() const { return scene_; }
  const std::string& load_error() const { return load_error_; }

 private:
  SharedContext shared_context() const {
    if (!physics_context_) return {};
    GLFWwindow* w = physics_context_;
    return {[w] { glfwMakeContextCurrent(w); }, [] { glfwMakeContextCurrent(nullptr); }};
  }

  void frame_scene() {
    tuning_.auto_frame = true;
    auto_frame_.reset();
  }

  void handle_keys(bool screenshot_button) {
    screenshot_requested_ = screenshot_requested_ || screenshot_button;
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE))
      physics_->status().running ? physics_->pause() : physics_->play();
    if (ImGui::IsKeyPressed(GLFW_KEY_N)) physics_->step_once();
    if (ImGui::IsKeyPressed(GLFW_KEY_R)) physics_->reset();
    if (ImGui::IsKeyPressed(GLFW_KEY_F)) frame_scene();
    if (ImGui::IsKeyPressed(GLFW_KEY_P)) screenshot_requested_ = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_Q) || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE))
      glfwSetWindowShouldClose(window_, GLFW_TRUE);
  }

  // Mouse: left drag orbits, or drags the free point under the cursor through a spring; right
  // (or middle, or shift + left) drag pans; the wheel zooms. Positions are converted from window
  // coordinates to framebuffer pixels (they differ on high-density screens).
  void handle_mouse(int width, int height) {
    ImGuiIO& io = ImGui::GetIO();
    const double sx = io.DisplayFramebufferScale.x, sy = io.DisplayFramebufferScale.y;
    const double mx = io.MousePos.x * sx, my = io.MousePos.y * sy;
    const double dx = io.MouseDelta.x * sx, dy = io.MouseDelta.y * sy;
    const bool shift = io.KeyShift;

    if (grabbed_) {
      if (!ImGui::IsMouseDown(0)) {
        physics_->drag().release();
        grabbed_.reset();
      } else {
        const render::Ray ray = camera_.ray(mx, my, width, height);
        // The grab plane faces the camera through the point where it was grabbed.
        const Vec3 n = camera_.forward();
        const Real denom = dot(ray.direction, n);
        if (std::abs(denom) > Real(1e-9)) {
          const Real t = dot(grab_anchor_ - ray.origin, n) / denom;
          drag_target_ = ray.origin + ray.direction * t;
          physics_->drag().move_to(drag_target_);
        }
      }
      return;
    }
    if (io.WantCaptureMouse) return;

    // Positions left on the GPU are not on the host to pick from (and only the CPU drags).
    if (ImGui::IsMouseClicked(0) && !shift && !renderer_.draws_device_positions()) {
      if (auto p = pick(mx, my, width, height, 12 * sx)) {
        grabbed_ = *p;
        grab_anchor_ = drag_target_ = renderer_.positions()[*p];
        DragTarget d = default_drag(scene_.model, tuning_.step, *p, drag_target_);
        d.stiffness *= tuning_.drag_factor;
        physics_->drag().grab(d);
        return;
      }
    }
    if (ImGui::IsMouseDown(0) && !shift && (dx != 0 || dy != 0)) camera_.orbit(-dx * 0.3, dy * 0.3);
    if ((ImGui::IsMouseDown(1) || ImGui::IsMouseDown(2) || (ImGui::IsMouseDown(0) && shift)) &&
        (dx != 0 || dy != 0)) {
      camera_.pan(dx, dy, height);
      tuning_.auto_frame = false;
    }
    if (io.MouseWheel != 0) {
      camera_.zoom(std::pow(0.88, double(io.MouseWheel)));
      tuning_.auto_frame = false;
    }
  }

  // The free point drawn nearest to pixel (x, y), within `radius` pixels; the nearest to the
  // eye among points at about the same pixel distance.
  std::optional<std::uint32_t> pick(double x, double y, int width, int height, double radius) {
    const auto positions = renderer_.positions();
    std::optional<std::uint32_t> best;
    double best_score = 0;
    for (std::uint32_t i = 0; i < positions.size(); ++i) {
      if (scene_.model.points.inv_mass[i] == 0) continue;
      const auto p = camera_.project(positions[i], width, height);
      if (!p) continue;
      const double d = std::hypot(p->x - x, p->y - y);
      if (d > radius) continue;
      const double score = d / radius + p->depth / camera_.distance;
      if (!best || score < best_score) {
        best = i;
        best_score = score;
      }
    }
    return best;
  }

  std::vector<render::OverlaySegment> drag_overlay() const {
    std::vector<render::OverlaySegment> segments;
    if (!grabbed_) return segments;
    const Vec3 p = renderer_.positions()[*grabbed_];
    segments.push_back({p, drag_target_, {1.0f, 0.9f, 0.1f}});
    const Real s = Real(0.02 * camera_.distance);  // a small cross at the mouse
    for (const Vec3& axis : {camera_.right(), camera_.up()})
      segments.push_back({drag_target_ - axis * s, drag_target_ + axis * s, {1.0f, 0.9f, 0.1f}});
    return segments;
  }

  GLFWwindow* window_;
  GLFWwindow* physics_context_;
  std::vector<render::OverlaySegment> stage_overlay_;  // from the last snapshot
  ViewerOptions options_;
  std::vector<std::filesystem::path> examples_;  // the scene picker's list
  render::Renderer renderer_;
  std::unique_ptr<render::SnapshotExchange> exchange_;
  std::unique_ptr<PhysicsThread> physics_;
  Sound sound_;  // after physics_: stopped (it tells the physics) before the physics goes
  Scene scene_;
  Tuning tuning_;
  render::RenderOptions options_render_;
  render::Camera camera_;
  render::AutoFrame auto_frame_;
  FileWatch watch_;
  std::string load_error_;
  std::optional<std::uint32_t> grabbed_;
  Vec3 grab_anchor_{}, drag_target_{};
  double frame_ms_ = 0;
  int device_frames_ = 0;
  bool screenshot_requested_ = false, screenshot_failed_ = false;
};

// --sound: the Sound panel's box ticked before the first frame.
void start_sound(Viewer& viewer, const ViewerOptions& o) {
  Sound::Choice& c = viewer.sound().choice();
  const auto& drivers = play::drivers();
  const auto d = std::find(drivers.begin(), drivers.end(), o.sound_driver);
  c.driver = d == drivers.end() ? 0 : static_cast<int>(d - drivers.begin()) + 1;
  std::snprintf(c.device.data(), c.device.size(), "%s", o.sound_device.c_str());
  if (viewer.sound().start(viewer.scene(), viewer.physics())) return;
  const Sound::Report& r = viewer.sound().report();
  std::cerr << "maille-viewer: sound is off: " << r.error << '\n';
  for (const auto& t : r.tried) std::cerr << "  " << t << '\n';
}

// The end of a --frames run with --sound: what played, the xruns, the CPU per period.
void print_sound(Sound& sound, const PhysicsStatus& st) {
  const Sound::Report& r = sound.report(true);
  if (!r.on) {
    std::cout << "maille-viewer: sound off\n";
    return;
  }
  const auto& k = r.counters;
  std::printf(
      "maille-viewer: sound on %s: %d Hz, %zu-frame periods, lead %zu frames; played %llu "
      "frames, rendered %llu, xruns %llu (ring empty %llu, driver %llu), CPU %.1f %% of the "
      "period%s%s\n",
      r.output.c_str(), r.rate, r.period, r.lead, static_cast<unsigned long long>(k.frames_played),
      static_cast<unsigned long long>(k.rendered),
      static_cast<unsigned long long>(k.underruns + k.driver_xruns),
      static_cast<unsigned long long>(k.underruns), static_cast<unsigned long long>(k.driver_xruns),
      100 * r.cpu, st.sound_notice.empty() ? "" : "; ", st.sound_notice.c_str());
  for (const auto& n : r.notes) std::printf("maille-viewer: sound: %s\n", n.c_str());
  for (const auto& in : r.inputs) std::printf("maille-viewer: controls: %s\n", in.c_str());
  std::fflush(stdout);
}

void on_glfw_error(int code, const char* message) {
  std::cerr << "maille-viewer: GLFW error " << code << ": " << message << '\n';
}

}  // namespace

int run_viewer(const ViewerOptions& o) {
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit()) {
    std::cerr << "maille-viewer: no display (set DISPLAY, or use `maille render` headless)\n";
    return 1;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "Maille", nullptr, nullptr);
  if (!window) {
    std::cerr << "maille-viewer: cannot open an OpenGL 4.5 core window\n";
    glfwTerminate();
    return 1;
  }
  // The physics thread's context: hidden, sharing the window's objects (a GPU backend's
  // buffers are drawn from directly). Without it, GPU positions are read back per snapshot.
  glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow* physics_context = glfwCreateWindow(1, 1, "Maille physics", nullptr, window);
  glfwDefaultWindowHints();
  if (!physics_context)
    std::cerr << "maille-viewer: no shared context for the physics thread: GPU positions will be "
                 "read back to draw\n";
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 450");

  int code = 0;
  {
    Viewer viewer(window, physics_context, o);
    if (!viewer.open(o.scene)) {
      std::cerr << viewer.load_error() << '\n';
      code = 1;
    } else {
      for (const auto& [stage, option, value] : o.stage_options)
        viewer.physics().set_stage_option(stage, option, value);
      if (o.sound) start_sound(viewer, o);
      for (int n = 1; o.frames <= 0 || n <= o.frames; ++n) {
        const bool last = o.frames > 0 && n == o.frames;
        if (!viewer.frame(last && !o.screenshot.empty(), o.screenshot)) break;
      }
      if (viewer.screenshot_failed()) code = 1;
      if (o.frames > 0) {
        const PhysicsStatus st = viewer.physics().status();
        std::cout << "maille-viewer: " << o.frames << " frames, simulated " << st.time << " s in "
                  << st.step << " steps on the " << st.backend << " backend, "
                  << viewer.device_frames() << " drawn from the GPU's buffers\n";
        if (!st.notice.empty()) std::cout << "maille-viewer: notice: " << st.notice << '\n';
        if (o.sound) print_sound(viewer.sound(), st);
      }
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  if (physics_context) glfwDestroyWindow(physics_context);
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}

}  // namespace maille::viewer
