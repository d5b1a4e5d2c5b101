// CHOLMOD (Debian's libsuitesparse-dev) on VBD's coarse matrix, for bench_coarse_factor.cpp's
// comparison with the engine's factorisation (Eigen's simplicial LDL^T, src/integrators/
// vbd_coarse.cpp). Benchmark-only: measured slower than Eigen's on these matrices with the BLAS
// Debian installs beside it, so the engine does not use it (docs/implicit.md, "The coarse
// correction").
//
// As the engine does: the pattern analysed once, each call a numeric refactorisation. The
// matrix comes in already in its fill-reducing order (Eigen's AMD), so CHOLMOD keeps the natural
// order (with its elimination tree's postorder, which makes its supernodes).
#pragma once

#include <memory>

namespace maille {

class CholmodFactor {
 public:
  // supernodal: CHOLMOD's supernodal LL^T (BLAS on dense blocks), else its simplicial LDL^T.
  explicit CholmodFactor(bool supernodal);
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
