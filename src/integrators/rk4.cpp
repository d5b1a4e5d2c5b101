// Classical fourth-order Runge-Kutta on (x, v):
//   k1 = F(t, y), k2 = F(t + h/2, y + h/2 k1), k3 = F(t + h/2, y + h/2 k2), k4 = F(t + h, y + h k3)
//   y(n+1) = y(n) + h/6 (k1 + 2 k2 + 2 k3 + k4),   F(x, v) = (v, f(x, v)/m)
// Four force passes per step, evaluated at intermediate states: stages that rewrite forces or
// velocities after the fact (facet responses) cannot be combined with it.
#include <cstdint>
#include <vector>

#include "integrators.hpp"

namespace maille {

namespace {

class Rk4 final : public MultiPassScheme<4> {
 public:
  std::string_view name() const override { return "rk4"; }

  void advance(const Model& m, State& s, Real h, ForceEvaluator& forces, Profile&) override {
    const std::size_t n = s.size();
    if (x0_.size() != n) {  // sized once: no allocation in later steps
      for (auto* a : {&x0_, &v0_, &kx_, &kv_, &sum_x_, &sum_v_}) a->assign(n, Vec3{});
    }
    const double t0 = s.time;
    const Real* w = m.points.inv_mass.data();
    copy_in(s, w);
    // Stages 2 to 4: y = y0 + c h k_prev, evaluate, accumulate with weight 2, 2, 1.
    const Real c[3] = {Real(0.5) * h, Real(0.5) * h, h};
    const Real weight[3] = {2, 2, 1};
    for (int stage = 0; stage < 3; ++stage) {
      set_stage(s, c[stage]);
      s.time = t0 + c[stage];
      forces.evaluate(s);
      gather(s, w, weight[stage]);
    }
    s.time = t0;
    finish(s, w, h / 6);
  }

  // hA + (hA)^2/2 + (hA)^3/6 + (hA)^4/24 = hA (I + hA/2 (I + hA/3 (I + hA/4))), A the test
  // equation's matrix [[0, 1], [-w2, -c]].
  Amplification increment(double h, double w2, double c) const override {
    const Amplification ha{{{0, h}, {-h * w2, -h * c}}};
    Amplification r{{{1, 0}, {0, 1}}};
    for (int k = 4; k >= 2; --k) {
      Amplification t = multiply(ha, r);
      for (auto& row : t)
        for (double& e : row) e /= k;
      r = {{{1 + t[0][0], t[0][1]}, {t[1][0], 1 + t[1][1]}}};
    }
    return multiply(ha, r);
  }

 private:
  // k1 = (v0, f0/m): start the weighted sums with it.
  void copy_in(const State& s, const Real* w) {
    const auto x = s.x(), v = s.v(), f = s.f();
    for (std::size_t i = 0; i < x0_.size(); ++i) {
      x0_[i] = x[i];
      v0_[i] = v[i];
      kx_[i] = v[i];
      kv_[i] = f[i] * w[i];
      sum_x_[i] = kx_[i];
      sum_v_[i] = kv_[i];
    }
  }
  void set_stage(State& s, Real c) {
    auto x = s.x(), v = s.v();
    for (std::size_t i = 0; i < x0_.size(); ++i) {
      x[i] = x0_[i] + kx_[i] * c;
      v[i] = v0_[i] + kv_[i] * c;
    }
  }
  void gather(const State& s, const Real* w, Real weight) {
    const auto v = s.v(), f = s.f();
    for (std::size_t i = 0; i < x0_.size(); ++i) {
      kx_[i] = v[i];
      kv_[i] = f[i] * w[i];
      sum_x_[i] += kx_[i] * weight;
      sum_v_[i] += kv_[i] * weight;
    }
  }
  // Fixed points stay where they were (their stage velocity may be a drive's, not theirs).
  void finish(State& s, const Real* w, Real h6) {
    auto x = s.x(), v = s.v();
    for (std::size_t i = 0; i < x0_.size(); ++i) {
      const bool moves = w[i] > 0;
      x[i] = moves ? x0_[i] + sum_x_[i] * h6 : x0_[i];
      v[i] = moves ? v0_[i] + sum_v_[i] * h6 : v0_[i];
    }
  }

  std::vector<Vec3> x0_, v0_, kx_, kv_, sum_x_, sum_v_;
};

}  // namespace

std::unique_ptr<Integrator> make_rk4() {
  return std::make_unique<Rk4>();
}

}  // namespace maille
