// Internal: the residual of the implicit Euler equations after a step solved by conjugate
// gradients (matrix_free, eigen): the largest force imbalance
//   |m_i (v_n+1,i - v_n,i) / h - f_i(x_n+1, v_n+1)|
// over free points, divided by m g of the heaviest free point (g = |gravity|, or 9.81 m/s^2 when
// gravity is off), the gauge `solver_residual` (VBD reports the same quantity from its own
// terms). The forces the solve takes implicitly (the model's links and the step's contact set:
// pairs, stencils, obstacles) are evaluated again at the end of the step; the
// others (gravity, wind, drag, stages without implicit terms) keep their value at x_n, as the
// solve did. It costs two passes over the links and contacts per step, a few CG iterations'
// worth; the unconverged-step watch (Simulator::unconverged) reads it every step.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/integrator.hpp"
#include "maille/mat3.hpp"
#include "maille/model.hpp"
#include "maille/state.hpp"

namespace maille {

class StepResidual {
 public:
  // At the step's start (s holds x_n, v_n and the forces of t_n, the contact set's apart): the
  // explicit forces, s.f() minus the model's links, which the solve takes implicitly. `free`:
  // the free points (the caller's list, read until end()).
  void begin(const Model& m, const State& s, Real h, std::span<const std::uint32_t> free);
  // After the solve (s holds x_n+1, v_n+1, with the contacts as the solve saw them).
  double end(const Model& m, const State& s, Real h, const ContactSet& contacts);

 private:
  // The implicit forces at (x, v) into f (cleared first): the model's links, and the contact
  // set's when `contacts` is not null.
  void implicit_forces(const Model& m, const State& s, Real h, const ContactSet* contacts,
                       std::vector<Vec3>& f);

  std::span<const std::uint32_t> free_;  // free points (the caller's)
  std::vector<Vec3> vn_, explicit_, work_;
  std::vector<Mat3> blocks_;  // point contacts' stiffness (unused)
};

}  // namespace maille
