// Scene files: TOML -> validated Model + SimulationSettings.
//
// Order of construction (point indices follow it): [[mass]] and [[fixed]] points in file order,
// then each builder keyword in the order of builder_tables() (flag, rope, net, membrane,
// lattice, floor), each in file order; then [[link]], then the gathered stage tables ([[contact]]:
// its links) and the other stage tables. Points are best referred
// to by name ("bob") or by group and index ("flag:17"); a bare integer is a global index.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "builder_tables.hpp"
#include "listen_table.hpp"
#include "maille/builders.hpp"
#include "maille/geometric_point.hpp"
#include "maille/group_contact.hpp"
#include "maille/limits.hpp"
#include "maille/scene.hpp"
#include "maille/stage_keys.hpp"
#include "overrides.hpp"
#include "point_ref.hpp"
#include "scene_digest.hpp"
#include "scene_keys.hpp"
#include "toml_cursor.hpp"
#include "toml_guard.hpp"

namespace maille {

namespace {

const StageRegistry& builtin_stages() {
  static const StageRegistry builtins = StageRegistry::with_builtins();
  return builtins;
}

class SceneReader {
 public:
  SceneReader(const LinkKindRegistry& kinds, const StageRegistry& stages, std::string file)
      : kinds_(kinds), stages_(stages), file_(std::move(file)) {}

  Scene read(const toml::table& root) {
    TomlCursor top(root, file_, "");
    Scene scene;
    if (auto t = top.table("scene")) {  // scene_keys.cpp declares every table's keys
      read_keys(*t, scene, scene_keys());
      t->finish();
    }
    if (auto t = top.table("simulation")) scene.settings = simulation(*t);
    if (auto t = top.table("fields")) scene.model.fields = fields(*t);
    for (auto& t : top.tables("mass")) point(t, scene.model, PointKind::free);
    for (auto& t : top.tables("fixed")) point(t, scene.model, PointKind::fixed);
    for (const auto& b : builder_tables())
      for (auto& t : top.tables(b.keyword)) builder(t, scene.model, b);
    for (auto& t : top.tables("geometric_point")) geometric_point(t, scene.model);
    std::vector<TomlCursor> links = top.tables("link");
    for (auto& t : links) link(t, scene.model);
    gathered_tables(top, scene.model);  // [[link]] kind = "geometric_contact", [[contact]]
    stage_tables(top, scene.model);
    scene.audio = read_audio_tables(top, scene.model);  // [[listen]], [audio]
    top.finish();
    if (scene.model.points.size() == 0)
      throw SceneFailure{{file_, 0, 0, "", "the scene has no point (add [[mass]] or a builder)"}};
    return scene;
  }

 private:
  // Tables registered by stages ([self_collision], [[obstacle]], ...), read against the
  // finished model; each yields a StageSpec that every simulator of the model installs.
  void stage_tables(TomlCursor& top, Model& model) {
    auto install = [&](TomlCursor& t, const StageRegistry::Entry& e) {
      StageSpec spec = e.parse(t, model);
      t.finish();
      model.stages.push_back(declared_stage(e, std::move(spec)));
    };
    for (const auto& e : stages_.entries()) {
      if (e.of_links && !e.gather)  // its [[link]] tables would be claimed and never read
        throw std::logic_error("the stage entry '" + e.table +
                               "' takes [[link]] tables (of_links) "
                               "but has no gather");
      if (e.gather) continue;  // gathered_tables()
      if (e.array) {
        for (auto& t : top.tables(e.table)) install(t, e);
      } else if (auto t = top.table(e.table)) {
        install(*t, e);
      }
    }
  }

