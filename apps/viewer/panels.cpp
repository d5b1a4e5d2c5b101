#include "panels.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <utility>

#include "maille/backend.hpp"
#include "maille/integrator.hpp"
#include "maille/smooth_surface.hpp"

namespace maille::viewer {

namespace {

void implicit_controls(PhysicsThread& physics, ImplicitSettings implicit);

float to_float(Real v) {
  return static_cast<float>(v);
}

// A command the physics refused, and why (wrapped: the reasons are sentences).
// Checkboxes side by side on one line.
void checkbox_row(std::initializer_list<std::pair<const char*, bool*>> boxes) {
  bool first = true;
  for (const auto& [label, value] : boxes) {
    if (!first) ImGui::SameLine();
    ImGui::Checkbox(label, value);
    first = false;
  }
}

void notice(const std::string& text) {
  ImGui::PushTextWrapPos(0);
  ImGui::TextColored(ImVec4(1, 0.7f, 0.2f, 1), "%s", text.c_str());
  ImGui::PopTextWrapPos();
}

void simulation_controls(PhysicsThread& physics, const PhysicsStatus& st, Tuning& t) {
  if (ImGui::Button(st.running ? "Pause (space)" : "Play (space)"))
    st.running ? physics.pause() : physics.play();
  ImGui::SameLine();
  if (ImGui::Button("Step (N)")) physics.step_once();
  ImGui::SameLine();
  if (ImGui::Button("Reset (R)")) physics.reset();

  if (ImGui::Checkbox("as fast as possible", &t.as_fast_as_possible))
    physics.set_speed(t.as_fast_as_possible ? 0.0 : t.speed);
  if (!t.as_fast_as_possible &&
      ImGui::SliderFloat("speed", &t.speed, 0.02f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic))
    physics.set_speed(t.speed);

  ImGui::InputDouble("step h (s)", &t.step, 0, 0, "%.3e");
  if (ImGui::IsItemDeactivatedAfterEdit()) {
    t.step = std::clamp(t.step, 1e-7, 1e-1);
    physics.set_time_step(t.step);
  }

  const auto& entries = IntegratorRegistry::builtin().entries();
  if (ImGui::BeginCombo("integrator", st.integrator.c_str())) {
    for (const auto& e : entries)
      if (ImGui::Selectable(e.name.c_str(), e.name == st.integrator))
        physics.set_integrator(e.name);
    ImGui::EndCombo();
  }

  if (st.integrator == "implicit_euler") implicit_controls(physics, st.implicit);

  if (ImGui::BeginCombo("backend", st.backend.c_str())) {
    for (const auto& e : BackendRegistry::global().entries())
      if (ImGui::Selectable(e.name.c_str(), e.name == st.backend)) physics.set_backend(e.name);
    ImGui::EndCombo();
  }
  if (ImGui::IsItemHovered() && st.backend != "cpu")
    ImGui::SetTooltip("particles can be dragged on the cpu backend only");

  ImGui::Text("t = %.3f s   step %llu", st.time, static_cast<unsigned long long>(st.step));
  ImGui::Text("%.0f steps/s   %.2fx real time", st.steps_per_second, st.realtime_factor);
  if (st.blow_up) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextColored(ImVec4(1, 0.35f, 0.3f, 1), "Blow-up: %s", st.blow_up->c_str());
    ImGui::PopTextWrapPos();
  }
  // A stage's refusal is shown under the stage, when the Stages panel lists it.
  const bool under_stage =
      std::any_of(st.stage_options.begin(), st.stage_options.end(),
                  [&](const Simulator::StageOptions& s) { return s.stage == st.notice_stage; });
  if (!st.notice.empty() && !under_stage) notice(st.notice);
}

void field_controls(PhysicsThread& physics, Tuning& t) {
  Fields& f = t.fields;
  float g[3] = {to_float(f.gravity.x), to_float(f.gravity.y), to_float(f.gravity.z)};
  float w[3] = {to_float(f.wind.velocity.x), to_float(f.wind.velocity.y),
                to_float(f.wind.velocity.z)};
  float drag = to_float(f.air_drag), turbulence = to_float(f.wind.turbulence);
  bool changed = false;
  if (ImGui::DragFloat3("gravity (m/s2)", g, 0.05f)) {
    f.gravity = {g[0], g[1], g[2]};
    changed = true;
  }
  if (ImGui::SliderFloat("air drag (1/s)", &drag, 0, 5, "%.3f", ImGuiSliderFlags_Logarithmic)) {
    f.air_drag = drag;
    changed = true;
  }
  if (ImGui::DragFloat3("wind (m/s)", w, 0.05f)) {
    f.wind.velocity = {w[0], w[1], w[2]};
    changed = true;
  }
  if (ImGui::SliderFloat("turbulence", &turbulence, 0, 1)) {
    f.wind.turbulence = turbulence;
    changed = true;
  }
  if (changed) physics.set_fields(f);
}

void link_controls(const Scene& scene, PhysicsThread& physics, Tuning& t) {
  const auto pools = scene.model.links.pools();
  for (std::size_t p = 0; p < pools.size(); ++p) {
    const LinkPoolBase& pool = *pools[p];
    ImGui::PushID(static_cast<int>(p));
    ImGui::Text("%s: %zu links", std::string(pool.keyword()).c_str(), pool.size());
    const auto fields = pool.fields();
    for (std::size_t k = 0; k < fields.size() && k < t.link_factor[p].size(); ++k) {
      float& factor = t.link_factor[p][k];
      const float before = factor;
      const double value = pool.size() ? double(pool.param(0, k)) * factor : 0.0;
      char label[96];
      std::snprintf(label, sizeof label, "%s x##%zu", fields[k].name.c_str(), k);
      char format[64];
      std::snprintf(format, sizeof format, "%%.3g (%.3g %s)", value, fields[k].unit.c_str());
      if (ImGui::SliderFloat(label, &factor, 0.01f, 100.0f, format, ImGuiSliderFlags_Logarithmic) &&
          factor > 0 && before > 0)
        physics.scale_link_param(p, k, Real(factor / before));
    }
    ImGui::PopID();
  }
}

// Every plugged-in stage's live settings, as combo boxes (self-collision: on/off, broad phase,
// exclusion, contacts and cells drawn; an obstacle's method): no stage-specific code here. The
// combo shows the stage's current choice, so a refused switch leaves it where it was, with the
// reason under the stage.
void stage_controls(PhysicsThread& physics, const PhysicsStatus& st) {
  for (const auto& w : st.stage_warnings) notice("warning: " + w);  // a leaking self-collision
  for (const auto& stage : st.stage_options) {
    ImGui::TextUnformatted(stage.stage.c_str());
    for (const auto& o : stage.options) {
      const std::string id = o.name + "##" + stage.stage;
      if (ImGui::BeginCombo(id.c_str(), o.value.c_str())) {
        for (const auto& c : o.choices)
          if (ImGui::Selectable(c.c_str(), c == o.value) && c != o.value)
            physics.set_stage_option(stage.stage, o.name, c);
        ImGui::EndCombo();
      }
    }
    if (!st.notice.empty() && st.notice_stage == stage.stage) notice(st.notice);
  }
}

// Sound (docs/sound.md, "The viewer's Sound panel"): on/off, the driver and device (taken when
// sound starts), the gain (smoothed by the callback), and what the sound costs: the CPU time of
// rendering over the sound's duration, and the xruns.
void sound_controls(const Scene& scene, PhysicsThread& physics, const PhysicsStatus& st,
                    Sound& sound) {
  const std::size_t channels = scene.audio.listeners.size();
  if (channels == 0) {
    ImGui::TextDisabled("no [[listen]] table in this scene: nothing to hear");
    return;
  }
  Sound::Choice& c = sound.choice();
  bool on = sound.on();
  if (ImGui::Checkbox("sound on", &on)) on ? (void)sound.start(scene, physics) : sound.stop();
  ImGui::SameLine();
  ImGui::TextDisabled("%zu channel%s, %zu control%s", channels, channels == 1 ? "" : "s",
                      scene.audio.controls.size(), scene.audio.controls.size() == 1 ? "" : "s");
  // The device is chosen when sound starts.
  ImGui::BeginDisabled(sound.on());
  const char* names[] = {"auto (jack, pulse, alsa)", "jack", "pulse", "alsa"};
  ImGui::Combo("driver", &c.driver, names, IM_ARRAYSIZE(names));
  ImGui::InputText("device", c.device.data(), c.device.size());
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "JACK: a port-name prefix (default: the physical playback ports); "
        "pulse, alsa: part of the device's name (default: the default device)");
  ImGui::EndDisabled();
  float gain = c.gain;
  if (ImGui::SliderFloat("gain", &gain, 0.0f, 4.0f, "%.2fx [audio] gain")) sound.set_gain(gain);

