#include "scene_digest.hpp"

#include <sstream>
#include <string_view>

namespace maille {

namespace {

constexpr std::string_view kOutputSimulationKeys[] = {
    "duration",       "output_every", "sample_every", "threads",
    "runaway_factor", "gpu_device",   "integrator",   "step"};

template <class List>
bool listed(const List& list, std::string_view key) {
  for (const std::string_view k : list)
    if (k == key) return true;
  return false;
}

class Digest {
 public:
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 1099511628211ull;
  }
  void text(std::string_view s) {
    const std::uint64_t n = s.size();
    bytes(&n, sizeof n);
    bytes(s.data(), s.size());
  }
  void tag(char c) { bytes(&c, 1); }

  // Tables in key order (toml++ keeps them sorted), arrays in order; each value with its type,
  // so 1 and 1.0 and "1" differ, and doubles by their bits (-0.0 and 0.0 differ too: harmless).
  void node(const toml::node& n) {
    if (const toml::table* t = n.as_table()) {
      tag('{');
      for (const auto& [key, value] : *t) {
        text(key.str());
        node(value);
      }
      tag('}');
    } else if (const toml::array* a = n.as_array()) {
      tag('[');
      for (const toml::node& e : *a) node(e);
      tag(']');
    } else if (const auto* s = n.as_string()) {
      tag('s');
      text(s->get());
    } else if (const auto* i = n.as_integer()) {
      tag('i');
      const std::int64_t v = i->get();
      bytes(&v, sizeof v);
    } else if (const auto* d = n.as_floating_point()) {
      tag('d');
      const double v = d->get();
      bytes(&v, sizeof v);
    } else if (const auto* b = n.as_boolean()) {
      tag(b->get() ? 'T' : 'F');
    } else {  // dates and times: no scene key takes one; their text is exact
      tag('?');
      std::ostringstream out;
      n.visit([&](const auto& value) { out << value; });
      text(out.str());
    }
  }

  std::uint64_t get() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

}  // namespace

std::uint64_t scene_digest(const toml::table& root) {
  Digest d;
  for (const auto& [key, value] : root) {
    if (listed(kOutputTables, key.str())) continue;
    d.text(key.str());
    const toml::table* simulation = key.str() == "simulation" ? value.as_table() : nullptr;
    if (!simulation) {
      d.node(value);
      continue;
    }
    d.tag('{');
    for (const auto& [k, v] : *simulation) {
      if (listed(kOutputSimulationKeys, k.str())) continue;
      d.text(k.str());
      d.node(v);
    }
    d.tag('}');
  }
  return d.get();
}

}  // namespace maille