  // Registered arrays whose elements make one stage together, and may add links ([[contact]]):
  // each read whole, before the other stage tables.
  void gathered_tables(TomlCursor& top, Model& model) {
    for (const auto& e : stages_.entries()) {
      if (!e.gather) continue;
      std::vector<TomlCursor> tables = e.of_links ? std::vector<TomlCursor>{} : top.tables(e.table);
      std::vector<SceneTable*> views =
          e.of_links ? claimed_links_[e.table] : std::vector<SceneTable*>{};
      for (TomlCursor& t : tables) views.push_back(&t);
      if (views.empty()) continue;
      std::optional<StageSpec> spec = e.gather(views, model);
      for (const SceneTable* t : views) t->finish();
      if (spec) model.stages.push_back(declared_stage(e, std::move(*spec)));
    }
  }

  // A registered table makes the stage its entry declares (StageTableEntry::stage): a spec
  // named otherwise is the entry's mistake, not the scene's.
  static StageSpec declared_stage(const StageRegistry::Entry& e, StageSpec spec) {
    if (!spec.name.starts_with(e.stage.name))
      throw std::logic_error("the table [" + e.table + "] made a stage named '" + spec.name +
                             "', not the '" + std::string(e.stage.name) + "' it declares");
    return spec;
  }

  SimulationSettings simulation(TomlCursor& t) {
    SimulationSettings s;
    read_keys(t, s, simulation_keys());  // [simulation.implicit] too (implicit_keys.cpp)
    t.finish();
    return s;
  }

  Fields fields(TomlCursor& t) {
    Fields f;
    read_keys(t, f, fields_keys());  // [fields.wind] too (src/core/wind_keys.cpp)
    t.finish();
    return f;
  }

  void claim_name(TomlCursor& t, const std::string& name) {
    if (name.empty() || name.find(':') != std::string::npos)
      t.fail("name", "must be a non-empty name without ':'");
    if (!names_.insert(name).second) t.fail("name", "duplicate name '" + name + "'");
  }

  void point(TomlCursor& t, Model& m, PointKind kind) {
    PointTable p;
    for (const char* key : {"name", "position", "mass"}) read_key(t, p, point_keys(), key);
    if (kind == PointKind::free) read_key(t, p, point_keys(), "velocity");  // [[fixed]]: unknown
    std::optional<DrivePath> path;
    if (kind == PointKind::fixed)
      if (auto d = t.table("drive")) path = drive(*d, p.position);
    const std::uint32_t first = m.points.size();
    m.points.add(path ? PointKind::driven : kind, p.mass, p.position, p.velocity);
    if (path) m.drives.push_back({first, *path});
    if (!p.name.empty()) {
      claim_name(t, p.name);
      m.groups.push_back({p.name, "point", first, 1});
    }
    t.finish();
  }

  DrivePath drive(TomlCursor& t, const Vec3& origin) {
    DrivePath p;
    p.origin = origin;
    // Each path reads its keys (drive_keys()) in this order; another path's key is unknown.
    auto read = [&](std::initializer_list<const char*> keys) {
      for (const char* key : keys) read_key(t, p, drive_keys(), key);
    };
    read({"path"});
    read({"phase"});
    switch (p.kind) {
      case DrivePath::Kind::sine:
        read({"amplitude", "frequency"});
        break;
      case DrivePath::Kind::circle:
        read({"radius", "axis", "frequency"});
        break;
      case DrivePath::Kind::rotate:
        read({"center", "axis", "frequency", "length"});
        break;
      case DrivePath::Kind::keyframes:
        keyframes(t, p);
        break;
    }
    t.finish();
    return p;
  }

  // keys = [[t, x, y, z], ...] with increasing t; positions are offsets from the point's scene
  // position, so the same path can drive every fixed point of a builder.
  void keyframes(TomlCursor& t, DrivePath& p) {
    const toml::node* n = t.node("keys");
    const toml::array* a = n ? n->as_array() : nullptr;
    if (!a || a->size() < 2) t.fail("keys", "must be an array of at least 2 [t, x, y, z] keys");
    for (const auto& key : *a) {
      const toml::array* k = key.as_array();
      if (!k || k->size() != 4) t.fail_at(key.source(), "keys", "each key must be [t, x, y, z]");
      double v[4];
      for (std::size_t i = 0; i < 4; ++i) {
        const auto d = (*k)[i].value<double>();
        if (!d || !std::isfinite(*d)) t.fail_at((*k)[i].source(), "keys", "must be numbers");
        if (std::abs(*d) > limits::max_coordinate)
          t.fail_at((*k)[i].source(), "keys", "must be within +-1e6 (s, m)");
        v[i] = *d;
      }
      if (!p.keys.empty() && !(v[0] > p.keys.back().first))
        t.fail_at(key.source(), "keys", "times must increase");
      p.keys.push_back({v[0], p.origin + Vec3{Real(v[1]), Real(v[2]), Real(v[3])}});
    }
  }