  const Sound::Report& r = sound.report();
  if (r.on) {
    ImGui::TextWrapped("%s", r.output.c_str());
    ImGui::Text("%d Hz, %zu-frame periods, latency %.1f ms", r.rate, r.period, 1e3 * r.latency);
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "CPU %.0f %% of the period (largest %.0f %%)",
                  100 * r.cpu, 100 * r.cpu_worst);
    ImGui::ProgressBar(static_cast<float>(std::min(r.cpu, 1.0)), ImVec2(-1, 0), overlay);
    const auto& k = r.counters;
    ImGui::Text("xruns %llu (ring empty %llu, driver %llu)",
                static_cast<unsigned long long>(k.underruns + k.driver_xruns),
                static_cast<unsigned long long>(k.underruns),
                static_cast<unsigned long long>(k.driver_xruns));
    ImGui::Text("played %.1f s", r.rate ? double(k.frames_played) / r.rate : 0.0);
    if (k.clipped) {
      ImGui::SameLine();
      ImGui::TextColored(ImVec4(1, 0.7f, 0.2f, 1), "%llu samples clipped: lower the gain",
                         static_cast<unsigned long long>(k.clipped));
    }
    for (const auto& in : r.inputs) ImGui::TextWrapped("controls: %s", in.c_str());
    if (!st.running)
      ImGui::TextDisabled("paused: silence");
    else if (st.sound)
      ImGui::TextDisabled("paced by the sound card (speed waits)");
  }
  for (const auto& n : r.notes) notice(n);
  if (!r.error.empty()) notice(r.error);
  for (const auto& t : r.tried) notice("  " + t);
  if (!st.sound_notice.empty()) notice(st.sound_notice);
}

