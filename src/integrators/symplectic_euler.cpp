// Symplectic (semi-implicit) Euler: kick then drift, with full-step velocities.
//   v(n+1) = v(n) + h a(x_n, v_n);   x(n+1) = x(n) + h v(n+1)
// The same recurrence as leapfrog without the half-kick start, so velocities are first-order
// accurate but energy stays bounded (symplectic).
#include "integrators.hpp"

namespace maille {

namespace {

// KickDriftScheme's own step: a kick and a drift of h each, the history kept as it is.
class SymplecticEuler final : public KickDriftScheme {
 public:
  std::string_view name() const override { return "symplectic_euler"; }
};

}  // namespace

std::unique_ptr<Integrator> make_symplectic_euler() {
  return std::make_unique<SymplecticEuler>();
}

}  // namespace maille