  void builder(TomlCursor& t, Model& m, const BuilderTable& b) {
    const std::string name =
        t.text("name", std::string(b.keyword) + std::to_string(m.groups.size()));
    claim_name(t, name);
    std::optional<TomlCursor> drive_table = t.table("drive");
    const Group g = b.build(t, m, name);
    if (drive_table) {
      // The same path, offset to each fixed point of the group (a pole that shakes).
      const DrivePath proto = drive(*drive_table, Vec3{});
      for (std::uint32_t i = g.first; i < g.first + g.count; ++i) {
        if (m.points.kind[i] != PointKind::fixed) continue;
        DrivePath path = proto;
        path.origin = m.points.initial_position[i];
        for (auto& k : path.keys) k.second += path.origin;
        m.points.set_kind(i, PointKind::driven);
        m.drives.push_back({i, path});
      }
    }
    t.finish();
  }

  // [[geometric_point]]: a shape placed by an affine map (docs/scene-format.md).
  void geometric_point(TomlCursor& t, Model& m) {
    GeometricPointTable table;  // geometric_point_keys()
    GeometricPoint& g = table.point;
    read_key(t, table, geometric_point_keys(), "name");
    for (const auto& other : m.geometric_points)
      if (other.name == g.name) t.fail("name", "another geometric point is named '" + g.name + "'");
    read_keys(t, table, geometric_point_keys());  // shape, its tube or top, the placement
    g.place = shapes::Affine::from(table.position, table.rotation, table.scale);
    m.geometric_points.push_back(std::move(g));
    t.finish();
  }

  void link(TomlCursor& t, Model& m) {
    LinkTable table;  // link_keys(); the kind's own keys are its fields
    read_key(t, table, link_keys(), "kind");
    const std::string& kind = table.kind;
    if (const StageRegistry::Entry* e = stages_.find(kind); e && e->of_links)
      return claimed_links_[kind].push_back(&t);  // a stage's, gathered with the others
    const LinkKindRegistry::Entry* entry = kinds_.find(kind);
    if (!entry) t.fail("kind", "unknown link kind '" + kind + "' (known: " + kinds_.names() + ")");
    const std::uint32_t a = point_ref(t, "a", m), b = point_ref(t, "b", m);
    if (a == b) t.fail("b", "a link needs two different points");
    std::vector<Real> values(entry->fields.size());
    for (std::size_t k = 0; k < values.size(); ++k) {
      const ParamInfo& f = entry->fields[k];
      if (auto v = t.maybe_real(f.name, f.bound)) {
        values[k] = *v;
        // limits::max_parameter: beyond it, omega^2 = k / m overflows.
        const Real most = limits::max_parameter(f.unit);
        t.check_range(f.name, *v, f.bound == Bound::any ? -most : 0, most, f.unit);
      } else if (f.default_value)
        values[k] = *f.default_value;
      else if (f.default_is_distance)
        values[k] = norm(m.points.initial_position[b] - m.points.initial_position[a]);
      else if (f.default_from.empty())
        t.fail(f.name, "is required for a " + kind + " link");
    }
    for (std::size_t k = 0; k < values.size(); ++k)  // defaults taken from another field
      if (!entry->fields[k].default_from.empty() && !t.has(entry->fields[k].name))
        for (std::size_t j = 0; j < values.size(); ++j)
          if (entry->fields[j].name == entry->fields[k].default_from) values[k] = values[j];
    LinkPoolBase* pool = m.links.find(kind);
    if (!pool) pool = &m.links.adopt(entry->make_pool());
    pool->add_generic({a, b}, values);
    t.finish();
  }

