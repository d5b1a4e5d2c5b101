// Implicit (backward) Euler in the Baraff-Witkin form (SIGGRAPH 1998): one linearised solve
// per step,
//
//   (M - h df/dv - h^2 df/dx) dv = h (f + h df/dx v),   v += dv,   x += h v
//
// with the Jacobians taken at (x_n, v_n). Optional Newton iterations (newton_iterations > 1)
// re-linearise at x_n + h v_k and solve M (v - v_n) = h f(x_n + h v, v) to convergence.
//
// The matrix is never formed for the "matrix_free" solver: each link pool stores one 3x3 block
// C = h dv + h^2 dx per link (definite-mode Jacobians, so the system is symmetric positive
// definite), and the product is a pass over the links like the force pass. The "eigen" solver
// assembles the same blocks into a CSR matrix of fixed pattern (systems/eigen.cpp) for
// comparison; both are preconditioned conjugate gradients.
//
// Fixed and driven points are handled by constraint filtering: their rows and columns are
// projected out (residual and search directions are zero there), so dv = 0 on them and the
// filtered system stays SPD. Air drag enters the diagonal (df/dv = -gamma m); wind and plugged-in
// force stages are taken explicitly.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "contact_entry.hpp"
#include "implicit_system.hpp"
#include "implicit_vbd.hpp"
#include "integrators.hpp"
#include "maille/stage.hpp"
#include "step_residual.hpp"

namespace maille {

namespace {

class ImplicitEuler final : public Integrator {
 public:
  explicit ImplicitEuler(const ImplicitSettings& settings)
      : settings_(settings), vbd_(settings, 1) {}

  std::string_view name() const override { return kImplicitEuler; }

  std::string check(const Model& m) const override {
    for (const auto& pool : m.links.pools())
      if (!pool->has_jacobian())
        return "link kind '" + std::string(pool->keyword()) +
               "' provides no Jacobian: implicit_euler cannot integrate it";
    if (!parse_name<ImplicitSolver>(to_string(settings_.solver)))  // a value off its table
      return "unknown implicit solver (" + name_list<ImplicitSolver>() + ")";
    if (settings_.solver != ImplicitSolver::vbd &&
        !ImplicitSystems::builtin().find(to_string(settings_.solver)))
      return "implicit solver '" + std::string(to_string(settings_.solver)) +
             "' has no CG system (src/integrators/systems/: " + ImplicitSystems::builtin().names() +
             ")";
    return {};
  }

  void advance(const Model& m, State& s, Real h, ForceEvaluator& forces,
               Profile& profile) override {
    if (solver_iterations_ < 0) {
      solver_iterations_ = profile.counter("solver_iterations");
      solver_residual_ = profile.gauge("solver_residual");
      vbd_ = VertexBlockDescent(settings_, threads_);
    }
    if (settings_.solver == ImplicitSolver::vbd) {
      vbd_.begin(m, s, h, s.time + h, forces);
      if (vbd_colours_ < 0) {
        vbd_colours_ = profile.counter("vbd_colours");
        vbd_resets_ = profile.counter("vbd_acceleration_resets");
        vbd_refreshes_ = profile.counter("vbd_candidate_refreshes");
        vbd_candidates_ = profile.counter("vbd_contact_candidates");
        vbd_swept_ = profile.counter("vbd_contact_candidates_swept");
      }
      const VbdResult r = vbd_.solve(m, s, h);
      if (r.stopped) return;  // the simulator puts the step's start back
      profile.set_count(solver_iterations_, std::uint64_t(r.sweeps));
      profile.set_count(vbd_colours_, std::uint64_t(r.colours));
      profile.set_count(vbd_resets_, std::uint64_t(r.acceleration_resets));
      profile.set_count(vbd_refreshes_, std::uint64_t(r.candidate_refreshes));
      profile.set_count(vbd_candidates_, r.candidates);
      profile.set_count(vbd_swept_, r.candidates_swept);
      profile.set_gauge(solver_residual_, vbd_.residual(m, s, h));
    } else {
      const std::uint64_t iterations = advance_cg(m, s, h, forces, profile);
      if (forces.stop_requested()) return;  // stopped inside: the step's start comes back
      profile.set_count(solver_iterations_, iterations);
      profile.set_gauge(solver_residual_, residual_.end(m, s, h, forces.contacts()));
    }
  }

