// maille.Model: a model built in code. Points and links go straight into a C++ Model, in the
// order they are added (indices are what add_point returns); builders ([[flag]], [[rope]], ...)
// are read from a one-table scene, so their keys, defaults and checks are the scene file's, and
// the result is appended. `simulation.*` and `fields.*` keys are kept as overrides and read the
// same way when a Simulation is made (fields default as in a scene file).
#include <cctype>
#include <cmath>
#include <limits>

#include "bindings.hpp"
#include "maille/limits.hpp"
#include "maille/link_registry.hpp"
#include "maille/stage_registry.hpp"

namespace maille::python {

namespace {

const LinkKindRegistry& kinds() {
  static const LinkKindRegistry k = LinkKindRegistry::with_builtins();
  return k;
}

Vec3 vec3_arg(const py::handle& value, const std::string& where, const std::string& key) {
  std::vector<double> v;
  const py::object seq = py::hasattr(value, "tolist") ? value.attr("tolist")()
                                                      : py::reinterpret_borrow<py::object>(value);
  if (py::isinstance<py::str>(seq) || py::isinstance<py::bytes>(seq) ||
      !py::isinstance<py::sequence>(seq))
    throw py::type_error(where + ": argument '" + key + "' must be a sequence of 3 numbers (got " +
                         py::str(value.get_type().attr("__name__")).cast<std::string>() + ")");
  for (const auto& item : seq.cast<py::sequence>()) {
    if (v.size() > 3) break;
    v.push_back(real_arg(item, where, key));
  }
  if (v.size() != 3)
    fail(where, key, "must have 3 components (got " + std::to_string(v.size()) + ")");
  for (double c : v)
    if (!std::isfinite(c) || std::abs(c) > double(limits::max_coordinate))
      fail(where, key,
           "every component must be finite and within +-1e6 (got " + std::to_string(c) + ")");
  return {Real(v[0]), Real(v[1]), Real(v[2])};
}

Real mass_arg(double mass, const std::string& where) {
  if (!(mass > 0) || !std::isfinite(mass))
    fail(where, "mass", "must be > 0 and finite (got " + std::to_string(mass) + ")");
  if (mass < double(limits::min_mass) || mass > double(limits::max_mass))
    fail(where, "mass", "must be in [1e-12, 1e12] kg (got " + std::to_string(mass) + ")");
  return Real(mass);
}

void claim_name(CodeModel& cm, const std::string& name, const std::string& where) {
  if (name.empty() || name.find(':') != std::string::npos)
    fail(where, "name", "must be a non-empty name without ':'");
  if (cm.model.group(name)) fail(where, "name", "duplicate name '" + name + "'");
}

std::uint32_t add_point(CodeModel& cm, PointKind kind, const py::handle& position,
                        const py::handle& mass_object, const py::handle& velocity,
                        const py::object& name, const std::string& where) {
  const double mass = real_arg(mass_object, where, "mass");
  if (cm.model.points.size() >= limits::max_points)
    fail(where, "position", "the model already has the most points allowed (2^28)");
  const Vec3 x = vec3_arg(position, where, "position");
  const Vec3 v = velocity.is_none() ? Vec3{} : vec3_arg(velocity, where, "velocity");
  const Real m = mass_arg(mass, where);
  std::string label;
  if (!name.is_none()) {
    label = str_of(name, where, "name");
    claim_name(cm, label, where);
  }
  const std::uint32_t i = cm.model.points.add(kind, m, x, v);
  if (!label.empty()) cm.model.groups.push_back({label, "point", i, 1});
  return i;
}

std::uint32_t point_arg(const CodeModel& cm, const py::handle& ref, const std::string& where,
                        const std::string& key) {
  const std::uint32_t n = cm.model.points.size();
  if (py::isinstance<py::str>(ref)) {  // a name, or "group:index" as in scene files
    const std::string text = str_of(ref, where, key);
    const auto colon = text.find(':');
    const Group* g = cm.model.group(text.substr(0, colon));
    if (!g) fail(where, key, "no point or group named '" + text.substr(0, colon) + "'");
    if (colon == std::string::npos) {
      if (g->count != 1) fail(where, key, "'" + text + "' is a group: use '" + text + ":index'");
      return g->first;
    }
    long long i = -1;
    try {
      std::size_t used = 0;
      i = std::stoll(text.substr(colon + 1), &used);
      if (used != text.size() - colon - 1) i = -1;
    } catch (const std::exception&) {
    }
    if (i < 0 || i >= g->count)
      fail(where, key,
           "'" + text + "': index must be in [0, " + std::to_string(g->count - 1) + "]");
    return g->first + static_cast<std::uint32_t>(i);
  }
  if (py::isinstance<py::bool_>(ref) || !PyIndex_Check(ref.ptr()))
    throw py::type_error(where + ": argument '" + key +
                         "' must be a point index (int) or a point name (str), got " +
                         py::str(ref.get_type().attr("__name__")).cast<std::string>());
  const long long i = int_arg(ref, where, key);
  if (i < 0 || i >= n)
    fail(where, key,
         "point index " + std::to_string(i) + " does not exist (the model has " +
             std::to_string(n) + " points)");
  return static_cast<std::uint32_t>(i);
}

// A link of any registered kind; parameters by the kind's field names, checked and defaulted
// as the scene reader does for [[link]] tables.
std::uint32_t add_link(CodeModel& cm, const py::object& kind_object, const py::handle& a_ref,
                       const py::handle& b_ref, const py::kwargs& params) {
  const std::string where = "<maille.Model.add_link>";
  const std::string kind = str_of(kind_object, where, "kind");
  if (kind == "geometric_contact")
    fail(where, "kind",
         "geometric contacts link [[geometric_point]] shapes, which a model built in code does not "
         "have: use a scene file");
  const LinkKindRegistry::Entry* entry = kinds().find(kind);
  if (!entry)
    fail(where, "kind", "unknown link kind '" + kind + "' (known: " + kinds().names() + ")");
  const std::uint32_t a = point_arg(cm, a_ref, where, "a"), b = point_arg(cm, b_ref, where, "b");
  if (a == b) fail(where, "b", "a link needs two different points");
  std::vector<std::string> known;
  for (const auto& f : entry->fields) known.push_back(f.name);
  for (const auto& [k, v] : params) {
    const std::string name = py::str(k).cast<std::string>();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const auto& n : known) list += (list.empty() ? "" : ", ") + n;
      fail(where, name,
           "a " + kind + " link has no parameter '" + name + "' (it has: " + list + ")");
    }
  }
  std::vector<Real> values(entry->fields.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    const ParamInfo& f = entry->fields[k];
    if (params.contains(f.name.c_str())) {
      const double v = real_arg(params[f.name.c_str()], where, f.name);
      if (!std::isfinite(v)) fail(where, f.name, "must be finite (got " + std::to_string(v) + ")");
      if (f.bound == Bound::positive && !(v > 0))
        fail(where, f.name, "must be > 0 (got " + std::to_string(v) + ")");
      if (f.bound == Bound::non_negative && !(v >= 0))
        fail(where, f.name, "must be >= 0 (got " + std::to_string(v) + ")");
      const double most = double(limits::max_parameter(f.unit));
      if (std::abs(v) > most)
        fail(where, f.name, "must be within +-" + std::to_string(most) + " " + f.unit);
      values[k] = Real(v);
    } else if (f.default_value) {
      values[k] = *f.default_value;
    } else if (f.default_is_distance) {
      values[k] = norm(cm.model.points.initial_position[b] - cm.model.points.initial_position[a]);
    } else if (f.default_from.empty()) {
      fail(where, f.name, "is required for a " + kind + " link");
    }
  }
  for (std::size_t k = 0; k < values.size(); ++k)  // defaults taken from another field
    if (!entry->fields[k].default_from.empty() && !params.contains(entry->fields[k].name.c_str()))
      for (std::size_t j = 0; j < values.size(); ++j)
        if (entry->fields[j].name == entry->fields[k].default_from) values[k] = values[j];
  LinkPoolBase* pool = cm.model.links.find(kind);
  if (!pool) pool = &cm.model.links.adopt(entry->make_pool());
  const auto id = static_cast<std::uint32_t>(pool->size());
  pool->add_generic({a, b}, values);
  return id;
}

