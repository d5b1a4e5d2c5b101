// The GPU backend: the model's points, links and faces in shader storage buffers
// (gpu_layout.hpp), and one step as four compute dispatches (shaders.hpp):
//   drive      driven points' x and v at t (uploaded: the paths are evaluated on the host)
//   faces      the wind's force per face (only with wind)
//   forces     per point: links (gather over its adjacency), faces, gravity, drag; on grid
//              cloth, per grid point by fixed offsets (the structured layout, gpu_structured.hpp)
//   integrate  per point: kick and drift, the health flag
// or, for implicit_euler with solver = "vbd", the faces and then the whole step by vertex block
// descent (gpu_vbd.hpp) in place of forces and integrate.
// Positions stay on the device between steps; the Simulator downloads them only when it needs
// them (backend.hpp). Arithmetic is float: the tests derive their tolerances from it.
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "../core/gust.hpp"
#include "gl_buffers.hpp"
#include "gpu_layout.hpp"
#include "gpu_self_collision.hpp"
#include "gpu_stage.hpp"
#include "gpu_structured.hpp"
#include "gpu_vbd.hpp"
#include "kernel.hpp"
#include "maille/backend.hpp"
#include "maille/detail/csr.hpp"
#include "maille/gpu.hpp"
#include "maille/render/headless.hpp"
#include "shaders.hpp"