void drawing_controls(render::RenderOptions& o, Tuning& t, PanelRequests& r) {
  checkbox_row(
      {{"surfaces", &o.surface}, {"links", &o.links}, {"cloth mesh", &o.links_on_surface}});
  checkbox_row({{"points", &o.points},
                {"contacts", &o.contacts},
                {"grid", &o.grid},
                {"obstacles", &o.solids}});
  // Smooth surface through the particles, evaluated on the GPU (smooth_surface.hpp).
  ImGui::Checkbox("smooth", &o.smooth);
  ImGui::SameLine();
  ImGui::SliderInt("level of detail", &o.smooth_lod, 1, kMaxSmoothLod);
  ImGui::SliderFloat("strain range", &o.strain_range, 0.001f, 0.5f, "%.3f",
                     ImGuiSliderFlags_Logarithmic);
  ImGui::SliderFloat("link width (px)", &o.link_width, 0.5f, 8.0f);
  ImGui::SliderFloat("point size", &o.point_scale, 0.1f, 5.0f, "%.2fx");
  ImGui::SliderFloat("drag stiffness", &t.drag_factor, 0.01f, 100.0f, "%.2fx",
                     ImGuiSliderFlags_Logarithmic);
  if (ImGui::Checkbox("auto-frame", &t.auto_frame) && t.auto_frame) r.frame_scene = true;
  ImGui::SameLine();
  if (ImGui::Button("Frame (F)")) r.frame_scene = true;
  ImGui::SameLine();
  if (ImGui::Button("Screenshot (P)")) r.screenshot = true;
}

