// Keys of the scene's own tables (scene_keys.hpp), in the order the reader reads them.
#include "scene_keys.hpp"

#include <array>
#include <cctype>
#include <iterator>
#include <sstream>
#include <vector>

#include "maille/backend.hpp"
#include "maille/integrator.hpp"
#include "maille/limits.hpp"
#include "maille/shape_keys.hpp"

namespace maille {

namespace {

// A scene name becomes a directory under out/: no separators, no "..", nothing hidden.
bool safe_name(const std::string& name) {
  if (name.empty() || name.size() > 200 || name[0] == '.') return false;
  for (const char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      return false;
  return true;
}

void check_scene_name(SceneTable& t, const Scene& s) {
  if (!s.name.empty() && !safe_name(s.name))
    t.fail("name", "'" + s.name +
                       "' names the output directory: use letters, digits, '_', '-' and "
                       "'.' only, not starting with '.'");
}

void check_integrator(SceneTable& t, const SimulationSettings& s) {
  if (!IntegratorRegistry::builtin().find(s.integrator))
    t.fail("integrator", "unknown integrator '" + s.integrator +
                             "' (known: " + IntegratorRegistry::builtin().names() + ")");
}

void check_steps(SceneTable& t, const SimulationSettings& s) {
  if (s.duration / s.step > double(limits::max_steps)) {
    std::ostringstream why;
    why << "duration / step = " << s.duration / s.step << " steps, more than the limit of "
        << double(limits::max_steps);
    t.fail(t.has("duration") ? "duration" : "step", why.str());
  }
}

void check_axis(SceneTable& t, const DrivePath& p) {
  if (norm(p.axis) == 0) t.fail("axis", "must not be zero");
}

}  // namespace

std::span<const StageKey<Scene>> scene_keys() {
  static const std::array<StageKey<Scene>, 2> keys{
      checked(text<&Scene::name>(
                  "name", {.doc = "used for the default output directory `out/NAME`: letters, "
                                  "digits, `_`, `-` and `.` only, not starting with `.`",
                           .default_doc = "the file name without extension"}),
              check_scene_name),
      text<&Scene::description>("description", {.doc = "shown by `maille info`"}),
  };
  return keys;
}

std::span<const StageKey<SimulationSettings>> simulation_keys() {
  using S = SimulationSettings;
  static const std::array<StageKey<S>, 10> keys = [] {
    auto integrator = checked(
        text<&S::integrator>("integrator", {.doc = "time-integration scheme"}), check_integrator);
    integrator.type = KeyType::choice;  // a registry's names (IntegratorRegistry)
    integrator.choices = [] { return IntegratorRegistry::builtin().names(); };
    return std::array<StageKey<S>, 10>{
        integrator,
        number<&S::step>("step", Bound::positive, limits::min_step, limits::max_duration,
                         {.unit = "s",
                          .doc = "time step h; `maille info` shows the largest stable step",
                          .range_doc = "[1e-12, 1e9]"}),
        checked(number<&S::duration>(
                    "duration", Bound::positive, 0, limits::max_duration,
                    {.unit = "s",
                     .doc = "simulated time of `maille run` (unless `--steps`/`--duration`)",
                     .range_doc = "(0, 1e9], at most 1e12 steps"}),
                check_steps),
        integer<&S::publish_every>(
            "output_every", 1, kNeverEvery,
            {.unit = "steps", .doc = "steps between published frames", .range_doc = ">= 1"}),
        integer<&S::sample_every>("sample_every", 0, kNeverEvery,
                                  {.unit = "steps",
                                   .doc = "steps between energy samples (rows of stats.csv); 0: "
                                          "`output_every`",
                                   .range_doc = ">= 0"}),
        integer<&S::threads>(
            "threads", 0, 1024,
            {.doc = "0: chosen during the run: every 0.25 s the cores free are asked again (the "
                    "cores it may run on less the other tasks runnable in the last samples of "
                    "/proc/stat); one free core gives one thread; with more, a few steps are "
                    "timed on one thread and on the free cores and the faster kept (again when "
                    "the free count changes, and every 10 s). It starts with one thread below "
                    "4096 points, else the cores free. Results are the same whatever the count",
             .range_doc = "[0, 1024]"}),
        named_text<BackendKind, &S::backend>(
            "backend",
            {.doc = "where the step runs: `cpu` (every stage and scheme, double precision, "
                    "OpenMP) or `gpu` (OpenGL 4.5 compute shaders, float: link forces of every "
                    "built-in kind but `friction`, gravity, drag, wind, driven points, conditional "
                    "contacts, "
                    "`[self_collision]` with `primitive = \"points\"` and `broad_phase = "
                    "\"uniform\"`, `[[obstacle]]` with `method = \"geometric\"` (every shape, "
                    "motion, friction), `leapfrog`, `symplectic_euler`, and `implicit_euler` "
                    "with `solver = \"vbd\"` and `coarse = \"off\"` (geometric obstacles, "
                    "`[self_collision]` with either primitive and `[[contact]]` inside its "
                    "solve); a stage or scheme it lacks is refused by name). "
                    "`--backend` overrides it; see docs/gpu.md"}),
        integer<&S::backend_options, &BackendOptions::device>(
            "gpu_device", -1, 64,
            {.doc = "the EGL device the `gpu` backend uses (`maille info --backend gpu` lists "
                    "them); -1: Mesa's surfaceless platform (a GPU Mesa drives, else llvmpipe). "
                    "`--gpu-device` overrides it",
             .range_doc = "[-1, 64]"}),
        number<&S::runaway_factor>("runaway_factor", Bound::positive, 0, 0,
                                   {.doc = "blow-up when kinetic + elastic energy exceeds this "
                                           "times the scene's energy scale"}),
        subtable<&implicit_keys, &S::implicit>(
            "implicit", {.doc = "implicit Euler's solver: `[simulation.implicit]` below",
                         .default_doc = "defaults"}),
    };
  }();
  return keys;
}

std::span<const StageKey<Fields>> fields_keys() {
  static const std::array<StageKey<Fields>, 3> keys{
      vector<&Fields::gravity>("gravity",
                               {.unit = "m/s^2", .doc = "g: force m g on every free point"}),
      number<&Fields::air_drag>(
          "air_drag", Bound::non_negative, 0, limits::max_stiffness,
          {.unit = "1/s", .doc = "γ: force −γ m v on every free point", .range_doc = ">= 0"}),
      subtable<&wind_keys, &Fields::wind>(
          "wind",
          {.doc = "wind on the surface's faces: `[fields.wind]` below", .default_doc = "none"}),
  };
  return keys;
}

std::span<const StageKey<PointTable>> point_keys() {
  using P = PointTable;
  static const std::array<StageKey<P>, 5> keys{
      text<&P::name>("name", {.doc = "name to refer to the point; also a one-point group",
                              .default_doc = "none",
                              .range_doc = "unique, no `:`"}),
      vector<&P::position>("position", {.unit = "m", .doc = "initial position", .required = true}),
      number<&P::mass>("mass", Bound::positive, limits::min_mass, limits::max_mass,
                       {.unit = "kg",
                        .doc = "mass (a fixed point keeps it for display only)",
                        .range_doc = "[1e-12, 1e12]"}),
      vector<&P::velocity>("velocity",
                           {.unit = "m/s", .doc = "initial velocity (`[[mass]]` only)"}),
      custom<P>("drive", KeyType::table,
                {.doc = "`[[fixed]]` only: a scripted path, see below", .default_doc = "none"}),
  };
  return keys;
}

std::span<const StageKey<DrivePath>> drive_keys() {
  using D = DrivePath;
  static const std::array<StageKey<D>, 9> keys{
      parsed_choice<&D::kind>("path", {.doc = "the path's shape"}),
      number<&D::phase>("phase", Bound::any, 0, 0,
                        {.unit = "rad", .methods = "sine, circle", .doc = "phase φ"}),
      vector<&D::amplitude>("amplitude", {.unit = "m",
                                          .methods = "sine",
                                          .doc = "`x(t) = x0 + A (sin(2π f t + φ) − sin φ)`",
                                          .required = true}),
      checked(number<&D::frequency>("frequency", Bound::positive, 0, 0,
                                    {.unit = "Hz",
                                     .methods = "sine, circle, rotate",
                                     .doc = "f: oscillations or turns per second",
                                     .range_doc = "(0, 1e6] (sine, circle); > 0 (rotate)",
                                     .required = true}),
              [](SceneTable& t, const D& p) {
                // The rotate path has never had an upper bound: kept so.
                if (p.kind != D::Kind::rotate)
                  t.check_range("frequency", p.frequency, 0, 1e6, "Hz");
              }),
      number<&D::radius>("radius", Bound::positive, 0, limits::max_coordinate,
                         {.unit = "m",
                          .methods = "circle",
                          .doc = "circle of radius r in the plane ⟂ `axis`, starting at x0",
                          .required = true}),
      checked(vector<&D::axis>("axis", {.methods = "circle, rotate",
                                        .doc = "circle or rotation axis",
                                        .range_doc = "non-zero"}),
              check_axis),
      custom<D>("keys", KeyType::custom,
                {.unit = "s, m",
                 .methods = "keyframes",
                 .doc = "offsets from x0, times increasing; linear in between, held at the ends",
                 .default_doc = "required",
                 .range_doc = "at least 2 keys, within ±1e6",
                 .type_doc = "array of `[t, x, y, z]`"}),
      vector<&D::center>("center",
                         {.unit = "m", .methods = "rotate", .doc = "a point of the rotation axis"}),
      number<&D::length>(
          "length", Bound::non_negative, 0, 0,
          {.unit = "m",
           .methods = "rotate",
           .doc = "0 for a rigid rotation at f turns per second; else a twist: each point turns "
                  "at f times its axial coordinate from `center` over `length` (clamped to ±1): "
                  "points at the center stay, points `length` away turn fully (wringing)"}),
  };
  return keys;
}

std::span<const StageKey<LinkTable>> link_keys() {
  using L = LinkTable;
  static const std::array<StageKey<L>, 3> keys{
      text<&L::kind>("kind", {.doc = "a registered link kind (the `[[link]] kinds` table "
                                     "below, generated from the registry), or "
                                     "`geometric_contact` (below)",
                              .required = true}),
      point_reference<L>("a",
                         {.doc = "the first point: `\"name\"`, `\"group:index\"` or a global index",
                          .default_doc = "required"}),
      point_reference<L>(
          "b", {.doc = "the second point, as `a`; distinct from it", .default_doc = "required"}),
  };
  return keys;
}

namespace {
// Where a geometric point's table holds its shape (shape_keys.hpp).
struct GeometricPointShape {
  static auto& kind(auto& g) { return g.point.shape; }
  static auto& parameter(auto& g) { return g.point.shape_parameter; }
  static bool canonical(const GeometricPointTable&) { return true; }
};
}  // namespace

std::span<const StageKey<GeometricPointTable>> geometric_point_keys() {
  using G = GeometricPointTable;
  static const std::vector<StageKey<G>> keys = [] {
    std::vector<StageKey<G>> out{
        // Read first: the reader checks it is unique before the others are read.
        read_first(text<&G::point, &GeometricPoint::name>(
            "name", {.doc = "unique among geometric points; links refer to it", .required = true})),
        shape_key<G, GeometricPointShape>({.doc = "as `[[obstacle]]`"}),
    };
    for (auto& k : shape_parameter_keys<G, GeometricPointShape>()) out.push_back(k);
    const StageKey<G> placement[] = {
        vector<&G::position>("position", {.unit = "m", .doc = "translation t"}),
        vector<&G::rotation>("rotation",
                             {.unit = "degrees", .doc = "about x, then y, then z (R = Rz Ry Rx)"}),
        checked(vector<&G::scale>("scale", {.doc = "scale factors S along the shape's axes",
                                            .range_doc = "> 1e-9 each"}),
                [](SceneTable& t, const G& g) {
                  if (!(g.scale.x > 1e-9 && g.scale.y > 1e-9 && g.scale.z > 1e-9))
                    t.fail("scale", "every component must be > 1e-9 (M_i divides by it)");
                }),
    };
    out.insert(out.end(), std::begin(placement), std::end(placement));
    return out;
  }();
  return keys;
}

std::span<const StageKey<GeometricContactTable>> geometric_contact_keys() {
  using G = GeometricContactTable;
  static const std::array<StageKey<G>, 5> keys{
      text<&G::a>("a", {.doc = "a `[[geometric_point]]`'s name", .required = true}),
      number<&G::contact, &GeometricContact::stiffness>(
          "stiffness", Bound::non_negative, 0, limits::max_stiffness,
          {.unit = "N/m",
           .doc = "k (through M_d: k times the world penetration)",
           .required = true}),
      number<&G::contact, &GeometricContact::damping>(
          "damping", Bound::non_negative, 0, limits::max_stiffness,
          {.unit = "N.s/m", .doc = "z, along the normal"}),
      choice<&G::normal>("normal", {.doc = "the canonical shape's normal mapped to the world, or "
                                           "the world gradient's"}),
      point_reference<G>("b", {.doc = "a free mass (`\"name\"`, `\"group:index\"`, an index) "
                                      "or a group's name: one contact per free point of the group",
                               .default_doc = "required"}),
  };
  return keys;
}

std::span<const StageKey<ObstacleMotion>> motion_keys() {
  using O = ObstacleMotion;
  static const std::array<StageKey<O>, 7> keys{
      parsed_choice<&O::kind>("path",
                              {.doc = "how the obstacle moves", .default_doc = "`\"rotate\"`"}),
      checked(
          vector<&O::axis>(
              "axis", {.methods = "rotate", .doc = "the rotation axis", .range_doc = "non-zero"}),
          [](SceneTable& t, const O& o) {
            if (norm(o.axis) == 0) t.fail("axis", "must not be zero");
          }),
      vector<&O::center>("center", {.unit = "m",
                                    .methods = "rotate",
                                    .doc = "a point of the axis",
                                    .default_doc = "the obstacle's `position`"}),
      number<&O::frequency>("frequency", Bound::positive, 0, 1e6,
                            {.unit = "Hz",
                             .methods = "rotate, oscillate",
                             .doc = "turns per second, or oscillations",
                             .required = true}),
      vector<&O::velocity>("velocity",
                           {.unit = "m/s", .methods = "translate", .doc = "x(t) = x + v t"}),
      vector<&O::amplitude>(
          "amplitude",
          {.unit = "m", .methods = "oscillate", .doc = "x(t) = x + A (sin(2π f t + φ) − sin φ)"}),
      number<&O::phase>("phase", Bound::any, 0, 0,
                        {.unit = "rad", .methods = "oscillate", .doc = "φ"}),
  };
  return keys;
}

}  // namespace maille