namespace maille::gpu {

namespace {

// ---------------------------------------------------------------------------------------------
// Host-side packing of the model.

struct ParamsHash {
  std::size_t operator()(const std::array<float, 4>& p) const {
    std::size_t h = 0;
    for (float x : p) {
      std::uint32_t bits;
      std::memcpy(&bits, &x, 4);
      h = h * 0x9E3779B97F4A7C15ull + bits;
    }
    return h;
  }
};

// Every link of every pool, as seen from each of its ends (CSR by point), with its parameters
// deduplicated (a cloth has a handful of distinct sets for millions of links).
struct Adjacency {
  std::vector<std::uint32_t> offset;  // n + 1
  std::vector<Adjacent> entries;
  std::vector<float> params;  // 4 per set
  std::vector<KindLaw> kinds;
};

// `slot_sets` (when not null) receives each slot's parameter set (the structured layout's).
Adjacency pack_links(const Model& m, LinkSets* slot_sets) {
  const std::uint32_t n = m.points.size();
  Adjacency out;
  std::vector<std::array<std::uint32_t, 2>> law;  // each slot's kind and parameter set, in order
  std::unordered_map<std::array<float, 4>, std::uint32_t, ParamsHash> sets;
  for (const auto& pool : m.links.pools()) {
    if (slot_sets) {
      slot_sets->pool_base.push_back(slot_sets->set_of_slot.size());
      slot_sets->pool_kind.push_back(pool->size() == 0 ? -1 : int(out.kinds.size()));
    }
    if (pool->size() == 0) continue;
    const auto kind = static_cast<std::uint32_t>(out.kinds.size());
    const std::size_t fields = pool->fields().size();
    out.kinds.push_back({std::string(pool->shared_law()), int(fields)});
    const auto ends = pool->slot_ends();
    for (std::size_t slot = 0; slot < ends.size(); ++slot) {
      std::array<float, 4> p{};
      const std::uint32_t id = pool->id_of_slot(slot);
      for (std::size_t f = 0; f < fields; ++f) p[f] = float(pool->param(id, f));
      auto [it, added] = sets.try_emplace(p, std::uint32_t(sets.size()));
      if (added) out.params.insert(out.params.end(), p.begin(), p.end());
      if (slot_sets) slot_sets->set_of_slot.push_back(it->second);
      law.push_back({kind, it->second});
    }
  }
  detail::build_rows(n, out.offset, out.entries, [&](auto&& emit) {
    std::size_t k = 0;
    for (const auto& pool : m.links.pools())
      for (const LinkEnds& e : pool->slot_ends()) {
        const auto [kind, set] = law[k++];
        emit(e.a, Adjacent{e.b, kind, set});
        emit(e.b, Adjacent{e.a, kind | kEndIsB, set});
      }
  });
  if (out.params.empty()) out.params.assign(4, 0.0f);
  return out;
}

// The faces of each point (CSR), for the gather of the wind's face forces.
void pack_faces(const Model& m, std::vector<std::uint32_t>& corners,
                std::vector<std::uint32_t>& offset, std::vector<std::uint32_t>& incidence) {
  const std::uint32_t n = m.points.size();
  const auto& tris = m.surface.triangles;
  corners.clear();
  for (const auto& t : tris) corners.insert(corners.end(), t.begin(), t.end());
  detail::build_rows(n, offset, incidence, [&](auto&& emit) {
    for (std::uint32_t f = 0; f < tris.size(); ++f)
      for (std::uint32_t c : tris[f]) emit(c, f);
  });
}

std::vector<float> packed(std::span<const Vec3> a) {
  std::vector<float> out(3 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    out[3 * i] = float(a[i].x);
    out[3 * i + 1] = float(a[i].y);
    out[3 * i + 2] = float(a[i].z);
  }
  return out;
}

void unpack(const std::vector<float>& in, std::span<Vec3> out) {
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = {Real(in[3 * i]), Real(in[3 * i + 1]), Real(in[3 * i + 2])};
}

std::string gl_string(GLenum e) {
  const auto* s = reinterpret_cast<const char*>(glGetString(e));
  return s ? s : "?";
}

GLint gl_int(GLenum e, GLuint index = 0, bool indexed = false) {
  GLint v = 0;
  if (indexed)
    glGetIntegeri_v(e, index, &v);
  else
    glGetIntegerv(e, &v);
  return v;
}

std::string describe_current() {
  std::ostringstream s;
  s << "renderer     " << gl_string(GL_RENDERER) << "\n"
    << "vendor       " << gl_string(GL_VENDOR) << "\n"
    << "version      OpenGL " << gl_string(GL_VERSION) << ", GLSL "
    << gl_string(GL_SHADING_LANGUAGE_VERSION) << "\n"
    << "work groups  at most " << gl_int(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, true)
    << " per dispatch of " << kGroupSize << " invocations (max "
    << gl_int(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS)
    << "): " << double(gl_int(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, true)) * kGroupSize
    << " points or faces\n"
    << "storage      " << gl_int(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS)
    << " blocks per compute shader, " << gl_int(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS)
    << " bindings, blocks up to " << double(gl_int(GL_MAX_SHADER_STORAGE_BLOCK_SIZE)) / (1 << 20)
    << " MiB\n";
  return s.str();
}

// The model's largest buffer against the driver's largest storage block (`maille info --backend
// gpu` prints it; Mesa's llvmpipe: 128 MiB, the links of flags above about 960 x 960).
std::string too_big(const Model& m, double max_block) {
  const double adjacency = 2.0 * double(m.links.total()) * sizeof(Adjacent);
  const double faces = 3.0 * 4 * double(m.surface.triangles.size());
  const double biggest = std::max({adjacency, faces, 12.0 * m.points.size()});
  if (biggest <= max_block) return {};
  std::ostringstream why;
  why << "the model needs a " << biggest / (1 << 20) << " MiB storage buffer (its links seen from "
      << "both ends), more than this driver's limit of " << max_block / (1 << 20) << " MiB";
  return why.str();
}

// ---------------------------------------------------------------------------------------------

class GpuBackend final : public Backend {
 public:
  explicit GpuBackend(const BackendOptions& o) {
    // A context current on this thread (the renderer's EGL one, or any the caller names with
    // use_current_context: the viewer's hidden GLX window) is used as is, so that renderers in
    // its share group draw from the position buffer; otherwise the backend makes its own.
    const bool current = o.use_current_context || eglGetCurrentContext() != EGL_NO_CONTEXT;
    if (o.device >= 0 || !current) own_ = std::make_unique<render::HeadlessContext>(o.device);
    if (epoxy_gl_version() < 45)
      throw std::runtime_error("the GPU backend needs OpenGL 4.5 (this context has " +
                               std::to_string(epoxy_gl_version()) + ")");
    glCreateBuffers(GLsizei(kBufferCount), buffers_.data());
    faces_ = Kernel("gpu faces", faces_shader());
    integrate_ = Kernel("gpu integrate", integrate_shader());
    drive_ = Kernel("gpu drive", drive_shader());
    max_invocations_ = double(gl_int(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, true)) * kGroupSize;
    GLint64 block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &block);
    max_block_ = double(block);
    layout_ = grid_layout_from_environment();
  }