// One line plot per series over the history, with the latest value written on it.
void plot(const char* label, const std::vector<float>& values, const char* unit) {
  if (values.empty()) return;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  char overlay[96], id[96];
  std::snprintf(overlay, sizeof overlay, "%s %.4g %s", label, double(values.back()), unit);
  std::snprintf(id, sizeof id, "##%s", label);  // the overlay names it: no label column
  ImGui::PlotLines(id, values.data(), static_cast<int>(values.size()), 0, overlay, *lo,
                   *hi + 1e-9f * (1 + std::abs(*hi)), ImVec2(ImGui::GetContentRegionAvail().x, 44));
}

// A combo over a name table's choices; true when the user picked another one.
template <class E>
bool name_combo(const char* label, E& value) {
  bool picked = false;
  if (ImGui::BeginCombo(label, std::string(to_string(value)).c_str())) {
    for (const auto& n : NameTable<E>::names)
      if (ImGui::Selectable(std::string(n.name).c_str(), n.value == value) && n.value != value) {
        value = n.value;
        picked = true;
      }
    ImGui::EndCombo();
  }
  return picked;
}

// Implicit Euler's solver and, for vertex block descent, its sweeps, coarse correction and (with
// the correction off) acceleration.
void implicit_controls(PhysicsThread& physics, ImplicitSettings implicit) {
  if (name_combo("solver", implicit.solver)) physics.set_implicit(implicit);
  if (implicit.solver != ImplicitSolver::vbd) return;
  int sweeps = implicit.iterations;
  if (ImGui::SliderInt("sweeps", &sweeps, 1, 200) && sweeps != implicit.iterations) {
    implicit.iterations = sweeps;
    physics.set_implicit(implicit);
  }
  if (name_combo("coarse", implicit.coarse)) physics.set_implicit(implicit);
  if (implicit.coarse != VbdCoarse::off) return;  // the correction replaces the acceleration
  float rho = float(implicit.acceleration);
  if (ImGui::SliderFloat("acceleration", &rho, 0.0f, 0.99f, "%.2f") &&
      Real(rho) != implicit.acceleration) {
    implicit.acceleration = Real(rho);
    physics.set_implicit(implicit);
  }
}