  const LinkKindRegistry& kinds_;
  const StageRegistry& stages_;
  // [[link]] tables whose kind is a registered stage's (StageTableEntry::of_links), by kind.
  std::map<std::string, std::vector<SceneTable*>, std::less<>> claimed_links_;
  std::string file_;
  std::set<std::string> names_;
};

}  // namespace

Result<Scene> parse_scene(std::string_view text, const std::string& source_name,
                          const LinkKindRegistry& kinds) {
  return parse_scene(text, source_name, kinds, builtin_stages());
}

Result<Scene> parse_scene(std::string_view text, const std::string& source_name,
                          const LinkKindRegistry& kinds, const StageRegistry& stages,
                          std::span<const std::string> overrides) {
  if (const auto hazard = find_toml_hazard(text))  // a toml++ 3.3 bug (toml_guard.hpp)
    return InputError{source_name, hazard->line, hazard->column, "", hazard->message};
  try {
    toml::table root = toml::parse(text, source_name);
    if (auto bad = apply_overrides(root, overrides)) return *bad;
    Scene scene = SceneReader(kinds, stages, source_name).read(root);
    scene.model.scene_digest = scene_digest(root);
    return scene;
  } catch (const toml::parse_error& e) {
    return InputError{
        source_name, static_cast<int>(e.source().begin.line),
        static_cast<int>(e.source().begin.column), "",
        toml_syntax_message(text, static_cast<int>(e.source().begin.line), e.description())};
  } catch (const SceneFailure& f) {
    return f.error;
  }
}

Result<Scene> load_scene(const std::filesystem::path& path, const LinkKindRegistry& kinds) {
  return load_scene(path, kinds, builtin_stages());
}

Result<Scene> load_scene(const std::filesystem::path& path, const LinkKindRegistry& kinds,
                         const StageRegistry& stages) {
  return load_scene(path, kinds, stages, {});
}

Result<Scene> load_scene(const std::filesystem::path& path,
                         std::span<const std::string> overrides) {
  static const LinkKindRegistry builtins = LinkKindRegistry::with_builtins();
  return load_scene(path, builtins, builtin_stages(), overrides);
}

Result<Scene> load_scene(const std::filesystem::path& path, const LinkKindRegistry& kinds,
                         const StageRegistry& stages, std::span<const std::string> overrides) {
  // Only a regular file of sane size is read: a directory, /dev/zero or a FIFO would otherwise
  // be read into memory without end or parsed as nothing.
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    return InputError{path.string(), 0, 0, "",
                      "cannot open the scene file: " +
                          (ec ? ec.message() : std::string("no such file or directory"))};
  if (std::filesystem::is_directory(status))
    return InputError{path.string(), 0, 0, "", "is a directory, not a scene file"};
  if (!std::filesystem::is_regular_file(status))
    return InputError{path.string(), 0, 0, "", "is not a regular file (a device or a pipe?)"};
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes > limits::max_scene_file_bytes)
    return InputError{path.string(), 0, 0, "",
                      "is " + std::to_string(bytes) + " bytes; scene files are limited to " +
                          std::to_string(limits::max_scene_file_bytes) + " bytes (64 MiB)"};
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return InputError{path.string(), 0, 0, "",
                      std::string("cannot open the scene file: ") + std::strerror(errno)};
  std::stringstream text;
  text << in.rdbuf();
  Result<Scene> r = parse_scene(text.str(), path.string(), kinds, stages, overrides);
  if (r) {
    r->source = path;
    if (r->name.empty()) r->name = path.stem().string();
  }
  return r;
}

Result<Scene> load_scene(const std::filesystem::path& path) {
  static const LinkKindRegistry builtins = LinkKindRegistry::with_builtins();
  return load_scene(path, builtins);
}

}  // namespace maille
