#include "maille/checkpoint.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <type_traits>

#include "maille/io.hpp"

namespace maille {

namespace {

constexpr char kMagic[8] = {'M', 'A', 'I', 'L', 'L', 'E', 'C', 'K'};
constexpr std::uint32_t kVersion = 2;  // 2: a checksum closes the file

class Fnv {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 1099511628211ull;
  }
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  void text(std::string_view s) {
    value(s.size());
    bytes(s.data(), s.size());
  }
  std::uint64_t get() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

// The checksum closing a file: FNV-1a's step on 8-byte words (a tail is zero-padded, the length
// mixed in), then a final avalanche. Each step is a bijection of the running value for a given
// word, so a change confined to one word (a flipped byte, a flipped bit) always changes the sum;
// other damage goes unnoticed with odds about 2^-64. A word at a time: 1 GB sums in ~0.3 s.
std::uint64_t checksum(const char* data, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull ^ n;
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    std::uint64_t w;
    std::memcpy(&w, data + i, 8);
    h = (h ^ w) * 1099511628211ull;
  }
  std::uint64_t tail = 0;
  std::memcpy(&tail, data + i, n - i);
  h = (h ^ tail) * 1099511628211ull;
  h ^= h >> 33;  // murmur3's finaliser: every bit of h reaches every bit of the result
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  return h ^ (h >> 33);
}

// Appends to a buffer: the checksum needs every byte before the file is written.
class Writer {
 public:
  explicit Writer(std::string& o) : o_(o) {}
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    o_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void text(const std::string& s) {
    value(std::uint64_t(s.size()));
    o_.append(s);
  }
  template <class T>
  void array(const T* data, std::size_t n) {
    o_.append(reinterpret_cast<const char*>(data), n * sizeof(T));
  }

 private:
  std::string& o_;
};

// Reads from the file's bytes with a bound on every length, so a corrupt file fails cleanly
// instead of allocating.
class Reader {
 public:
  Reader(const char* data, std::uint64_t size) : p_(data), left_(size) {}
  template <class T>
  T value() {
    T v{};
    take(&v, sizeof v);
    return v;
  }
  std::string text() {
    const auto n = value<std::uint64_t>();
    if (n > left_) throw std::runtime_error("truncated");
    std::string s(n, '\0');
    take(s.data(), n);
    return s;
  }
  template <class T>
  void array(T* data, std::size_t n) {
    if (n > left_ / sizeof(T)) throw std::runtime_error("truncated");
    take(data, n * sizeof(T));
  }
  std::uint64_t left() const { return left_; }

 private:
  void take(void* out, std::uint64_t n) {
    if (n > left_) throw std::runtime_error("truncated");
    std::memcpy(out, p_, n);
    p_ += n;
    left_ -= n;
  }
  const char* p_;
  std::uint64_t left_;
};

}  // namespace

std::uint64_t model_fingerprint(const Model& m) {
  Fnv h;
  const auto& p = m.points;
  h.value(p.size());
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    h.value(p.kind[i]);
    h.value(p.mass[i]);
    h.value(p.initial_position[i]);
    h.value(p.initial_velocity[i]);
  }
  for (const auto& pool : m.links.pools()) {
    h.text(pool->keyword());
    h.value(pool->size());
    const std::size_t fields = pool->fields().size();
    for (std::size_t id = 0; id < pool->size(); ++id) {
      h.value(pool->ends(id));
      for (std::size_t k = 0; k < fields; ++k) h.value(pool->param(id, k));
    }
  }
  for (const auto& t : m.surface.triangles) h.value(t);
  for (const auto& g : m.groups) {  // stages choose their points by group
    h.text(g.name);
    h.value(g.first);
    h.value(g.count);
    h.value(g.grid_nx);
    h.value(g.grid_ny);
  }
  const Fields& f = m.fields;
  h.value(f.gravity);
  h.value(f.air_drag);
  h.value(f.wind.velocity);
  h.value(f.wind.density);
  h.value(f.wind.drag_coefficient);
  h.value(f.wind.turbulence);
  h.value(f.wind.gust_frequency);
  h.value(f.wind.gust_wavelength);
  h.value(m.drives.size());
  for (const Drive& d : m.drives) {
    const DrivePath& q = d.path;
    h.value(d.point);
    h.value(q.kind);
    for (const Vec3& v : {q.origin, q.amplitude, q.axis, q.center}) h.value(v);
    for (const Real r : {q.length, q.radius, q.frequency, q.phase}) h.value(r);
    for (const auto& [t, x] : q.keys) {
      h.value(t);
      h.value(x);
    }
  }
  for (const GeometricPoint& g : m.geometric_points) {
    h.text(g.name);
    h.value(g.shape);
    // Every shape parameter in table order: the point's own for its shape, else the default.
    const auto table = shape_table();
    for (std::size_t i = 0; i < table.size(); ++i)
      if (table[i].parameter)
        h.value(ShapeKind(i) == g.shape ? shape_parameter(g.shape, g.shape_parameter)
                                        : table[i].parameter->fallback);
    h.value(g.place);
  }
  for (const auto& s : m.stages) {
    h.text(s.name);
    h.text(s.variant);
    h.value(s.fingerprint);
    for (const auto& [key, value] :
         s.parameters) {  // every declared key, resolved (stage_keys.hpp)
      h.text(key);
      h.text(value);
    }
  }
  h.value(m.scene_digest);
  return h.get();
}