  // Baraff-Witkin by conjugate gradients (matrix_free or eigen); returns the CG iterations.
  std::uint64_t advance_cg(const Model& m, State& s, Real h, ForceEvaluator& forces,
                           Profile& profile) {
    if (!system_) {
      system_ = make_implicit_system(settings_.solver, m, threads_);
      cg_iterations_ = profile.counter("cg_iterations");
      cg_residual_ = profile.gauge("cg_residual");
      newton_residual_ = profile.gauge("newton_residual");
    }
    const std::size_t n = s.size();
    if (x0_.size() != n) {
      x0_.assign(n, Vec3{});
      v0_.assign(n, Vec3{});
      rhs_.assign(n, Vec3{});
      dv_.assign(n, Vec3{});
      contact_f_.assign(n, Vec3{});
      contact_blocks_.assign(n, Mat3{});
    }
    const auto x = s.x(), v = s.v();
    std::copy(x.begin(), x.end(), x0_.begin());
    std::copy(v.begin(), v.end(), v0_.begin());
    start_contacts(m, s, h, forces);

    std::uint64_t iterations = 0;
    double residual = 0;
    for (int k = 0; k < settings_.newton_iterations; ++k) {
      if (k > 0 && forces.stop_requested()) return iterations;
      if (k > 0) {  // forces at the current guess: x_n + h v_k, v_k; the step's contact set
        for (std::size_t i = 0; i < n; ++i)
          if (m.points.inv_mass[i] > 0) x[i] = x0_[i] + v[i] * h;
        s.time += h;
        forces.evaluate_keeping_contacts(s);
        s.time -= h;
        if (forces.failed()) return iterations;  // a stage refused the iterate (not finite)
        contact_forces(s, h, forces.contacts());
      }
      build_rhs(m, s, h, k == 0);
      system_->linearise(m, s, h, k == 0 ? rhs_.data() : nullptr, forces.contacts());
      const auto r =
          system_->solve(rhs_, dv_, settings_.tolerance, settings_.max_iterations, &forces);
      iterations += static_cast<std::uint64_t>(r.iterations);
      if (r.stopped) return iterations;
      residual = r.relative_residual;
      for (std::size_t i = 0; i < n; ++i) v[i] += dv_[i];
      if (k + 1 < settings_.newton_iterations && newton_converged(m, s)) break;
    }
    // Positions from the new velocities; fixed points stay (their velocity is a drive's).
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = m.points.inv_mass[i] > 0 ? x0_[i] + v[i] * h : x0_[i];
      finite = finite && is_finite(v[i]);
    }
    // A solve that diverged (or a stage that refused a non-finite iterate) goes no further:
    // the contact passes below search grids, and the simulator's health check names the point.
    if (!finite || forces.failed()) return iterations;
    // Obstacles: a point the linearised step carried into a contact it did not touch at x_n,
    // or through a thin one, stops where it entered it (continuous detection, as in VBD).
    entry_.stop_at_entry(free_, x.data(), v.data(), h);
    // Point-triangle candidates: no point crosses a face on its way to the solved position
    // (conservative bounds, implicit_vbd.hpp), nor meets a pair the search left out.
    if (const auto tri = forces.contacts().stencils(); !tri.empty()) {
      target_.assign(x.begin(), x.end());
      std::copy(x0_.begin(), x0_.end(), x.begin());
      advance_guarded(m, s, h, forces);
      for (std::size_t i = 0; i < n; ++i)
        if (m.points.inv_mass[i] > 0) v[i] = (x[i] - x0_[i]) * (Real(1) / h);
    }
    profile.set_count(cg_iterations_, iterations);
    profile.set_gauge(cg_residual_, residual);
    profile.set_gauge(newton_residual_, newton_residual_value_);
    return iterations;
  }

  // From x_n toward the solved positions (target_) in at most kBoundStages stages: each point
  // within its conservative bound and its drift limit (drift_guard.hpp); a point held at its
  // drift limit has the stages search again at the stage's positions before the next one.
  void advance_guarded(const Model& m, State& s, Real h, ForceEvaluator& forces) {
    const auto tri = forces.contacts().stencils();
    const auto x = s.x(), v = s.v();
    guard_.first_search(tri, m, x0_.data(), v0_.data(), h);
    guard_.take_common(target_.data());
    bound_.resize(x.size());
    for (int k = 0; k < kBoundStages; ++k) {
      conservative_bounds(tri, x.data(), bound_);
      bool arrived = true;
      for (std::size_t i = 0; i < x.size(); ++i) {
        if (!(m.points.inv_mass[i] > 0)) continue;
        x[i] = guard_.hold(std::uint32_t(i), x[i], within_bound(x[i], target_[i], bound_[i]));
        arrived = arrived && x[i] == target_[i];
      }
      if (arrived) return;
      if (!guard_.search_due() || k + 1 == kBoundStages) continue;
      for (std::size_t i = 0; i < x.size(); ++i)
        if (m.points.inv_mass[i] > 0) v[i] = (x[i] - x0_[i]) * (Real(1) / h);
      const std::span<const std::uint32_t> moved = guard_.moved(x.data());  // empty: everywhere
      if (!forces.find_contacts_again(s, moved)) continue;
      if (moved.empty())
        guard_.searched_again(x.data());
      else
        guard_.searched_near(x.data());
    }
  }

