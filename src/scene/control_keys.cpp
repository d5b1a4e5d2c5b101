// A [[control]]'s key made live (scene.hpp: build_parameter_table): the scene is read again with
// `--set KEY=VALUE` at values across the control's range, through exactly the reader's
// validation, and each model is compared with the playing one. A key that changes the model's
// structure (points, links, drives), or changes nothing the model holds, cannot be played; the
// slots it does change are tabulated, so that the audio thread only blends validated values.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "maille/integrator.hpp"
#include "maille/live.hpp"
#include "maille/scene.hpp"
#include "maille/stability.hpp"

namespace maille {

namespace {

constexpr std::size_t kCurvedRows = 33;  // rows when the model is not linear in the key

// Why `b` (the scene read with the key at some value) cannot be reached from `a` (the playing
// model) by changing slots (empty: it can): its structure differs, or values that are not slots
// (initial positions and velocities, faces, drive paths' shapes, stages).
std::string unplayable_change(const Model& a, const Model& b) {
  const char* structure =
      "changes the model's structure (its points, links, faces, drives or stages)";
  if (a.points.size() != b.points.size() || a.drives.size() != b.drives.size() ||
      a.surface.triangles.size() != b.surface.triangles.size() ||
      a.stages.size() != b.stages.size())
    return structure;
  const auto pa = a.links.pools(), pb = b.links.pools();
  if (pa.size() != pb.size()) return structure;
  for (std::size_t p = 0; p < pa.size(); ++p) {
    if (pa[p]->keyword() != pb[p]->keyword() || pa[p]->size() != pb[p]->size()) return structure;
    for (std::uint32_t id = 0; id < pa[p]->size(); ++id)
      if (pa[p]->ends(id).a != pb[p]->ends(id).a || pa[p]->ends(id).b != pb[p]->ends(id).b)
        return structure;
  }
  for (std::uint32_t i = 0; i < a.points.size(); ++i) {
    if (a.points.kind[i] != b.points.kind[i]) return structure;
    if (a.points.initial_position[i] != b.points.initial_position[i] ||
        a.points.initial_velocity[i] != b.points.initial_velocity[i])
      return "changes the points' initial positions or velocities";
  }
  for (std::size_t d = 0; d < a.drives.size(); ++d) {
    const DrivePath &x = a.drives[d].path, &y = b.drives[d].path;
    if (a.drives[d].point != b.drives[d].point || x.kind != y.kind || x.origin != y.origin ||
        x.axis != y.axis || x.center != y.center || x.length != y.length || x.keys != y.keys)
      return "changes a drive's path other than its frequency, phase, radius or amplitude";
  }
  return {};
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

InputError control_error(const audio::Control& c, const std::string& message) {
  return InputError{c.file, c.line, c.column, c.name + ".key", message};
}

}  // namespace

Result<audio::ParameterTable> build_parameter_table(const std::filesystem::path& path,
                                                    std::span<const std::string> sets,
                                                    const Model& playing,
                                                    const SimulationSettings& settings,
                                                    const audio::Control& c) {
  auto read_at = [&](double value) -> Result<Model> {
    std::vector<std::string> with(sets.begin(), sets.end());
    with.push_back(c.key + "=" + number(value));
    Result<Scene> s = load_scene(path, with);
    if (!s)
      return control_error(c, "'" + c.key + "' = " + number(value) + " (in range [" +
                                  number(c.low) + ", " + number(c.high) +
                                  "]) is refused: " + s.error().to_string());
    if (const std::string why = unplayable_change(playing, s.value().model); !why.empty())
      return control_error(c,
                           "'" + c.key + "' " + why + ": it cannot change while the model plays");
    return std::move(s.value().model);
  };
  const std::vector<audio::ParameterSlot> all = audio::parameter_slots(playing);
  const std::vector<double> base = audio::parameter_values(playing);
  std::vector<std::vector<double>> values;
  for (const double v : {c.low, 0.5 * (c.low + c.high), c.high}) {
    Result<Model> m = read_at(v);
    if (!m) return m.error();
    values.push_back(audio::parameter_values(m.value()));
  }
  // The slots the key moves, and whether they move linearly with it.
  std::vector<std::size_t> moved;
  bool linear = true;
  for (std::size_t k = 0; k < all.size(); ++k) {
    const double lo = values[0][k], mid = values[1][k], hi = values[2][k];
    if (lo == base[k] && mid == base[k] && hi == base[k]) continue;
    moved.push_back(k);
    const double scale = std::max({std::abs(lo), std::abs(hi), 1e-30});
    const double tolerance = std::is_same_v<Real, float> ? 1e-6 : 1e-12;
    if (std::abs(mid - 0.5 * (lo + hi)) > tolerance * scale) linear = false;
  }
  if (moved.empty())
    return control_error(c, "'" + c.key +
                                "' changes nothing that can change while the model plays (link "
                                "parameters, fields, free points' masses, drives' frequency, "
                                "phase, radius and amplitude)");
  audio::ParameterTable t;
  for (const std::size_t k : moved) t.slots.push_back(all[k]);
  const std::size_t rows = linear ? 2 : kCurvedRows;
  if (!linear) {  // read again at every row's value
    values.clear();
    for (std::size_t j = 0; j < rows; ++j) {
      Result<Model> m = read_at(c.low + (c.high - c.low) * double(j) / double(rows - 1));
      if (!m) return m.error();
      values.push_back(audio::parameter_values(m.value()));
    }
  } else {
    values = {values[0], values[2]};
  }
  t.rows = rows;
  for (const auto& row : values)
    for (const std::size_t k : moved) t.values.push_back(row[k]);
  // Where the scene's own value sits in the range: on the slot that moves the most.
  std::size_t widest = 0;
  double span = -1;
  for (std::size_t s = 0; s < moved.size(); ++s) {
    const double d = std::abs(values.back()[moved[s]] - values.front()[moved[s]]);
    if (d > span) span = d, widest = s;
  }
  const std::size_t n = moved.size();
  const double here = base[moved[widest]];
  t.initial = 0;
  for (std::size_t j = 0; j + 1 < rows; ++j) {
    const double a = t.values[j * n + widest], b = t.values[(j + 1) * n + widest];
    if ((here - a) * (here - b) <= 0 && a != b) {
      t.initial = (double(j) + (here - a) / (b - a)) / double(rows - 1);
      break;
    }
    if (j + 2 == rows)
      t.initial =
          std::abs(here - t.values[widest]) < std::abs(here - t.values[(rows - 1) * n + widest])
              ? 0.0
              : 1.0;
  }
  // The blend's error between rows, from the second differences (a curve's midpoint is off
  // its chord by about a quarter of them).
  for (std::size_t j = 1; j + 1 < rows; ++j)
    for (std::size_t s = 0; s < n; ++s) {
      const double a = t.values[(j - 1) * n + s], b = t.values[j * n + s],
                   d = t.values[(j + 1) * n + s];
      const double scale = std::max({std::abs(a), std::abs(d), 1e-30});
      t.max_blend_error = std::max(t.max_blend_error, std::abs(a - 2 * b + d) / 4 / scale);
    }
  // Every row must run at the scene's step: the ends of the range bound the stiffest.
  const IntegratorRegistry::Entry* scheme = IntegratorRegistry::builtin().find(settings.integrator);
  if (scheme) {
    const auto integrator = scheme->make(settings.implicit);
    for (const double v : {c.low, c.high}) {
      Result<Model> m = read_at(v);
      if (!m) return m.error();
      const StabilityEstimate e = estimate_stability(m.value(), *integrator);
      if (settings.step > double(e.max_step))
        return control_error(c, "'" + c.key + "' = " + number(v) + " needs a step below " +
                                    number(double(e.max_step)) + " s (" +
                                    std::string(integrator->name()) +
                                    " stability estimate), the scene's is " +
                                    number(settings.step) + " s: narrow the range");
    }
  }
  return t;
}

}  // namespace maille