  // Frees the buffers and programs when the context can be made current here; otherwise (it is
  // current on another thread) destroying the context frees them.
  ~GpuBackend() override {
    try {
      current();
    } catch (const std::exception&) {
      forces_.forget(), faces_.forget(), integrate_.forget(), drive_.forget();
      if (vbd_) vbd_->forget(), vbd_.reset();  // forgotten: its destructor makes no GL call
      if (structured_) structured_->forget();
      // Their GL objects go with the context; their few host bytes are left (no GL call may
      // run without a current context).
      for (auto& st : stages_) static_cast<void>(st.release());
      return;
    }
    stages_.clear();
    vbd_.reset();
    structured_.reset();
    forces_ = {};
    faces_ = {};
    integrate_ = {};
    drive_ = {};
    glDeleteBuffers(GLsizei(kBufferCount), buffers_.data());
  }

  std::string_view name() const override { return "gpu"; }

  std::string describe() const override {
    const_cast<GpuBackend*>(this)->current();
    std::string out = describe_current();
    const std::vector<std::string> devices = render::egl_devices();
    out += "devices      " + std::to_string(devices.size()) + " EGL device(s) (--gpu-device N)\n";
    for (const auto& d : devices) out += "             " + d + "\n";
    out += "grid layout  " + std::string(to_string(layout_)) +
           " (MAILLE_GPU_LAYOUT = auto | structured | general)\n";
    return out;
  }

  std::string refuses(const Model& m, const Integrator& scheme,
                      std::span<const Stage* const> stages) const override {
    const ImplicitSettings* implicit = scheme.implicit_settings();
    if (implicit && implicit->solver != ImplicitSolver::vbd)
      return "implicit solver '" + std::string(to_string(implicit->solver)) +
             "' has no GPU version (the GPU runs implicit_euler with solver = \"vbd\"; the CPU "
             "runs every solver)";
    if (implicit && implicit->coarse != VbdCoarse::off)
      return "vbd's coarse correction (coarse = \"" + std::string(to_string(implicit->coarse)) +
             "\", the default) has no GPU version: set coarse = \"off\" in "
             "[simulation.implicit] (sweeps with the Chebyshev acceleration) or run with "
             "--backend cpu";
    if (!steps(scheme) && !scheme.kick_drift_step(State(), Real(1e-3)))
      return "integrator '" + std::string(scheme.name()) +
             "' has no GPU version (the GPU runs leapfrog, symplectic_euler and implicit_euler "
             "with solver = \"vbd\"; the CPU runs every scheme)";
    if (steps(scheme))
      if (std::string why = vbd_refuses(m, stages, max_block_); !why.empty()) return why;
    for (const auto& pool : m.links.pools()) {
      if (pool->size() == 0) continue;
      if (pool->shared_law().empty())
        return "link kind '" + std::string(pool->keyword()) +
               "' has no GPU version (its force law is not in "
               "include/maille/detail/link_laws.glsl): run this scene with --backend cpu";
      if (pool->fields().size() > 4)
        return "link kind '" + std::string(pool->keyword()) + "' has more than 4 parameters";
    }
    for (const Stage* st : stages) {  // every stage needs a registered device version
      // but those whose point pairs the VBD step uploads (vbd_refuses accepted them)
      if (steps(scheme) && uploaded_contacts(st->contacts_found())) continue;
      const GpuStageEntry* entry = GpuStageRegistry::builtin().find(st->name());
      if (!entry)
        return "stage '" + st->name() +
               "' has no GPU version yet: run this scene with --backend cpu" + st->refusal_hint();
      if (std::string why = entry->check(*st); !why.empty()) return why;
      if (st->phase() != Phase::forces)  // the step dispatches device stages after the forces
        return "stage '" + st->name() + "' runs at phase " + std::string(to_string(st->phase())) +
               ": the GPU backend runs force stages only";
    }
    if (const std::string why = too_big(m, max_block_); !why.empty()) return why;
    const double biggest = std::max<double>(m.points.size(), double(m.surface.triangles.size()));
    if (biggest > max_invocations_)
      return std::to_string(std::uint64_t(biggest)) +
             " points or faces exceed what one dispatch reaches here (" +
             std::to_string(std::uint64_t(max_invocations_)) + ")";
    return {};
  }