// Appends `part` (a model read from a one-builder scene) to cm's model: points, links, faces,
// drives and groups, with point indices shifted.
void append(CodeModel& cm, const Model& part) {
  Model& m = cm.model;
  const std::uint32_t offset = m.points.size();
  const PointPool& p = part.points;
  for (std::uint32_t i = 0; i < p.size(); ++i)
    m.points.add(p.kind[i], p.mass[i], p.initial_position[i], p.initial_velocity[i]);
  for (const auto& pool : part.links.pools()) {
    LinkPoolBase* into = m.links.find(pool->keyword());
    if (!into) into = &m.links.adopt(kinds().find(pool->keyword())->make_pool());
    const std::size_t fields = pool->fields().size();
    std::vector<Real> values(fields);
    for (std::size_t id = 0; id < pool->size(); ++id) {
      const LinkEnds e = pool->ends(id);
      for (std::size_t k = 0; k < fields; ++k) values[k] = pool->param(id, k);
      into->add_generic({e.a + offset, e.b + offset}, values);
    }
  }
  for (auto t : part.surface.triangles) {
    for (auto& i : t) i += offset;
    m.surface.triangles.push_back(t);
  }
  for (Drive d : part.drives) {
    d.point += offset;
    m.drives.push_back(d);
  }
  for (Group g : part.groups) {
    g.first += offset;
    m.groups.push_back(g);
  }
}

