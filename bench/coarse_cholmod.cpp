// CHOLMOD on VBD's coarse matrix (coarse_cholmod.hpp).
#include "coarse_cholmod.hpp"

#include <cholmod.h>

#include <algorithm>
#include <cstring>

namespace maille {

struct CholmodFactor::Impl {
  cholmod_common common{};
  cholmod_sparse* a = nullptr;
  cholmod_factor* l = nullptr;
  cholmod_dense* b = nullptr;
  cholmod_dense* x = nullptr;  // cholmod_solve2 reuses x, y and e once they exist
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  std::size_t n = 0, nonzeros = 0;

  explicit Impl(bool supernodal) {
    cholmod_start(&common);
    common.print = 0;  // a matrix that is not positive definite is an answer, not a message
    common.supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_NATURAL;  // already in AMD order (vbd_coarse.cpp)
    common.postorder = 1;
  }
  ~Impl() {
    cholmod_free_dense(&b, &common);
    cholmod_free_dense(&x, &common);
    cholmod_free_dense(&y, &common);
    cholmod_free_dense(&e, &common);
    cholmod_free_factor(&l, &common);
    cholmod_free_sparse(&a, &common);
    cholmod_finish(&common);
  }
};

CholmodFactor::CholmodFactor(bool supernodal) : impl_(std::make_unique<Impl>(supernodal)) {}
CholmodFactor::~CholmodFactor() = default;

bool CholmodFactor::analyse(int n, const int* column_start, const int* rows) {
  Impl& c = *impl_;
  c.n = std::size_t(n);
  c.nonzeros = std::size_t(column_start[n]);
  // stype 1: the upper triangle holds the symmetric matrix.
  c.a = cholmod_allocate_sparse(c.n, c.n, c.nonzeros, 1, 1, 1, CHOLMOD_REAL, &c.common);
  c.b = cholmod_zeros(c.n, 1, CHOLMOD_REAL, &c.common);
  if (!c.a || !c.b) return false;
  std::memcpy(c.a->p, column_start, sizeof(int) * (c.n + 1));
  std::memcpy(c.a->i, rows, sizeof(int) * c.nonzeros);
  std::fill_n(static_cast<double*>(c.a->x), c.nonzeros, 0.0);
  c.l = cholmod_analyze(c.a, &c.common);
  return c.l != nullptr;
}

bool CholmodFactor::factor(const double* values) {
  Impl& c = *impl_;
  if (!c.l) return false;
  std::memcpy(c.a->x, values, sizeof(double) * c.nonzeros);
  const int ok = cholmod_factorize(c.a, c.l, &c.common);
  return ok && c.common.status == CHOLMOD_OK && c.l->minor == c.n;
}

void CholmodFactor::solve(const double* b, double* x) {
  Impl& c = *impl_;
  std::memcpy(c.b->x, b, sizeof(double) * c.n);
  cholmod_solve2(CHOLMOD_A, c.l, c.b, nullptr, &c.x, nullptr, &c.y, &c.e, &c.common);
  std::memcpy(x, c.x->x, sizeof(double) * c.n);
}

}  // namespace maille
