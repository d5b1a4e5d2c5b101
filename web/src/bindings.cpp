// Embind: the Playground as the JavaScript class Module.Playground. Arrays go out as typed-array
// views on the WebAssembly heap (no copy): valid until the next call that may reallocate (a
// step does not move positions; load, set and reset may).
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <algorithm>
#include <cstdio>

#include "integrators/vbd_lanes.hpp"
#include "playground.hpp"

namespace maille::web {
namespace {

using emscripten::val;

val error_object(const InputError& e) {
  val o = val::object();
  o.set("line", e.line);
  o.set("column", e.column);
  o.set("key", e.key);
  o.set("message", e.message);
  o.set("text", e.to_string());
  return o;
}

val load_result(const LoadResult& r) {
  val o = val::object();
  o.set("ok", r.ok);
  o.set("error", r.ok ? val::null() : error_object(r.error));
  return o;
}

val load(Playground& p, const std::string& text, const std::string& source_name) {
  return load_result(p.load(text, source_name, {}));
}

val set(Playground& p, const std::string& key, const std::string& value) {
  return load_result(p.set(key, value));
}

double step(Playground& p, double n) {
  return double(p.step(std::uint64_t(n)));
}

val positions(Playground& p) {
  if (!p.loaded())
    return val(emscripten::typed_memory_view(std::size_t(0), static_cast<const double*>(nullptr)));
  const auto x = p.simulator().state().x();
  static_assert(sizeof(Vec3) == 3 * sizeof(Real));
  return val(emscripten::typed_memory_view(3 * x.size(), &x.data()->x));
}

std::string state_hash(Playground& p) {
  char s[17];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(p.state_hash()));
  return s;
}

val stats(Playground& p) {
  val o = val::object();
  if (!p.loaded()) return o;
  Simulator& sim = p.simulator();
  o.set("scene", p.scene().name);
  o.set("step", double(sim.steps_taken()));
  o.set("time", sim.time());
  o.set("h", sim.settings().step);
  o.set("points", sim.model().points.size());
  o.set("links", double(sim.model().links.total()));
  o.set("integrator", sim.settings().integrator);
  o.set("msPerStep", p.last_step_ms());
  o.set("threads", p.threads());
  o.set("vbdLanes", vbd_lane_width());  // VBD's sweeps: 2 lanes (f64x2) or 1 (scalar)
  if (!sim.blow_up()) {
    const Energies e = sim.energies();
    for_each_energy(e, [&](const char* name, double value) { o.set(name, value); });
    o.set("energy", e.total());  // the page's plot
  }
  if (const auto& b = sim.blow_up()) {
    val bo = val::object();
    bo.set("step", double(b->step));
    bo.set("time", b->time);
    bo.set("module", b->module);
    bo.set("message", b->message);
    o.set("blowUp", bo);
  } else {
    o.set("blowUp", val::null());
  }
  return o;
}

// Where the steps' time went since the load: ns per stage of the simulator's profile (the
// benchmark's breakdown of a step).
val profile(Playground& p) {
  val o = val::object();
  if (!p.loaded()) return o;
  for (const auto& s : p.simulator().profile().stages()) o.set(s.name, s.total_ns);
  return o;
}

// What the frame loop reads every frame, without the force pass stats() makes for the energies.
val timing(Playground& p) {
  val o = val::object();
  o.set("h", p.loaded() ? p.simulator().settings().step : 0.0);
  o.set("msPerStep", p.last_step_ms());
  o.set("blownUp", p.loaded() && p.simulator().blow_up().has_value());
  return o;
}

val topology(Playground& p) {
  const render::RenderTopology& t = p.topology();
  val o = val::object();
  o.set("triangles", val(emscripten::typed_memory_view(t.triangles.size(), t.triangles.data())));
  o.set("links", val(emscripten::typed_memory_view(t.link_ends.size(), t.link_ends.data())));
  o.set("linkOnSurface",
        val(emscripten::typed_memory_view(t.link_on_surface.size(), t.link_on_surface.data())));
  o.set("linkRest", val(emscripten::typed_memory_view(t.link_rest.size(), t.link_rest.data())));
  o.set("pointStyle",
        val(emscripten::typed_memory_view(t.point_style.size(), t.point_style.data())));
  o.set("pointRadius", t.point_radius);
  return o;
}

val normals(Playground& p) {
  const std::vector<float>& n = p.normals();
  return val(emscripten::typed_memory_view(n.size(), n.data()));
}

// The smooth surface's layout at a level of detail (the page's shader evaluates it): the grids
// as 4 uints each (first point, nx, ny, first vertex), the PN triangles' corners, the vertex
// count (grid vertices first) and the smooth mesh's triangles. Copies: made once per load.
val smooth_layout(Playground& p, int lod) {
  const SmoothSurface& s = p.smooth();
  lod = std::clamp(lod, 1, kMaxSmoothLod);
  std::vector<std::uint32_t> grids;
  for (const SmoothSurface::Grid& g : s.grids_at(lod))
    grids.insert(grids.end(), {g.first, g.nx, g.ny, g.vertex_offset});
  const std::vector<std::uint32_t> triangles =
      s.empty() ? std::vector<std::uint32_t>{} : s.triangles(lod);
  const auto u32 = [](const std::vector<std::uint32_t>& v) {
    return val::global("Uint32Array").new_(val(emscripten::typed_memory_view(v.size(), v.data())));
  };
  val o = val::object();
  o.set("lod", lod);
  o.set("grids", u32(grids));
  o.set("pnTriangles", u32(s.other_triangles()));
  o.set("gridVertices", s.empty() ? 0u : s.grid_vertices(lod));
  o.set("vertexCount", s.empty() ? 0u : s.vertex_count(lod));
  o.set("triangles", u32(triangles));
  return o;
}

val smooth_normals(Playground& p) {
  const std::vector<float>& n = p.smooth_normals();
  return val(emscripten::typed_memory_view(n.size(), n.data()));
}

val smooth_evaluate(Playground& p, int lod) {
  const SmoothMesh& m = p.smooth_evaluate(lod);
  return val(emscripten::typed_memory_view(m.vertices.size(), m.vertices.data()));
}

val solids(Playground& p) {
  val list = val::array();
  for (const Solid& s : p.solids()) {
    val o = val::object();
    o.set("name", s.name);
    o.set("vertices", val(emscripten::typed_memory_view(s.vertices.size(), s.vertices.data())));
    o.set("placement", val(emscripten::typed_memory_view(s.placement.size(), s.placement.data())));
    o.set("colour", val(emscripten::typed_memory_view(s.colour.size(), s.colour.data())));
    list.call<void>("push", o);
  }
  return list;
}

void grab(Playground& p, double point, double x, double y, double z) {
  p.grab(std::uint32_t(point), Vec3{Real(x), Real(y), Real(z)});
}
void move_to(Playground& p, double x, double y, double z) {
  p.move_to(Vec3{Real(x), Real(y), Real(z)});
}

val listened(Playground& p) {
  const std::vector<float> samples = p.take_listened();
  val o = val::object();
  o.set("channels", p.loaded() ? p.scene().audio.listeners.size() : 0);
  o.set("rate", p.audio_rate());  // samples per second: the scene's [audio] rate
  o.set("sampling", p.sampling());
  o.set("samples", val::global("Float32Array")
                       .new_(val(emscripten::typed_memory_view(samples.size(), samples.data()))));
  return o;
}

val declared_keys(Playground& p) {
  val list = val::array();
  for (const DeclaredKey& k : p.declared_keys()) {
    val o = val::object();
    o.set("key", k.key);
    o.set("value", k.value);
    o.set("integer", k.integer);
    list.call<void>("push", o);
  }
  return list;
}

val slider_keys(Playground& p) {
  val list = val::array();
  for (const SliderKey& k : p.slider_keys()) {
    val o = val::object();
    o.set("key", k.key);
    o.set("value", k.value);
    o.set("lo", k.lo);
    o.set("hi", k.hi);
    o.set("loOpen", k.lo_open);
    o.set("integer", k.integer);
    o.set("declared", k.declared);
    o.set("written", k.written);
    o.set("bound", k.bound);
    o.set("unit", k.unit);
    o.set("doc", k.doc);
    o.set("range", k.range);
    list.call<void>("push", o);
  }
  return list;
}

val scene_info(Playground& p) {
  val o = val::object();
  if (!p.loaded()) return o;
  o.set("name", p.scene().name);
  o.set("description", p.scene().description);
  o.set("text", p.text());
  val listeners = val::array();
  for (const audio::Listener& l : p.scene().audio.listeners) listeners.call<void>("push", l.label);
  o.set("listeners", listeners);
  return o;
}

// VBD's lane width for the next steps (1: the scalar sweep, 2: f64x2; 0: the default, the
// widest): the benchmark's comparison. False for a width this build cannot run.
bool set_vbd_lanes(int width) {
  return set_vbd_lane_width(width);
}

}  // namespace
}  // namespace maille::web

EMSCRIPTEN_BINDINGS(maille) {
  using namespace maille::web;
  emscripten::class_<Playground>("Playground")
      .constructor<>()
      .function("load", &load)
      .function("set", &set)
      .function("step", &step)
      .function("reset", &Playground::reset)
      .function("setThreads", &Playground::set_threads)
      .function("threads", &Playground::threads)
      .class_function("maxThreads", &Playground::max_threads)
      .class_function("setVbdLanes", &set_vbd_lanes)
      .function("positions", &positions)
      .function("stateHash", &state_hash)
      .function("stats", &stats)
      .function("timing", &timing)
      .function("profile", &profile)
      .function("topology", &topology)
      .function("normals", &normals)
      .function("solids", &solids)
      .function("smoothLayout", &smooth_layout)
      .function("smoothNormals", &smooth_normals)
      .function("smoothEvaluate", &smooth_evaluate)
      .function("grab", &grab)
      .function("moveTo", &move_to)
      .function("release", &Playground::release)
      .function("listened", &listened)
      .function("declaredKeys", &declared_keys)
      .function("sliderKeys", &slider_keys)
      .function("sceneInfo", &scene_info);
}