bool bare_key(const std::string& key) {
  if (key.empty()) return false;
  for (const char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

py::array_t<std::int64_t> indices(const Group& g) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(g.count));
  auto w = out.mutable_unchecked<1>();
  for (std::uint32_t i = 0; i < g.count; ++i) w(i) = g.first + i;
  return out;
}

// A builder table ([[flag]], [[rope]], ...) from keyword arguments, read as a one-table scene.
py::array_t<std::int64_t> build(CodeModel& cm, const py::object& keyword_object,
                                const py::object& name, const py::kwargs& params) {
  const std::string keyword = str_of(keyword_object, "<maille.Model.build>", "builder");
  if (!bare_key(keyword))
    fail("<maille.Model.build>", "builder", "'" + keyword + "' is not a builder");
  const std::string where = "<maille.Model." + keyword + ">";
  const std::string label = name.is_none() ? keyword + std::to_string(cm.model.groups.size())
                                           : str_of(name, where, "name");
  claim_name(cm, label, where);
  std::string text = "[[" + keyword + "]]\nname = " + toml_value(py::str(label), "name") + "\n";
  for (const auto& [k, v] : params) {
    const std::string key = py::str(k).cast<std::string>();
    // A bare TOML key only: a newline or '=' in it would write other keys than the one named.
    if (!bare_key(key)) fail(where, key, "is not a key of [[" + keyword + "]]");
    text += key + " = " + toml_value(v, keyword + "." + key) + "\n";
  }
  static const StageRegistry stages = StageRegistry::with_builtins();
  const Scene part = value_or_throw(parse_scene(text, where, kinds(), stages));
  if (part.model.groups.empty()) fail(where, "", "'" + keyword + "' is not a builder");
  if (double(cm.model.points.size()) + part.model.points.size() > double(limits::max_points))
    fail(where, "", "the model would have more than 2^28 points");
  // Appended to a copy, swapped in whole: running out of memory half-way (MemoryError) leaves
  // the model as it was, not with half a flag.
  Model grown = cm.model;
  std::swap(grown, cm.model);
  try {
    append(cm, part.model);
  } catch (...) {
    std::swap(grown, cm.model);
    throw;
  }
  return indices(cm.model.groups.back());
}

py::dict groups_of(const Model& m) {
  py::dict out;
  for (const auto& g : m.groups) out[py::str(g.name)] = indices(g);
  return out;
}

}  // namespace

