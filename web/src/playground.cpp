#include "playground.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <stdexcept>

#define TOML_HEADER_ONLY 0
#include <toml++/toml.h>

#include "../../apps/viewer/drag_spring.hpp"
#include "maille/link_registry.hpp"
#include "maille/stage_registry.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace maille::web {

namespace {

const LinkKindRegistry& kinds() {
  static const LinkKindRegistry k = LinkKindRegistry::with_builtins();
  return k;
}

const StageRegistry& stages() {
  static const StageRegistry s = StageRegistry::with_builtins();
  return s;
}

// Every number the text writes, by its `--set` path: tables by name, arrays of tables by index.
void collect_keys(const toml::table& t, const std::string& prefix, std::vector<DeclaredKey>& out) {
  for (const auto& [k, node] : t) {
    const std::string path =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const auto* sub = node.as_table()) {
      collect_keys(*sub, path, out);
    } else if (const auto* arr = node.as_array()) {
      if (arr->is_array_of_tables()) {
        for (std::size_t i = 0; i < arr->size(); ++i)
          collect_keys(*arr->get(i)->as_table(), path + "[" + std::to_string(i) + "]", out);
      }
    } else if (const auto* i = node.as_integer()) {
      out.push_back({path, double(i->get()), true});
    } else if (const auto* f = node.as_floating_point()) {
      out.push_back({path, f->get(), false});
    }
  }
}

// A scene that asks for a compute backend (`backend = "gpu"`: OpenGL 4.5 compute shaders) is
// refused at that key: WebGL2 has no compute shaders, and running it on the CPU instead would
// not be the scene the file describes (gpu_cloth_512 has 262 144 particles).
InputError refuse_backend(const std::string& text, const std::string& source_name,
                          const Scene& scene) {
  InputError e{source_name, 0, 0, "simulation.backend",
               "the scene asks for the '" + scene.settings.backend +
                   "' compute backend, which the browser build does not have (WebGL2 has no "
                   "compute shaders); the browser runs scenes on the CPU"};
  try {
    const toml::table root = toml::parse(text, source_name);
    if (const toml::node* n = root.at_path("simulation.backend").node()) {
      e.line = int(n->source().begin.line);
      e.column = int(n->source().begin.column);
    }
  } catch (const toml::parse_error&) {
  }
  return e;
}

}  // namespace

Playground::Playground() : drag_(std::make_shared<viewer::DragState>()) {}
Playground::~Playground() = default;

LoadResult Playground::load(const std::string& text, const std::string& source_name,
                            const std::vector<std::string>& overrides) {
  Result<Scene> r = parse_scene(text, source_name, kinds(), stages(), overrides);
  if (!r) return {false, r.error()};
  Scene scene = std::move(r.value());
  if (scene.settings.backend != "cpu") return {false, refuse_backend(text, source_name, scene)};
  if (scene.name.empty()) {
    const std::string stem = std::filesystem::path(source_name).stem().string();
    scene.name = stem.empty() ? "scene" : stem;
  }
  try {
    start(std::move(scene), std::nullopt);
  } catch (const std::exception& e) {  // the simulator refuses the model (scheme, stage)
    return {false, InputError{source_name, 0, 0, "", e.what()}};
  }
  text_ = text;
  source_name_ = source_name;
  overrides_ = overrides;
  return {true, {}};
}

LoadResult Playground::set(const std::string& key, const std::string& value) {
  if (!sim_) return {false, InputError{"--set", 0, 0, key, "no scene is loaded"}};
  std::vector<std::string> overrides = overrides_;
  const std::string assignment = key + "=" + value;
  // A key set again replaces its earlier value (the later one would win anyway).
  std::erase_if(overrides, [&](const std::string& o) { return o.rfind(key + "=", 0) == 0; });
  overrides.push_back(assignment);
  Result<Scene> r = parse_scene(text_, source_name_, kinds(), stages(), overrides);
  if (!r) return {false, r.error()};
  std::optional<State> keep;
  if (r->model.points.size() == sim_->model().points.size()) keep = sim_->state();
  try {
    start(std::move(r.value()), std::move(keep));
  } catch (const std::exception& e) {
    return {false, InputError{"--set", 0, 0, key, e.what()}};
  }
  overrides_ = std::move(overrides);
  return {true, {}};
}

