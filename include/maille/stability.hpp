// Largest stable step: a Gershgorin bound on the stiffest mode, per point, per scheme.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "maille/integrator.hpp"
#include "maille/model.hpp"

namespace maille {

struct StabilityEstimate {
  Real max_step = 0;        // s; +inf when nothing is stiff (no links)
  std::uint32_t point = 0;  // the point that sets it
  std::string link_kind;    // the stiffest kind acting on that point
  Real omega = 0;           // rad/s, bound on the highest angular frequency at that point
  Real damping_rate = 0;    // 1/s, c at that point
};

// For each free point i: omega_i^2 = inv_m_i * sum_links k (x2 when the other end is free),
// c_i likewise with damping; the step limit is the integrator's stable_step(omega_i^2, c_i),
// minimised over points. Exact for a single mass on a spring and for two free masses.
// Stages that act like springs add their terms (Stage::stability_terms) and are named when they
// set the limit.
StabilityEstimate estimate_stability(const Model& m, const Integrator& scheme,
                                     std::span<const Stage* const> stages = {});

}  // namespace maille
