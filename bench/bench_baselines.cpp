// Reference loops, measured in the same run as the engine so that ratios mean something on a
// shared, noisy machine:
//   BM_GenericLinkList  the textbook loop: one array of link records {a, b, k, L0, z}, one fused
//                       gather-compute-scatter pass, AoS positions (what course codes do);
//   BM_StructuredGrid   the best case for a regular grid: struct-of-arrays positions and one
//                       contiguous, vectorised pass per link family (no index arrays at all).
// Both compute exactly the flag's physics (structural, shear and bending spring-dampers,
// gravity, leapfrog), so their ns per particle-step compare directly with BM_FlagStep (all in
// wall-clock time, as BM_FlagStep's thread counts need).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace {

struct LinkRecord {
  std::uint32_t a, b;
  double k, rest, z;
};
struct P3 {
  double x = 0, y = 0, z = 0;
};

struct FlagTopology {
  int n;
  std::vector<std::pair<int, int>> offsets;  // (di, dj) of the link families
  std::vector<double> stiffness;
};

FlagTopology topology(int n) {
  return {n, {{1, 0}, {0, 1}, {1, 1}, {-1, 1}, {2, 0}, {0, 2}}, {200, 200, 100, 100, 20, 20}};
}

void BM_GenericLinkList(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const FlagTopology t = topology(n);
  const double h = 1e-5, m = 0.2 / (n * n), dx = 1.0 / (n - 1);
  std::vector<P3> x(n * n), v(n * n), f(n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) x[j * n + i] = {i * dx, j * dx, 0};
  std::vector<LinkRecord> links;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (std::size_t o = 0; o < t.offsets.size(); ++o) {
        const int i2 = i + t.offsets[o].first, j2 = j + t.offsets[o].second;
        if (i2 < 0 || i2 >= n || j2 >= n) continue;
        const int a = j * n + i, b = j2 * n + i2;
        const double r = std::hypot(x[b].x - x[a].x, x[b].y - x[a].y);
        links.push_back({std::uint32_t(a), std::uint32_t(b), t.stiffness[o], r, 0.02});
      }
  for (auto _ : st) {
    for (auto& q : f) q = {};
    for (const LinkRecord& l : links) {
      const double ddx = x[l.b].x - x[l.a].x, ddy = x[l.b].y - x[l.a].y, ddz = x[l.b].z - x[l.a].z;
      const double len = std::sqrt(ddx * ddx + ddy * ddy + ddz * ddz);
      const double nx = ddx / len, ny = ddy / len, nz = ddz / len;
      const double vr =
          (v[l.b].x - v[l.a].x) * nx + (v[l.b].y - v[l.a].y) * ny + (v[l.b].z - v[l.a].z) * nz;
      const double s = l.k * (len - l.rest) + l.z * vr;
      f[l.a].x += s * nx, f[l.a].y += s * ny, f[l.a].z += s * nz;
      f[l.b].x -= s * nx, f[l.b].y -= s * ny, f[l.b].z -= s * nz;
    }
    for (int p = n; p < n * n; ++p) {  // row 0 is the pole: fixed
      f[p].y -= m * 9.81;
      v[p].x += h * f[p].x / m, v[p].y += h * f[p].y / m, v[p].z += h * f[p].z / m;
      x[p].x += h * v[p].x, x[p].y += h * v[p].y, x[p].z += h * v[p].z;
    }
    benchmark::ClobberMemory();
  }
  st.counters["ns_pps"] =
      benchmark::Counter(double(st.iterations()) * n * n * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_StructuredGrid(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), N = n * n;
  const FlagTopology t = topology(n);
  const double h = 1e-5, m = 0.2 / N, dx = 1.0 / (n - 1);
  std::vector<double> X(N), Y(N), Z(N), VX(N), VY(N), VZ(N), FX(N), FY(N), FZ(N);
  std::vector<double> lx(N), ly(N), lz(N);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) X[j * n + i] = i * dx, Y[j * n + i] = j * dx;
  for (auto _ : st) {
    std::fill(FX.begin(), FX.end(), 0.0);
    std::fill(FY.begin(), FY.end(), 0.0);
    std::fill(FZ.begin(), FZ.end(), 0.0);
    for (std::size_t o = 0; o < t.offsets.size(); ++o) {
      const int di = t.offsets[o].first, dj = t.offsets[o].second, off = dj * n + di;
      const double k = t.stiffness[o], rest = dx * std::hypot(di, dj), z = 0.02;
      const int i0 = di < 0 ? -di : 0, i1 = n - (di > 0 ? di : 0);
      for (int j = 0; j + dj < n; ++j) {
        const int row = j * n;
        for (int i = i0; i < i1; ++i) {  // contiguous: vectorises
          const int a = row + i, b = a + off;
          const double ex = X[b] - X[a], ey = Y[b] - Y[a], ez = Z[b] - Z[a];
          const double inv = 1 / std::sqrt(ex * ex + ey * ey + ez * ez);
          const double vr =
              ((VX[b] - VX[a]) * ex + (VY[b] - VY[a]) * ey + (VZ[b] - VZ[a]) * ez) * inv;
          const double s = (k * (1 - rest * inv) + z * vr * inv);
          lx[a] = s * ex, ly[a] = s * ey, lz[a] = s * ez;
        }
        for (int i = i0; i < i1; ++i)
          FX[row + i] += lx[row + i], FY[row + i] += ly[row + i], FZ[row + i] += lz[row + i];
        for (int i = i0; i < i1; ++i)
          FX[row + i + off] -= lx[row + i], FY[row + i + off] -= ly[row + i],
              FZ[row + i + off] -= lz[row + i];
      }
    }
    for (int p = n; p < N; ++p) {
      FY[p] -= m * 9.81;
      VX[p] += h * FX[p] / m, VY[p] += h * FY[p] / m, VZ[p] += h * FZ[p] / m;
      X[p] += h * VX[p], Y[p] += h * VY[p], Z[p] += h * VZ[p];
    }
    benchmark::ClobberMemory();
  }
  st.counters["ns_pps"] =
      benchmark::Counter(double(st.iterations()) * N * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The structured stencil fused with integration: rows in order, each row's links (every family
// whose first end is in the row) into row buffers and scattered, then the row whose forces are
// complete (it receives only from its own and the two rows below) integrated at once, its force
// cleared for the next step. Per-family rest length and stiffness, contiguous loops, SoA: the
// reference the engine's structured grid kernel is measured against.
void BM_StructuredStencilFused(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), N = n * n;
  const FlagTopology t = topology(n);
  const double h = 1e-5, m = 0.2 / N, dx = 1.0 / (n - 1), inv_m = 1 / m;
  std::vector<double> X(N), Y(N), Z(N), VX(N), VY(N), VZ(N), FX(N), FY(N), FZ(N);
  std::vector<double> lx(n), ly(n), lz(n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) X[j * n + i] = i * dx, Y[j * n + i] = j * dx;
  std::vector<double> rest(t.offsets.size());
  for (std::size_t o = 0; o < t.offsets.size(); ++o)
    rest[o] = dx * std::hypot(t.offsets[o].first, t.offsets[o].second);
  for (auto _ : st) {
    for (int j = 0; j < n; ++j) {
      const int row = j * n;
      for (std::size_t o = 0; o < t.offsets.size(); ++o) {
        const int di = t.offsets[o].first, dj = t.offsets[o].second, off = dj * n + di;
        if (j + dj >= n) continue;
        const double k = t.stiffness[o], r0 = rest[o], z = 0.02;
        const int i0 = di < 0 ? -di : 0, i1 = n - (di > 0 ? di : 0);
        for (int i = i0; i < i1; ++i) {  // contiguous: vectorises
          const int a = row + i, b = a + off;
          const double ex = X[b] - X[a], ey = Y[b] - Y[a], ez = Z[b] - Z[a];
          const double inv = 1 / std::sqrt(ex * ex + ey * ey + ez * ez);
          const double vr =
              ((VX[b] - VX[a]) * ex + (VY[b] - VY[a]) * ey + (VZ[b] - VZ[a]) * ez) * inv;
          const double s = (k * (1 - r0 * inv) + z * vr * inv);
          lx[i] = s * ex, ly[i] = s * ey, lz[i] = s * ez;
        }
        for (int i = i0; i < i1; ++i)
          FX[row + i] += lx[i], FY[row + i] += ly[i], FZ[row + i] += lz[i];
        for (int i = i0; i < i1; ++i)
          FX[row + i + off] -= lx[i], FY[row + i + off] -= ly[i], FZ[row + i + off] -= lz[i];
      }
      if (j > 0)  // row 0 is the pole: fixed
        for (int p = row; p < row + n; ++p) {
          VX[p] += h * FX[p] * inv_m, VY[p] += h * (FY[p] - m * 9.81) * inv_m,
              VZ[p] += h * FZ[p] * inv_m;
          X[p] += h * VX[p], Y[p] += h * VY[p], Z[p] += h * VZ[p];
        }
      for (int p = row; p < row + n; ++p) FX[p] = FY[p] = FZ[p] = 0;
    }
    benchmark::ClobberMemory();
  }
  st.counters["ns_pps"] =
      benchmark::Counter(double(st.iterations()) * N * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The fused stencil in the engine's data layout, to see where the engine's extra time goes:
// positions, velocities and forces as arrays of 3-vectors (the State's layout) instead of
// three arrays each, and, with kPerLink, each link's stiffness, rest length and damping read
// from per-link arrays in the rows' order (the link pools' records) instead of one constant
// per family. Same rows, same fusion as BM_StructuredStencilFused.
template <bool kPerLink>
void BM_StencilFusedAoS(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0)), N = n * n;
  const FlagTopology t = topology(n);
  const double h = 1e-5, m = 0.2 / N, dx = 1.0 / (n - 1), inv_m = 1 / m;
  std::vector<P3> x(N), v(N), f(N);
  std::vector<P3> l(n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) x[j * n + i] = {i * dx, j * dx, 0};
  const std::size_t families = t.offsets.size();
  std::vector<double> rest(families);
  for (std::size_t o = 0; o < families; ++o)
    rest[o] = dx * std::hypot(t.offsets[o].first, t.offsets[o].second);
  // Per-link parameters, family by family, row by row (n entries per row, unused at the ends).
  std::vector<double> pk(kPerLink ? families * N : 0), pr(pk.size()), pz(pk.size());
  for (std::size_t o = 0; o < families && kPerLink; ++o)
    for (int a = 0; a < N; ++a)
      pk[o * N + a] = t.stiffness[o], pr[o * N + a] = rest[o], pz[o * N + a] = 0.02;
  for (auto _ : st) {
    for (int j = 0; j < n; ++j) {
      const int row = j * n;
      for (std::size_t o = 0; o < families; ++o) {
        const int di = t.offsets[o].first, dj = t.offsets[o].second, off = dj * n + di;
        if (j + dj >= n) continue;
        const double k0 = t.stiffness[o], r0 = rest[o], z0 = 0.02;
        const double* K = kPerLink ? pk.data() + o * N : nullptr;
        const double* R = kPerLink ? pr.data() + o * N : nullptr;
        const double* Zs = kPerLink ? pz.data() + o * N : nullptr;
        const int i0 = di < 0 ? -di : 0, i1 = n - (di > 0 ? di : 0);
        for (int i = i0; i < i1; ++i) {
          const int a = row + i, b = a + off;
          const double k = kPerLink ? K[a] : k0, r = kPerLink ? R[a] : r0,
                       z = kPerLink ? Zs[a] : z0;
          const double ex = x[b].x - x[a].x, ey = x[b].y - x[a].y, ez = x[b].z - x[a].z;
          const double inv = 1 / std::sqrt(ex * ex + ey * ey + ez * ez);
          const double vr =
              ((v[b].x - v[a].x) * ex + (v[b].y - v[a].y) * ey + (v[b].z - v[a].z) * ez) * inv;
          const double s = (k * (1 - r * inv) + z * vr * inv);
          l[i] = {s * ex, s * ey, s * ez};
        }
        for (int i = i0; i < i1; ++i)
          f[row + i].x += l[i].x, f[row + i].y += l[i].y, f[row + i].z += l[i].z;
        for (int i = i0; i < i1; ++i)
          f[row + i + off].x -= l[i].x, f[row + i + off].y -= l[i].y, f[row + i + off].z -= l[i].z;
      }
      if (j > 0)
        for (int p = row; p < row + n; ++p) {
          v[p].x += h * f[p].x * inv_m, v[p].y += h * (f[p].y - m * 9.81) * inv_m,
              v[p].z += h * f[p].z * inv_m;
          x[p].x += h * v[p].x, x[p].y += h * v[p].y, x[p].z += h * v[p].z;
        }
      for (int p = row; p < row + n; ++p) f[p] = {};
    }
    benchmark::ClobberMemory();
  }
  st.counters["ns_pps"] =
      benchmark::Counter(double(st.iterations()) * N * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

// One thread each: ns_pps from CPU time (a busy shared machine takes wall time away from any
// process; the CPU time of a one-thread loop does not depend on it).
BENCHMARK(BM_GenericLinkList)->Arg(32)->Arg(64)->Arg(128)->Arg(512)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StructuredGrid)->Arg(32)->Arg(64)->Arg(128)->Arg(512)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StructuredStencilFused)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Arg(512)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_StencilFusedAoS, false)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Arg(512)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_StencilFusedAoS, true)
    ->Arg(32)
    ->Arg(64)
    ->Arg(128)
    ->Arg(512)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GenericLinkList)->Arg(2048)->Iterations(3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StructuredGrid)->Arg(2048)->Iterations(3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StructuredStencilFused)->Arg(2048)->Iterations(3)->Unit(benchmark::kMicrosecond);