void Playground::start(Scene scene, std::optional<State> keep) {
  // The golden tests' settings: the CPU, one thread, or the threads the page asks for in the
  // threaded module (the engine's results do not depend on the count).
  SimulationSettings settings = scene.settings;
  settings.backend = "cpu";
  settings.threads = threads_;
  auto sim = std::make_unique<Simulator>(scene.model, settings);
  sim->on_publish([this](const Snapshot& s) { surfaces_ = s.surfaces; });
  if (keep) {
    try {
      sim->restore(std::move(*keep));
    } catch (const std::invalid_argument&) {
      // the state does not fit the new model (its scheme or stages changed): start afresh
    }
  }
  drag_->release();
  drag_installed_ = false;
  topology_ = render::make_topology(sim->model());
  smooth_ = SmoothSurface(sim->model());
  // Kept state (set, threads) continues the sound with the same resamplers, if the step and the
  // listeners stayed; anything else starts it again.
  const bool continuing = keep.has_value() && sim->steps_taken() > 0 && scene_ &&
                          scene_->audio.listeners.size() == scene.audio.listeners.size() &&
                          scene_->settings.step == scene.settings.step &&
                          scene_->audio.settings.rate == scene.audio.settings.rate &&
                          scene_->audio.settings.resampler == scene.audio.settings.resampler;
  scene_ = std::move(scene);
  listen(*sim, continuing);
  sim_ = std::move(sim);
  solids_.clear();
}

std::uint64_t Playground::step(std::uint64_t n) {
  if (!sim_) return 0;
  const auto t0 = std::chrono::steady_clock::now();
  std::uint64_t done = 0;
  for (; done < n; ++done)
    if (!sim_->step()) break;
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (done > 0) last_step_ms_ = ms / double(done);
  return done;
}

int Playground::max_threads() {
#ifdef _OPENMP
  return omp_get_num_procs();
#else
  return 1;
#endif
}

int Playground::set_threads(int n) {
  n = std::clamp(n, 1, max_threads());
  if (n == threads_) return n;
  threads_ = n;
  // The run goes on from its state with the new team (as `set` does).
  if (sim_) start(Scene(*scene_), sim_->state());
  return n;
}

void Playground::reset() {
  if (!sim_) return;
  sim_->reset();
  drag_->release();
  listen(*sim_, false);
}

std::uint64_t Playground::state_hash() const {
  return sim_ ? maille::state_hash(sim_->state()) : 0;
}

const std::vector<float>& Playground::normals() {
  if (sim_) render::surface_normals(topology_, sim_->state().x(), normals_);
  return normals_;
}

const std::vector<float>& Playground::smooth_normals() {
  if (sim_) vertex_normals(smooth_.other_triangles(), sim_->state().x(), smooth_normals_);
  return smooth_normals_;
}

const SmoothMesh& Playground::smooth_evaluate(int lod) {
  if (sim_ && !smooth_.empty())
    smooth_.evaluate(sim_->state().x(), std::clamp(lod, 1, kMaxSmoothLod), smooth_mesh_);
  return smooth_mesh_;
}

const std::vector<Solid>& Playground::solids() {
  if (!sim_) return solids_;
  sim_->publish_now();  // the listener installed by start() keeps the solids placed now
  const std::vector<SurfaceInstance>& surfaces = surfaces_;
  std::vector<Solid> out;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const SurfaceInstance& s = surfaces[i];
    Solid solid;
    solid.name = s.name;
    // The mesh never changes between snapshots of one stage: its vertices are made once.
    if (i < solids_.size() && solids_[i].name == s.name)
      solid.vertices = std::move(solids_[i].vertices);
    else if (s.mesh)
      solid.vertices = render::solid_vertices(*s.mesh);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) solid.placement[std::size_t(3 * r + c)] = float(s.direct.m[r][c]);
    solid.placement[9] = float(s.translation.x);
    solid.placement[10] = float(s.translation.y);
    solid.placement[11] = float(s.translation.z);
    solid.colour = s.colour;
    out.push_back(std::move(solid));
  }
  solids_ = std::move(out);
  return solids_;
}

void Playground::grab(std::uint32_t point, const Vec3& target) {
  if (!sim_ || point >= sim_->model().points.size()) return;
  if (sim_->model().points.inv_mass[point] == 0) return;  // a fixed point does not follow
  // The drag spring joins the run at the first grab, so that a run never dragged is the very
  // run of the golden tests (the same stages: the same state hash).
  if (!drag_installed_) {
    sim_->add_stage(std::make_unique<viewer::DragSpring>(drag_));
    drag_installed_ = true;
  }
  drag_->grab(viewer::default_drag(sim_->model(), sim_->settings().step, point, target));
}

void Playground::move_to(const Vec3& target) {
  drag_->move_to(target);
}
void Playground::release() {
  drag_->release();
}

std::vector<DeclaredKey> Playground::declared_keys() const {
  std::vector<DeclaredKey> out;
  try {
    const toml::table root = toml::parse(text_, source_name_);
    collect_keys(root, "", out);
  } catch (const toml::parse_error&) {
  }
  // The overrides in force replace the text's values.
  for (const std::string& o : overrides_) {
    const auto eq = o.find('=');
    for (DeclaredKey& k : out)
      if (o.compare(0, eq, k.key) == 0 && eq == k.key.size())
        k.value = std::strtod(o.c_str() + eq + 1, nullptr);
  }
  return out;
}

}  // namespace maille::web