  void load(const Model& m, const State& s, std::span<const Stage* const> stages) override {
    current();
    points_ = m.points.size();
    upload(Buf::x, packed(s.x()));
    upload(Buf::v, packed(s.v()));
    upload(Buf::f, std::vector<float>(3 * std::size_t(points_), 0.0f));
    std::vector<float> inv_mass(points_), mass(points_);
    for (std::uint32_t i = 0; i < points_; ++i) {
      inv_mass[i] = float(m.points.inv_mass[i]);
      mass[i] = float(m.points.mass[i]);
    }
    upload(Buf::inv_mass, inv_mass);
    upload(Buf::mass, mass);

    LinkSets sets;
    Adjacency adj = pack_links(m, layout_ == GridLayout::general ? nullptr : &sets);
    upload(Buf::adjacency_offset, adj.offset);
    upload(Buf::adjacency, adj.entries);
    upload(Buf::link_params, adj.params);
    kinds_ = adj.kinds;
    vbd_memory_.clear();  // the guess's memory, for the solver's next load
    for (const StageMemory& mem : s.stage_memory)
      if (mem.stage == kVbdMemory) vbd_memory_.push_back(mem);
    vbd_stale_ = true;
    const std::string source = forces_shader(adj.kinds);
    if (source != forces_source_) {
      forces_ = Kernel("gpu forces", source);
      forces_source_ = source;
    }
    structured_ = GpuStructured::make(m, sets, adj.kinds, layout_, structured_.get());

    wind_ = m.fields.wind.active() && !m.surface.triangles.empty();
    faces_count_ = wind_ ? std::uint32_t(m.surface.triangles.size()) : 0;
    std::vector<std::uint32_t> corners, offset, incidence;
    if (wind_) pack_faces(m, corners, offset, incidence);
    if (offset.empty()) offset.assign(std::size_t(points_) + 1, 0);
    upload(Buf::face_corner, corners);
    upload(Buf::face_offset, offset);
    upload(Buf::face_of_point, incidence);
    upload(Buf::face_force, std::vector<float>(3 * std::size_t(faces_count_), 0.0f));

    driven_.resize(m.drives.size());
    upload(Buf::driven, driven_);
    upload(Buf::health, std::vector<std::uint32_t>{0xffffffffu});

    // The stages' device versions (refuses() let them through), after the step's buffers.
    stages_.clear();
    cpu_stages_.assign(stages.begin(), stages.end());
    for (const Stage* st : stages)
      if (const GpuStageEntry* entry = GpuStageRegistry::builtin().find(st->name()))
        stages_.push_back(entry->make(m, *st, GpuLimits{max_invocations_}));
  }

