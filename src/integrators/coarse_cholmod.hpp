// Internal: the coarse correction's factorisation by CHOLMOD's supernodal Cholesky (Debian's
// libsuitesparse-dev; built in only where it is found: src/CMakeLists.txt defines
// MAILLE_HAVE_CHOLMOD). vbd_coarse.cpp uses it when `[simulation.implicit] coarse_factor =
// "cholmod"`; docs/implicit.md ("The coarse correction") has the measurement against Eigen's LDL^T.
//
// The pattern is analysed once (the coarse matrix's pattern is fixed for a model: contacts add
// to its diagonal blocks only), each correction refactorises numerically. The matrix comes in
// already in its fill-reducing order (Eigen's AMD, as for the LDL^T), so CHOLMOD keeps the
// natural order (and its elimination tree's postorder, which makes its supernodes).
#pragma once

#include <memory>

namespace maille {

class CholmodFactor {
 public:
  CholmodFactor();
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  // The symbolic factorisation of an n x n symmetric matrix given by its upper triangle in
  // compressed columns (sorted rows). Allocates; false when CHOLMOD fails.
  bool analyse(int n, const int* column_start, const int* rows);
  // The numeric factorisation with `values` (the analysed pattern's order); false when the
  // matrix is not positive definite.
  bool factor(const double* values);
  // x = A^-1 b (n values each); needs a successful factor().
  void solve(const double* b, double* x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace maille
