// Vertex block descent's loops over a pool's links (maille/link_loops.hpp). The links of a run
// of points are gathered into batches (the active ones, in each point's slot order), the kind's
// law evaluated over a batch in one call (in lanes for kinds with the axial form, SpringDamper's:
// the axis from the point to the link's other end, so that the force on the point is force d at
// either end), then summed point by point in slot order: the same sums, bit for bit, as the
// kind's block taken link by link (tests/unit/test_link_lanes.cpp).
#include <algorithm>
#include <cstdint>

#include "maille/link_loops.hpp"

namespace maille {
namespace {

constexpr std::size_t kBatch = 64;

// A batch of gathered links: the slot of each, the point it is gathered for.
struct Batch {
  std::uint32_t slot[kBatch];
  std::uint32_t owner[kBatch];
  std::uint8_t active[kBatch];
  std::size_t n = 0;

  // Appends the links of point i (slots[row[i]] .. slots[row[i + 1] - 1]), running `flush`
  // each time the batch is full.
  template <class Flush>
  void add_point(std::uint32_t i, const std::uint32_t* row, const std::uint32_t* slots,
                 Flush& flush) {
    for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) {
      slot[n] = slots[k];
      owner[n] = i;
      if (++n == kBatch) flush();
    }
  }

  // Keeps the active links of the batch (in order); returns how many.
  std::size_t keep_active(const LinkPoolBase& pool, const Vec3* x) {
    if (!pool.conditional()) return n;
    pool.active_mask(slot, n, x, active);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (active[k]) {
        slot[kept] = slot[k];
        owner[kept] = owner[k];
        ++kept;
      }
    n = kept;
    return kept;
  }
};

// One point's running sums, carried across batches and added to f and hessian when the next
// point starts (or at the end). Points with no active link are never started: f untouched.
struct PointSum {
  std::uint32_t current = ~std::uint32_t(0);
  Vec3 fi{};
  Mat3 hi;

  void to(std::uint32_t point, Vec3* f, Mat3* hessian) {
    if (point == current) return;
    commit(f, hessian);
    current = point;
    fi = Vec3{};
    hi = Mat3{};
  }
  void commit(Vec3* f, Mat3* hessian) const {
    if (current == ~std::uint32_t(0)) return;
    f[current] += fi;
    hessian[current] += hi;
  }
};

// Kinds with the axial form.
void axial_point_terms(const LinkPoolBase& pool, std::span<const std::uint32_t> points,
                       const std::uint32_t* row, const std::uint32_t* slots, const Vec3* x,
                       const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian) {
  const LinkEnds* ends = pool.slot_ends().data();
  Batch batch;
  alignas(64) Real dx[kBatch], dy[kBatch], dz[kBatch], d2[kBatch], dvd[kBatch];
  alignas(64) Real force[kBatch], iso[kBatch], axial[kBatch];
  PointSum sum;
  auto flush = [&] {
    const std::size_t n = batch.keep_active(pool, x);
    for (std::size_t e = 0; e < n; ++e) {
      const auto [a, b] = ends[batch.slot[e]];
      const std::uint32_t i = batch.owner[e], j = a == i ? b : a;
      const Vec3 d = x[j] - x[i], dv = v[j] - v[i];
      dx[e] = d.x;
      dy[e] = d.y;
      dz[e] = d.z;
      d2[e] = dot(d, d);
      dvd[e] = dot(dv, d);
    }
    pool.axial_terms(batch.slot, n, d2, dvd, inv_h, force, iso, axial);
    for (std::size_t e = 0; e < n; ++e) {
      sum.to(batch.owner[e], f, hessian);
      const Vec3 d{dx[e], dy[e], dz[e]};
      sum.fi += d * force[e];
      sum.hi += axial_block(d, {force[e], iso[e], axial[e]});
    }
    batch.n = 0;
  };
  for (const std::uint32_t i : points) batch.add_point(i, row, slots, flush);
  flush();
  sum.commit(f, hessian);
}

// Kinds with a block (or a force and a Jacobian): every point of `points` adds its sums, even
// when none of its links acts.
void block_point_terms(const LinkPoolBase& pool, std::span<const std::uint32_t> points,
                       const std::uint32_t* row, const std::uint32_t* slots, const Vec3* x,
                       const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian) {
  const LinkEnds* ends = pool.slot_ends().data();
  Batch batch;
  std::uint32_t acting[kBatch];
  LinkBlock blocks[kBatch];
  PointSum sum;
  auto flush = [&] {
    const std::size_t n = batch.n;
    if (pool.conditional())
      pool.active_mask(batch.slot, n, x, batch.active);
    else
      std::fill_n(batch.active, n, std::uint8_t(1));
    std::size_t m = 0;
    for (std::size_t e = 0; e < n; ++e)
      if (batch.active[e]) acting[m++] = batch.slot[e];
    pool.vbd_blocks(acting, m, x, v, inv_h, blocks);
    for (std::size_t e = 0, r = 0; e < n; ++e) {
      const std::uint32_t i = batch.owner[e];
      sum.to(i, f, hessian);
      if (!batch.active[e]) continue;
      sum.fi += ends[batch.slot[e]].a == i ? blocks[r].force : -blocks[r].force;
      sum.hi += blocks[r].stiffness;
      ++r;
    }
    batch.n = 0;
  };
  for (const std::uint32_t i : points) {
    if (row[i] == row[i + 1]) {  // no link: f[i] and hessian[i] still get their (zero) sums
      flush();
      sum.to(i, f, hessian);
      continue;
    }
    batch.add_point(i, row, slots, flush);
  }
  flush();
  sum.commit(f, hessian);
}

}  // namespace

