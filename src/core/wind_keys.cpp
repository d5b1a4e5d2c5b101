// [fields.wind]'s keys (fields.hpp: the law). The bounds keep the wind's force and the gusts'
// phase finite (limits.hpp).
#include <array>

#include "maille/fields.hpp"
#include "maille/limits.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<WindField>> wind_keys() {
  using W = WindField;
  static const std::array<StageKey<W>, 6> keys{
      vector<&W::velocity>("velocity", {.unit = "m/s", .doc = "mean wind U"}),
      number<&W::density>("density", Bound::positive, 0, 1e6,
                          {.unit = "kg/m^3", .doc = "air density ρ"}),
      number<&W::drag_coefficient>("drag_coefficient", Bound::non_negative, 0, 1e6,
                                   {.doc = "pressure coefficient C_d of a face"}),
      number<&W::turbulence>(
          "turbulence", Bound::non_negative, 0, 1e6,
          {.doc = "relative amplitude of gusts (0.3: ±30 %) along and across the wind"}),
      number<&W::gust_frequency>("gust_frequency", Bound::positive, 0, 1e6,
                                 {.unit = "Hz", .doc = "frequency of the gusts"}),
      number<&W::gust_wavelength>("gust_wavelength", Bound::positive, 0, 2 * limits::max_coordinate,
                                  {.unit = "m", .doc = "spatial scale of the gusts"}),
  };
  return keys;
}

}  // namespace maille