  void drive(const Model& m, double t) override {
    if (m.drives.empty()) return;
    current();
    for (std::size_t k = 0; k < m.drives.size(); ++k) {
      const Drive& d = m.drives[k];
      const Vec3 p = d.path.position(t), u = d.path.velocity(t);
      driven_[k] = {d.point,    float(p.x), float(p.y), float(p.z),
                    float(u.x), float(u.y), float(u.z)};
    }
    glNamedBufferSubData(buffer(Buf::driven), 0, GLsizeiptr(driven_.size() * sizeof(DrivenPoint)),
                         driven_.data());
    bind();
    drive_.run(GLuint(driven_.size()));
  }

  void evaluate(const Model& m, double t) override {
    current();
    bind();
    wind_faces(m, t);
    forces_.set("u_gravity", m.fields.gravity);
    forces_.set("u_drag", float(m.fields.air_drag));
    forces_.set_flag("u_wind", wind_);
    if (structured_) {  // the grids by stencil, the points between them by their adjacency
      for (const GpuStructured::Range& r : structured_->general_ranges()) {
        forces_.set("u_base", GLuint(r.first));
        forces_.run(r.count);
      }
      forces_.set("u_base", GLuint(0));  // a later caller of the kernel runs from point 0
      structured_->evaluate(m.fields.gravity, float(m.fields.air_drag), wind_);
    } else {
      forces_.set("u_base", GLuint(0));
      forces_.run(points_);
    }
    for (const auto& st : stages_) st->evaluate(t);  // Phase::forces stages: added into f
  }

  bool steps(const Integrator& scheme) const override {
    const ImplicitSettings* implicit = scheme.implicit_settings();
    return implicit && implicit->solver == ImplicitSolver::vbd;
  }

  DeviceImplicitStep implicit_step(const Model& m, const Integrator& scheme, double t, Real h,
                                   std::uint64_t step, bool measure,
                                   const ContactSet& contacts) override {
    if (!steps(scheme)) return Backend::implicit_step(m, scheme, t, h, step, measure, contacts);
    current();
    bind();
    wind_faces(m, t);  // f_ext at the step's start
    if (!vbd_) vbd_ = std::make_unique<GpuVbd>(max_block_);
    if (vbd_stale_) {
      vbd_->load(m, vbd_memory_, kinds_, cpu_stages_);
      vbd_stale_ = false;
    }
    return vbd_->step(m, *scheme.implicit_settings(), t, h, step, wind_, measure, contacts);
  }

 private:
  // The wind's force on each face at t (FaceForces), when the model has wind.
  void wind_faces(const Model& m, double t) {
    if (wind_) {
      const WindField& w = m.fields.wind;
      const gust::Basis b = gust::basis(w, t);
      faces_.set("u_mean", b.mean);
      faces_.set("u_coef", float(w.density * w.drag_coefficient / Real(12)));
      faces_.set_flag("u_gusty", !b.steady);
      faces_.set("u_k_along", b.k_along);
      faces_.set("u_k_across", b.k_across);
      // The phases grow with time: reduced in double here, so the GPU's float keeps its digits.
      float phase[4];
      for (int k = 0; k < 4; ++k) phase[k] = float(b.phase[k] - std::nearbyint(b.phase[k]));
      faces_.set("u_phase", phase);
      faces_.set("u_along", b.along);
      faces_.set("u_across1", b.across1);
      faces_.set("u_across2", b.across2);
      faces_.run(faces_count_);
    }
  }

 public:
  void integrate(Real kick, Real drift, std::uint64_t step) override {
    current();
    bind();
    integrate_.set("u_kick", float(kick));
    integrate_.set("u_drift", float(drift));
    integrate_.set("u_step", GLuint(std::min<std::uint64_t>(step, 0xfffffffeu)));
    integrate_.run(points_);
  }

  std::uint64_t first_non_finite() override {
    current();
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::uint32_t first = 0;
    glGetNamedBufferSubData(buffer(Buf::health), 0, 4, &first);
    return first == 0xffffffffu ? 0 : first;
  }