  // (I - hA)^-1 - I = (I - hA)^-1 hA with A = [[0, 1], [-w2, -c]]: every step is stable.
  Amplification increment(double h, double w2, double c) const override {
    const double det = 1 + h * c + h * h * w2;
    return {{{-h * h * w2 / det, h / det}, {-h * w2 / det, (-h * h * w2 - h * c) / det}}};
  }
  int force_evaluations() const override {
    return settings_.solver == ImplicitSolver::vbd ? 1 : settings_.newton_iterations;
  }
  void set_threads(int threads) override {
    threads_ = threads;
    vbd_.set_threads(threads);
    if (system_) system_->set_threads(threads);
  }

  void reset() override {
    system_.reset();
    vbd_.reset();
  }
  bool uses_jacobians() const override { return true; }
  const ImplicitSettings* implicit_settings() const override { return &settings_; }
  // A response stage run before the solve would zero a velocity into a facet, then the solve's
  // dv, coupled to every neighbour, would undo it: facets answer the solved motion instead.
  ResponseTiming response_timing() const override { return ResponseTiming::after_solve; }

 private:
  // The step's start for the point contacts, as VBD takes it: placed at t_n (the residual's
  // explicit forces are taken there), then lagged for the solve (friction's normal force held)
  // and moved to t_n+1; continuous detection from x_n.
  void start_contacts(const Model& m, const State& s, Real h, ForceEvaluator& forces) {
    const auto contacts = forces.contacts().obstacles();
    free_.clear();
    for (std::uint32_t i = 0; i < s.size(); ++i)
      if (m.points.inv_mass[i] > 0) free_.push_back(i);
    for (PointContacts* c : contacts) c->set_time(s.time);
    contact_forces(s, h, forces.contacts());
    residual_.begin(m, s, h, free_);
    for (PointContacts* c : contacts) c->lag(free_, s.x().data(), s.v().data(), s.time + h);
    entry_.begin(contacts, x0_.data(), s.size());
  }

  // The contact set's forces at s (obstacles where their set_time or lag placed them), apart
  // from s.f(), which holds every other force.
  void contact_forces(const State& s, Real h, const ContactSet& set) {
    std::fill(contact_f_.begin(), contact_f_.end(), Vec3{});
    set.add_forces(free_, s.x().data(), s.v().data(), Real(1) / h, contact_f_.data(),
                   contact_blocks_.data());
  }

  // Iteration 0 (Baraff-Witkin): b = h f(x_n, v_n), plus h^2 df/dx v_n added by the pools.
  // Newton iteration k: b = h f(x_n + h v_k, v_k) - M (v_k - v_n). f: s.f() and the contacts.
  void build_rhs(const Model& m, const State& s, Real h, bool first) {
    const auto f = s.f(), v = s.v();
    for (std::size_t i = 0; i < rhs_.size(); ++i) {
      rhs_[i] = (f[i] + contact_f_[i]) * h;
      if (!first) rhs_[i] -= (v[i] - v0_[i]) * m.points.mass[i];
    }
  }

  // Newton stops early when the update is small against the velocities.
  bool newton_converged(const Model& m, const State& s) {
    double dv2 = 0, v2 = 1e-30;
    for (std::size_t i = 0; i < dv_.size(); ++i)
      if (m.points.inv_mass[i] > 0) {
        dv2 += norm2(dv_[i]);
        v2 += norm2(s.v()[i]);
      }
    newton_residual_value_ = std::sqrt(dv2 / v2);
    return newton_residual_value_ < settings_.tolerance;
  }

  ImplicitSettings settings_;
  std::unique_ptr<ImplicitSystem> system_;
  std::vector<Real> bound_;   // conservative bounds of the CG solvers' step
  std::vector<Vec3> target_;  // the solved positions, reached in bounded stages
  DriftGuard guard_;          // the stencil stages' drift limits in those stages
  // Stages toward the solved positions: each closes at most 0.8 of a gap, so a point within a
  // contact's reach of its face stops there after a few; eight leave 0.2^8 of a far one's way.
  static constexpr int kBoundStages = 8;
  VertexBlockDescent vbd_;           // solver = "vbd"
  StepResidual residual_;            // the CG solvers' solver_residual
  ContactEntry entry_;               // the CG solvers' continuous detection against point contacts
  std::vector<std::uint32_t> free_;  // free points
  int solver_iterations_ = -1, solver_residual_ = -1, vbd_colours_ = -1, vbd_resets_ = -1,
      vbd_refreshes_ = -1, vbd_candidates_ = -1, vbd_swept_ = -1;
  std::vector<Vec3> x0_, v0_, rhs_, dv_;
  std::vector<Vec3> contact_f_;       // the contact set's forces at the current iterate
  std::vector<Mat3> contact_blocks_;  // their obstacles' blocks (scratch)
  int cg_iterations_ = 0, cg_residual_ = 0, newton_residual_ = 0;
  double newton_residual_value_ = 0;
};

}  // namespace

std::unique_ptr<Integrator> make_implicit_euler(const ImplicitSettings& settings) {
  return std::make_unique<ImplicitEuler>(settings);
}

}  // namespace maille
