// Internal: the linear system of implicit Euler, A dv = b with
//   A = M (1 + h gamma) - h df/dv - h^2 df/dx   (filtered: rows and columns of fixed points
// replaced by the identity, their right-hand side by zero), solved by preconditioned CG.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "maille/integrator.hpp"
#include "maille/model.hpp"
#include "maille/registry.hpp"
#include "maille/stage.hpp"
#include "maille/state.hpp"

namespace maille {

struct SolveResult {
  int iterations = 0;
  double relative_residual = 0;  // |b - A dv| / |b| at exit (0 when b = 0)
  bool stopped = false;          // a stop was requested (ImplicitSystem::solve)
};

class ImplicitSystem {
 public:
  virtual ~ImplicitSystem() = default;
  // Takes the link Jacobians at the state (the model's pools and the contact set's pairs), the
  // stiffness of the set's obstacles and stencils (a system of fixed pattern refuses scenes
  // with contact stages: ImplicitEuler::check_stage); adds h^2 df/dx v into rhs when rhs is not
  // null.
  virtual void linearise(const Model& m, const State& s, Real h, Vec3* rhs,
                         const ContactSet& contacts) = 0;
  // Solves A dv = rhs (rhs is filtered in place; dv is overwritten, starting from zero).
  // `stop`, when given, is asked every kStopEvery iterations; the solve ends when it answers
  // true (SolveResult::stopped), dv unfinished.
  virtual SolveResult solve(std::vector<Vec3>& rhs, std::vector<Vec3>& dv, Real tolerance,
                            int max_iterations, ForceEvaluator* stop = nullptr) = 0;
  static constexpr int kStopEvery = 32;
  // The product A u (filtered), for tests comparing the two solvers.
  virtual void multiply(const std::vector<Vec3>& u, std::vector<Vec3>& out) = 0;
  // Between solves (Integrator::set_threads).
  virtual void set_threads(int threads) = 0;
};

// The CG systems by solver name (ImplicitSolver's name table): one file each in
// src/integrators/systems/, whose `register_system_<file name>(ImplicitSystems&)` adds its entry
// (cmake/RegisterFolder.cmake generates the call of every file's). A solver that is not a CG
// system (vbd) has no entry: ImplicitEuler runs its own loop.
struct ImplicitSystemEntry {
  std::string_view name;  // to_string(ImplicitSolver::...)
  std::unique_ptr<ImplicitSystem> (*make)(const Model& m, int threads);
};
class ImplicitSystems : public Registry<ImplicitSystemEntry, &ImplicitSystemEntry::name> {
 public:
  ImplicitSystems() : Registry("implicit system registry") {}
  // Every file of src/integrators/systems/, registered once.
  static const ImplicitSystems& builtin();
};

// The system of `solver`; null for a solver that is not a CG system.
std::unique_ptr<ImplicitSystem> make_implicit_system(ImplicitSolver solver, const Model& m,
                                                     int threads);

// Inverse of a symmetric positive definite 3x3 matrix (cofactors; identity if singular).
Mat3 inverse_spd(const Mat3& a);

}  // namespace maille