  void download(State& s) override {
    current();
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> tmp(3 * std::size_t(points_));
    const auto bytes = GLsizeiptr(tmp.size() * sizeof(float));
    glGetNamedBufferSubData(buffer(Buf::x), 0, bytes, tmp.data());
    unpack(tmp, s.x());
    glGetNamedBufferSubData(buffer(Buf::v), 0, bytes, tmp.data());
    unpack(tmp, s.v());
    glGetNamedBufferSubData(buffer(Buf::f), 0, bytes, tmp.data());
    unpack(tmp, s.f());
    if (vbd_ && !vbd_stale_) vbd_->download_memory(s);  // the guess's memory, as the CPU keeps it
  }

  void finish() override {
    current();
    glFinish();
  }

  // Shared only when the backend runs in the caller's context.
  std::uint32_t gl_positions() const override { return own_ ? 0 : buffer(Buf::x); }

  std::optional<SelfCollisionDebug> self_collision_debug() {
    for (const auto& st : stages_)
      if (const auto* sc = dynamic_cast<const GpuSelfCollision*>(st.get())) {
        current();
        return sc->debug();
      }
    return std::nullopt;
  }

  GridLayout layout() const { return layout_; }
  std::vector<StructuredGridInfo> structured_grids() const {
    return structured_ ? structured_->grids() : std::vector<StructuredGridInfo>{};
  }

 private:
  void current() {
    if (own_) own_->make_current();
  }
  GLuint buffer(Buf b) const { return buffers_[unsigned(b)]; }

  template <class T>
  void upload(Buf b, const std::vector<T>& data) {
    gpu::upload(buffer(b), data);
  }

  // The renderer shares the context and binds its own buffers to low bindings: ours are bound
  // again before every pass.
  void bind() {
    for (unsigned k = 0; k < kBufferCount; ++k)
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, k, buffers_[k]);
  }

  std::unique_ptr<render::HeadlessContext> own_;
  std::array<GLuint, kBufferCount> buffers_{};
  Kernel forces_, faces_, integrate_, drive_;
  std::string forces_source_;
  std::uint32_t points_ = 0, faces_count_ = 0;
  bool wind_ = false;
  std::vector<DrivenPoint> driven_;
  double max_invocations_ = 0;
  double max_block_ = 0;  // bytes, the largest storage block this driver binds
  std::vector<std::unique_ptr<GpuStage>> stages_;  // device versions of the installed stages
  std::vector<const Stage*> cpu_stages_;           // the installed stages (VBD's obstacles)
  // Implicit Euler by VBD: made at the first implicit step, loaded again after every load.
  std::unique_ptr<GpuVbd> vbd_;
  bool vbd_stale_ = true;
  std::vector<KindLaw> kinds_;           // the model's kinds, as the kernels call them
  std::vector<StageMemory> vbd_memory_;  // the guess's memory the last load brought
  GridLayout layout_ = GridLayout::automatic;
  std::unique_ptr<GpuStructured> structured_;  // null: every point runs the general kernel
};

}  // namespace

void register_backend() {
  if (BackendRegistry::global().find(to_string(BackendKind::gpu))) return;  // once per process
  BackendRegistry::global().add({std::string(to_string(BackendKind::gpu)),
                                 std::string(doc_of(BackendKind::gpu)),
                                 [](const BackendOptions& o) -> std::unique_ptr<Backend> {
                                   return std::make_unique<GpuBackend>(o);
                                 }});
}

std::optional<SelfCollisionDebug> self_collision_debug(Backend& b) {
  auto* gpu = dynamic_cast<GpuBackend*>(&b);
  return gpu ? gpu->self_collision_debug() : std::nullopt;
}

GridLayout grid_layout(Backend& b) {
  auto* gpu = dynamic_cast<GpuBackend*>(&b);
  return gpu ? gpu->layout() : GridLayout::general;
}

std::vector<StructuredGridInfo> structured_grids(Backend& b) {
  auto* gpu = dynamic_cast<GpuBackend*>(&b);
  return gpu ? gpu->structured_grids() : std::vector<StructuredGridInfo>{};
}

}  // namespace maille::gpu