void plots(const PhysicsThread& physics, const PhysicsStatus& st) {
  const std::vector<PlotSample> history = physics.history();
  if (ImGui::CollapsingHeader("Energies", ImGuiTreeNodeFlags_DefaultOpen)) {
    // One curve per stats.csv energy column (for_each_energy), in its order.
    std::array<std::vector<float>, kEnergyColumns> curves;
    std::array<const char*, kEnergyColumns> names{};
    for (const auto& s : history) {
      std::size_t k = 0;
      for_each_energy(s.energies, [&](const char* name, double value) {
        names[k] = name;
        curves[k++].push_back(float(value));
      });
    }
    for (std::size_t k = 0; k < kEnergyColumns && !history.empty(); ++k)
      plot(names[k], curves[k], "J");
  }
  if (ImGui::CollapsingHeader("Time per stage", ImGuiTreeNodeFlags_DefaultOpen)) {
    double sum = 0;
    for (const auto& s : st.stages) sum += s.ns_per_step;
    for (const auto& s : st.stages) {
      char overlay[96];
      std::snprintf(overlay, sizeof overlay, "%s %.1f us", s.name.c_str(), s.ns_per_step * 1e-3);
      ImGui::ProgressBar(sum > 0 ? float(s.ns_per_step / sum) : 0.0f, ImVec2(-1, 0), overlay);
    }
    ImGui::Text("step: %.1f us", sum * 1e-3);
  }
  if (ImGui::CollapsingHeader("Counters", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (std::size_t c = 0; c < st.counters.size(); ++c) {
      std::vector<float> values;
      for (const auto& s : history)
        if (c < s.counters.size()) values.push_back(float(s.counters[c]));
      plot(st.counters[c].name.c_str(), values, "");
    }
  }
  // Gauges: the implicit solvers' residuals (solver_residual: the largest force imbalance over
  // m g), obstacles' depths, the self-collision cell size.
  if (!st.gauges.empty() && ImGui::CollapsingHeader("Gauges", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (std::size_t g = 0; g < st.gauges.size(); ++g) {
      std::vector<float> values;
      for (const auto& s : history)
        if (g < s.gauges.size()) values.push_back(float(s.gauges[g]));
      plot(st.gauges[g].c_str(), values, "");
    }
  }
}

}  // namespace

Tuning Tuning::from(const Scene& scene) {
  Tuning t;
  for (const auto& pool : scene.model.links.pools())
    t.link_factor.emplace_back(pool->fields().size(), 1.0f);
  t.fields = scene.model.fields;
  t.step = scene.settings.step;
  return t;
}

PanelRequests draw_panels(const Scene& scene, PhysicsThread& physics, Tuning& tuning, Sound& sound,
                          render::RenderOptions& options,
                          const std::vector<std::filesystem::path>& examples,
                          const std::string& load_error, double frame_ms) {
  PanelRequests r;
  const PhysicsStatus st = physics.status();

  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(370, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Maille");
  const std::string current = scene.source.filename().string();
  if (ImGui::BeginCombo("scene", current.c_str())) {
    for (const auto& e : examples)
      if (ImGui::Selectable(e.filename().string().c_str(), e.filename() == scene.source.filename()))
        r.open = e;
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("Reload")) r.reload = true;
  if (!scene.description.empty()) ImGui::TextWrapped("%s", scene.description.c_str());
  if (!load_error.empty()) {
    ImGui::PushTextWrapPos(0);
    ImGui::TextColored(ImVec4(1, 0.35f, 0.3f, 1), "%s", load_error.c_str());
    ImGui::PopTextWrapPos();
  }
  ImGui::Text("%u points, %zu links, %zu faces; drawing %.1f ms", scene.model.points.size(),
              scene.model.links.total(), scene.model.surface.triangles.size(), frame_ms);

  if (ImGui::CollapsingHeader("Simulation", ImGuiTreeNodeFlags_DefaultOpen))
    simulation_controls(physics, st, tuning);
  if (ImGui::CollapsingHeader("Fields", ImGuiTreeNodeFlags_DefaultOpen))
    field_controls(physics, tuning);
  if (ImGui::CollapsingHeader("Links", ImGuiTreeNodeFlags_DefaultOpen))
    link_controls(scene, physics, tuning);
  if (!st.stage_options.empty() &&
      ImGui::CollapsingHeader("Stages", ImGuiTreeNodeFlags_DefaultOpen))
    stage_controls(physics, st);
  // Open by default when the scene has something to hear.
  if (ImGui::CollapsingHeader("Sound",
                              scene.audio.listeners.empty() ? 0 : ImGuiTreeNodeFlags_DefaultOpen))
    sound_controls(scene, physics, st, sound);
  if (ImGui::CollapsingHeader("Drawing")) drawing_controls(options, tuning, r);
  ImGui::TextDisabled("left drag: orbit or grab a point; right drag: pan; wheel: zoom");
  ImGui::End();

  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(display.x - 338, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Plots");
  plots(physics, st);
  ImGui::End();
  return r;
}

}  // namespace maille::viewer
