#include "maille/checkpoint.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <type_traits>

#include "maille/io.hpp"

namespace maille {

namespace {

constexpr char kMagic[8] = {'M', 'A', 'I', 'L', 'L', 'E', 'C', 'K'};
constexpr std::uint32_t kVersion = 1;

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

class Writer {
 public:
  explicit Writer(std::ostream& o) : o_(o) {}
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    o_.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void text(const std::string& s) {
    value(std::uint64_t(s.size()));
    o_.write(s.data(), static_cast<std::streamsize>(s.size()));
  }
  template <class T>
  void array(const T* data, std::size_t n) {
    o_.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n * sizeof(T)));
  }

 private:
  std::ostream& o_;
};

// Reads with a bound on every length, so a corrupt file fails cleanly instead of allocating.
class Reader {
 public:
  Reader(std::istream& i, std::uint64_t size) : i_(i), left_(size) {}
  template <class T>
  T value() {
    T v{};
    take(sizeof v);
    i_.read(reinterpret_cast<char*>(&v), sizeof v);
    return v;
  }
  std::string text() {
    const auto n = value<std::uint64_t>();
    take(n);
    std::string s(n, '\0');
    i_.read(s.data(), static_cast<std::streamsize>(n));
    return s;
  }
  template <class T>
  void array(T* data, std::size_t n) {
    take(n * sizeof(T));
    i_.read(reinterpret_cast<char*>(data), static_cast<std::streamsize>(n * sizeof(T)));
  }
  void take(std::uint64_t n) {
    if (n > left_ || !i_) throw std::runtime_error("truncated");
    left_ -= n;
  }

 private:
  std::istream& i_;
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
  h.value(m.fields.gravity);
  h.value(m.fields.air_drag);
  h.value(m.fields.wind.velocity);
  h.value(m.fields.wind.turbulence);
  h.value(m.drives.size());
  for (const auto& s : m.stages) h.text(s.name);
  return h.get();
}

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c) {
  AtomicFile file(path);
  Writer w(file.stream());
  file.stream().write(kMagic, sizeof kMagic);
  w.value(kVersion);
  w.value(std::uint32_t(sizeof(Real)));
  w.value(c.model_fingerprint);
  w.text(c.integrator);
  w.value(c.step);
  w.value(c.frames_published);
  w.value(c.stats_rows);
  const State& s = c.state;
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
  file.commit();
}

Result<Checkpoint> read_checkpoint(const std::filesystem::path& path, const Model& model) {
  auto error = [&](const std::string& why) {
    return InputError{path.string(), 0, 0, "", "checkpoint: " + why};
  };
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return error("cannot read: " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) return error(std::string("cannot open: ") + std::strerror(errno));
  try {
    Reader r(in, size);
    char magic[sizeof kMagic];
    r.array(magic, sizeof magic);
    if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) return error("not a Maille checkpoint");
    if (r.value<std::uint32_t>() != kVersion) return error("written by another version");
    if (r.value<std::uint32_t>() != sizeof(Real))
      return error("written with another precision (float/double build)");
    Checkpoint c;
    c.model_fingerprint = r.value<std::uint64_t>();
    if (c.model_fingerprint != model_fingerprint(model))
      return error("written for another model (the scene changed since)");
    c.integrator = r.text();
    c.step = r.value<double>();
    c.frames_published = r.value<std::uint64_t>();
    c.stats_rows = r.value<std::uint64_t>();
    const auto n = r.value<std::uint64_t>();
    if (n != model.points.size()) return error("point count differs from the model's");
    State s(n);
    s.time = r.value<double>();
    s.step = r.value<std::uint64_t>();
    s.history.scheme = r.text();
    s.history.primed = r.value<std::uint8_t>() != 0;
    s.history.last_h = r.value<double>();
    const auto memories = r.value<std::uint64_t>();
    if (memories > size / 16) return error("truncated");  // each holds two lengths at least
    for (std::uint64_t k = 0; k < memories; ++k) {
      StageMemory m;
      m.stage = r.text();
      const auto values = r.value<std::uint64_t>();
      if (values > size / sizeof(double)) return error("truncated");
      m.values.resize(values);
      r.array(m.values.data(), values);
      s.stage_memory.push_back(std::move(m));
    }
    r.array(s.x().data(), n);
    r.array(s.v().data(), n);
    r.array(s.f().data(), n);
    c.state = std::move(s);
    return c;
  } catch (const std::runtime_error& e) {
    return error(e.what());
  }
}

}  // namespace maille