void bind_model(py::module_& mod) {
  auto cls = py::class_<CodeModel>(mod, "Model", R"(A model built in code.

Points and links are added in order (add_point returns the point's index); builders add
the same structures as a scene file's [[flag]], [[rope]], [[net]], [[membrane]], [[lattice]]
and [[floor]] tables, with the same keys and defaults. Fields default as in a scene file
(gravity -9.81 m/s^2 along y); change them with set("fields.gravity", [0, -1.6, 0]).
Make a simulation with maille.Simulation(model, step=1e-4).)");
  cls.def(py::init<>());
  cls.def(
      "add_point",
      [](CodeModel& cm, const py::object& position, const py::object& mass,
         const py::object& velocity, const py::object& name) {
        return add_point(cm, PointKind::free, position, mass, velocity, name,
                         "<maille.Model.add_point>");
      },
      py::arg("position"), py::arg("mass") = py::float_(1.0), py::arg("velocity") = py::none(),
      py::arg("name") = py::none(),
      "Adds a free point (a mass, kg) at `position` (m) with `velocity` (m/s); returns its index.");
  cls.def(
      "add_fixed_point",
      [](CodeModel& cm, const py::object& position, const py::object& mass,
         const py::object& name) {
        return add_point(cm, PointKind::fixed, position, mass, py::none(), name,
                         "<maille.Model.add_fixed_point>");
      },
      py::arg("position"), py::arg("mass") = py::float_(1.0), py::arg("name") = py::none(),
      "Adds a fixed point at `position` (m); returns its index.");
  cls.def("add_link", &add_link, py::arg("kind"), py::arg("a"), py::arg("b"),
          "add_link(kind, a, b, **params): a link of a registered kind between points a and b "
          "(indices, names or \"group:index\"), parameters by the kind's field names "
          "(spring_damper: stiffness, rest_length, damping); omitted ones default as the kind "
          "declares (rest_length: the distance between the points). Returns the link's id "
          "within its kind.");
  cls.def("build", &build, py::arg("builder"), py::arg("name") = py::none(),
          "build(builder, name=None, **keys): a builder table (flag, rope, net, membrane, "
          "lattice, floor) with the scene file's keys; returns the index array of its points.");
  for (const char* keyword : {"flag", "rope", "net", "membrane", "lattice", "floor"}) {
    const std::string k = keyword;
    cls.def(("add_" + k).c_str(),
            [k](CodeModel& cm, const py::object& name, const py::kwargs& params) {
              return build(cm, py::str(k), name, params);
            },
            py::arg("name") = py::none(),
            ("add_" + k + "(name=None, **keys): a [[" + k +
             "]] of the scene format (docs/scene-format.md) with these keys; returns the index "
             "array of its points (also in groups[name]).")
                .c_str());
  }
  cls.def(
      "set",
      [](CodeModel& cm, const py::object& key_object, const py::object& value) {
        const std::string key = key_arg(key_object, "<maille.Model.set>", "key");
        if (key.rfind("fields.", 0) != 0 && key.rfind("simulation.", 0) != 0)
          fail("<maille.Model.set>", key,
               "a model built in code takes fields.* and simulation.* keys (points, links and "
               "builders are added by its methods)");
        std::vector<std::string> sets = cm.settings;
        merge_override(sets, override_text(key, value));
        settings_scene(sets);  // throws SceneError naming the key
        cm.settings = std::move(sets);
      },
      py::arg("key"), py::arg("value"),
      "Sets a fields.* or simulation.* key as in a scene file (validated now).");
  cls.def_property_readonly("point_count",
                            [](const CodeModel& cm) { return cm.model.points.size(); });
  cls.def_property_readonly("link_count",
                            [](const CodeModel& cm) { return cm.model.links.total(); });
  cls.def_property_readonly(
      "groups", [](const CodeModel& cm) { return groups_of(cm.model); },
      "dict: group name -> NumPy index array of its points");
  cls.def_property_readonly(
      "positions",
      [](const CodeModel& cm) {
        const auto& x = cm.model.points.initial_position;
        py::array_t<Real> out({static_cast<py::ssize_t>(x.size()), py::ssize_t{3}});
        std::copy_n(reinterpret_cast<const Real*>(x.data()), 3 * x.size(), out.mutable_data());
        return out;
      },
      "the initial positions, (n, 3), a copy");
  cls.def("__repr__", [](const CodeModel& cm) {
    return "<maille.Model: " + std::to_string(cm.model.points.size()) + " points, " +
           std::to_string(cm.model.links.total()) + " links>";
  });
}

// Exposed to simulation.cpp through bindings.hpp's groups accessor.
py::dict model_groups(const Model& m) {
  return groups_of(m);
}

}  // namespace maille::python