std::uint64_t model_fingerprint(const Model& m, const SimulationSettings& s) {
  Fnv h;
  h.value(model_fingerprint(m));
  const ImplicitSettings& i = s.implicit;
  h.text(to_string(i.solver));
  h.value(i.tolerance);
  h.value(i.max_iterations);
  h.value(i.newton_iterations);
  h.value(i.iterations);
  h.value(i.acceleration);
  h.text(s.backend);
  for (const auto& spec : m.stages) {  // the stages that run, after --no-self-collision & co.
    const auto& off = s.disabled_stages;
    h.value(std::uint8_t(std::find(off.begin(), off.end(), spec.name) == off.end()));
  }
  return h.get();
}

std::string scheme_mismatch(const std::string& integrator, double step, const std::string& now,
                            const std::string& now_integrator, double now_step) {
  char a[32], b[32];
  std::snprintf(a, sizeof a, "%.17g", step);
  std::snprintf(b, sizeof b, "%.17g", now_step);
  return "the checkpoint was taken with " + integrator + " at h = " + a + " s; " + now + " " +
         now_integrator + " at h = " + b + " s";
}

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c) {
  std::string bytes;
  const State& s = c.state;
  bytes.reserve(256 + 3 * s.size() * sizeof(Vec3));
  Writer w(bytes);
  w.array(kMagic, sizeof kMagic);
  w.value(kVersion);
  w.value(std::uint32_t(sizeof(Real)));
  w.value(c.model_fingerprint);
  w.text(c.integrator);
  w.value(c.step);
  w.value(c.frames_published);
  w.value(c.stats_rows);
  w.value(std::uint64_t(s.size()));
  w.value(s.time);
  w.value(s.step);
  w.text(s.history.scheme);
  w.value(std::uint8_t(s.history.primed));
  w.value(s.history.last_h);
  w.value(std::uint64_t(s.stage_memory.size()));
  for (const auto& m : s.stage_memory) {
    w.text(m.stage);
    w.value(std::uint64_t(m.values.size()));
    w.array(m.values.data(), m.values.size());
  }
  w.array(s.x().data(), s.size());
  w.array(s.v().data(), s.size());
  w.array(s.f().data(), s.size());
  w.value(checksum(bytes.data(), bytes.size()));
  AtomicFile file(path);
  file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.commit();
}

namespace {

// The whole file, refused unless its last 8 bytes are the checksum of the others.
std::string read_verified(const std::filesystem::path& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw std::runtime_error("cannot read: " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string("cannot open: ") + std::strerror(errno));
  constexpr std::uint64_t header = sizeof kMagic + 2 * sizeof(std::uint32_t);
  if (size < header + sizeof(std::uint64_t)) {
    char magic[sizeof kMagic] = {};
    in.read(magic, sizeof magic);
    if (std::memcmp(magic, kMagic, sizeof kMagic) != 0)
      throw std::runtime_error("not a Maille checkpoint");
    throw std::runtime_error("truncated");
  }
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (!in) throw std::runtime_error("cannot read the whole file");
  if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw std::runtime_error("not a Maille checkpoint");
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + sizeof kMagic, sizeof version);
  if (version != kVersion) throw std::runtime_error("written by another version");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + size - sizeof stored, sizeof stored);
  if (stored != checksum(bytes.data(), size - sizeof stored))
    throw std::runtime_error(
        "corrupt or truncated: the checksum does not match its contents (the file was changed, "
        "cut short or damaged after it was written)");
  bytes.resize(size - sizeof stored);
  return bytes;
}

}  // namespace

Result<Checkpoint> read_checkpoint(const std::filesystem::path& path, const Model& model) {
  Result<Checkpoint> c = read_checkpoint(path, model_fingerprint(model));
  if (c && c->state.size() != model.points.size())
    return InputError{path.string(), 0, 0, "", "checkpoint: point count differs from the model's"};
  return c;
}

Result<Checkpoint> read_checkpoint(const std::filesystem::path& path, std::uint64_t fingerprint) {
  auto error = [&](const std::string& why) {
    return InputError{path.string(), 0, 0, "", "checkpoint: " + why};
  };
  try {
    const std::string bytes = read_verified(path);
    Reader r(bytes.data(), bytes.size());
    char magic[sizeof kMagic];
    r.array(magic, sizeof magic);
    r.value<std::uint32_t>();  // the version, checked
    if (r.value<std::uint32_t>() != sizeof(Real))
      return error("written with another precision (float/double build)");
    Checkpoint c;
    c.model_fingerprint = r.value<std::uint64_t>();
    if (c.model_fingerprint != fingerprint)
      return error("written for another model (the scene changed since)");
    c.integrator = r.text();
    c.step = r.value<double>();
    c.frames_published = r.value<std::uint64_t>();
    c.stats_rows = r.value<std::uint64_t>();
    const auto n = r.value<std::uint64_t>();
    if (n > r.left() / (3 * sizeof(Vec3))) return error("truncated");
    State s(n);
    s.time = r.value<double>();
    s.step = r.value<std::uint64_t>();
    s.history.scheme = r.text();
    s.history.primed = r.value<std::uint8_t>() != 0;
    s.history.last_h = r.value<double>();
    const auto memories = r.value<std::uint64_t>();
    if (memories > r.left() / 16) return error("truncated");  // each holds two lengths at least
    for (std::uint64_t k = 0; k < memories; ++k) {
      StageMemory m;
      m.stage = r.text();
      const auto values = r.value<std::uint64_t>();
      if (values > r.left() / sizeof(double)) return error("truncated");
      m.values.resize(values);
      r.array(m.values.data(), values);
      s.stage_memory.push_back(std::move(m));
    }
    r.array(s.x().data(), n);
    r.array(s.v().data(), n);
    r.array(s.f().data(), n);
    if (r.left() != 0) return error("corrupt: bytes after the state");
    c.state = std::move(s);
    return c;
  } catch (const std::runtime_error& e) {
    return error(e.what());
  }
}

}  // namespace maille