void add_point_terms(const LinkPoolBase& pool, std::span<const std::uint32_t> points,
                     const std::uint32_t* row, const std::uint32_t* slots, const Vec3* x,
                     const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian) {
  if (pool.has_axial())
    axial_point_terms(pool, points, row, slots, x, v, inv_h, f, hessian);
  else if (pool.has_jacobian())
    block_point_terms(pool, points, row, slots, x, v, inv_h, f, hessian);
}

void add_link_terms(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Real inv_h, Vec3* f,
                    Mat3* hessian, Mat3* blocks) {
  const auto ends = pool.slot_ends();
  Batch batch;
  for (std::size_t begin = 0; begin < ends.size(); begin += kBatch) {
    const std::size_t n = std::min(kBatch, ends.size() - begin);
    for (std::size_t e = 0; e < n; ++e) batch.slot[e] = std::uint32_t(begin + e);
    if (pool.has_axial() && !pool.conditional()) {
      alignas(64) Real d2[kBatch], dvd[kBatch], force[kBatch], iso[kBatch], axial[kBatch];
      Vec3 d[kBatch];
      for (std::size_t e = 0; e < n; ++e) {
        const auto [a, b] = ends[begin + e];
        d[e] = x[b] - x[a];
        d2[e] = dot(d[e], d[e]);
        dvd[e] = dot(v[b] - v[a], d[e]);
      }
      pool.axial_terms(batch.slot, n, d2, dvd, inv_h, force, iso, axial);
      for (std::size_t e = 0; e < n; ++e) {
        const auto [a, b] = ends[begin + e];
        const Vec3 fa = d[e] * force[e];
        const Mat3 k = axial_block(d[e], {force[e], iso[e], axial[e]});
        f[a] += fa;
        f[b] -= fa;
        hessian[a] += k;
        hessian[b] += k;
        blocks[begin + e] = k;
      }
    } else if (pool.has_jacobian()) {
      batch.n = n;
      for (std::size_t e = 0; e < n; ++e) blocks[begin + e] = Mat3{};  // inactive: zero
      const std::size_t kept = batch.keep_active(pool, x);
      LinkBlock terms[kBatch];
      pool.vbd_blocks(batch.slot, kept, x, v, inv_h, terms);
      for (std::size_t e = 0; e < kept; ++e) {
        const std::uint32_t l = batch.slot[e];
        const auto [a, b] = ends[l];
        f[a] += terms[e].force;
        f[b] -= terms[e].force;
        hessian[a] += terms[e].stiffness;
        hessian[b] += terms[e].stiffness;
        blocks[l] = terms[e].stiffness;
      }
    }
  }
}

}  // namespace maille
