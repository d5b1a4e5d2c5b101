// The model's live parameters as flat slots (live.hpp): what a [[control]] key may change while
// a model plays. Links: every parameter of every link; fields: gravity (3), air drag, the wind's
// velocity (3), density, drag coefficient, turbulence, gust frequency and wavelength; masses of
// free points; drives: frequency, phase, radius, amplitude (3).
#include <array>
#include <string>

#include "maille/live.hpp"

namespace maille::audio {

namespace {

constexpr std::uint32_t kFieldSlots = 13;
constexpr std::uint32_t kDriveSlots = 6;
constexpr const char* kFieldNames[kFieldSlots] = {"fields.gravity.x",
                                                  "fields.gravity.y",
                                                  "fields.gravity.z",
                                                  "fields.air_drag",
                                                  "fields.wind.velocity.x",
                                                  "fields.wind.velocity.y",
                                                  "fields.wind.velocity.z",
                                                  "fields.wind.density",
                                                  "fields.wind.drag_coefficient",
                                                  "fields.wind.turbulence",
                                                  "fields.wind.gust_frequency",
                                                  "fields.wind.gust_wavelength",
                                                  "(unused)"};
constexpr const char* kDriveNames[kDriveSlots] = {"frequency",   "phase",       "radius",
                                                  "amplitude.x", "amplitude.y", "amplitude.z"};

// Slot i of a record, among its slots listed in order (nullptr past the last).
template <std::size_t N>
Real* slot(const std::array<Real*, N>& slots, std::uint32_t i) {
  return i < N ? slots[i] : nullptr;
}

Real* field_slot(Fields& f, std::uint32_t i) {
  return slot<kFieldSlots - 1>(
      {&f.gravity.x, &f.gravity.y, &f.gravity.z, &f.air_drag, &f.wind.velocity.x,
       &f.wind.velocity.y, &f.wind.velocity.z, &f.wind.density, &f.wind.drag_coefficient,
       &f.wind.turbulence, &f.wind.gust_frequency, &f.wind.gust_wavelength},
      i);
}

Real* drive_slot(DrivePath& p, std::uint32_t i) {
  return slot<kDriveSlots>(
      {&p.frequency, &p.phase, &p.radius, &p.amplitude.x, &p.amplitude.y, &p.amplitude.z}, i);
}

// Calls f(slot, value) for every slot of m in order.
template <class F>
void for_each_slot(const Model& m, F&& f) {
  const auto pools = m.links.pools();
  for (std::uint32_t p = 0; p < pools.size(); ++p) {
    const std::size_t fields = pools[p]->fields().size();
    for (std::uint32_t id = 0; id < pools[p]->size(); ++id)
      for (std::uint32_t k = 0; k < fields; ++k)
        f(ParameterSlot{ParameterSlot::Kind::link, p, id, k}, double(pools[p]->param(id, k)));
  }
  Fields fields = m.fields;
  for (std::uint32_t i = 0; i + 1 < kFieldSlots; ++i)
    f(ParameterSlot{ParameterSlot::Kind::field, 0, 0, i}, double(*field_slot(fields, i)));
  for (std::uint32_t i = 0; i < m.points.size(); ++i)
    if (m.points.kind[i] == PointKind::free)
      f(ParameterSlot{ParameterSlot::Kind::mass, 0, i, 0}, double(m.points.mass[i]));
  for (std::uint32_t d = 0; d < m.drives.size(); ++d) {
    DrivePath path = m.drives[d].path;
    for (std::uint32_t i = 0; i < kDriveSlots; ++i)
      f(ParameterSlot{ParameterSlot::Kind::drive, 0, d, i}, double(*drive_slot(path, i)));
  }
}

}  // namespace

std::vector<ParameterSlot> parameter_slots(const Model& m) {
  std::vector<ParameterSlot> out;
  for_each_slot(m, [&](const ParameterSlot& s, double) { out.push_back(s); });
  return out;
}

std::vector<double> parameter_values(const Model& m) {
  std::vector<double> out;
  for_each_slot(m, [&](const ParameterSlot&, double v) { out.push_back(v); });
  return out;
}

void set_parameter(Model& m, const ParameterSlot& s, double value) {
  const Real v = static_cast<Real>(value);
  switch (s.kind) {
    case ParameterSlot::Kind::link:
      m.links.pools()[s.pool]->set_param(s.index, s.field, v);
      break;
    case ParameterSlot::Kind::field:
      if (Real* r = field_slot(m.fields, s.field)) *r = v;
      break;
    case ParameterSlot::Kind::mass:
      m.points.mass[s.index] = v;
      m.points.inv_mass[s.index] = Real(1) / v;
      break;
    case ParameterSlot::Kind::drive:
      if (Real* r = drive_slot(m.drives[s.index].path, s.field)) *r = v;
      break;
  }
}

std::string describe(const Model& m, const ParameterSlot& s) {
  switch (s.kind) {
    case ParameterSlot::Kind::link: {
      const LinkPoolBase& pool = *m.links.pools()[s.pool];
      return std::string(pool.keyword()) + " link " + std::to_string(s.index) + " " +
             pool.fields()[s.field].name;
    }
    case ParameterSlot::Kind::field:
      return kFieldNames[s.field];
    case ParameterSlot::Kind::mass:
      return "mass of point " + std::to_string(s.index);
    case ParameterSlot::Kind::drive:
      return "drive " + std::to_string(s.index) + " " + kDriveNames[s.field];
  }
  return {};
}

}  // namespace maille::audio
