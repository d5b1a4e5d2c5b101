#include "broad_phase.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "../thread_lists.hpp"
#include "maille/detail/csr.hpp"

namespace maille::collision {

void PartnerRows::build(const std::vector<Sink>& sinks, std::size_t points) {
  detail::build_rows(points, start, partners, [&](auto&& emit) {
    for (const auto& s : sinks)
      for (std::size_t k = 0; k < s.pairs.size(); k += 2) emit(s.pairs[k], s.pairs[k + 1]);
  });
  for (std::size_t a = 0; a < points; ++a)
    std::sort(partners.begin() + start[a], partners.begin() + start[a + 1]);
}

Real motion_margin(const Vec3* v, const std::vector<std::uint32_t>& set, Real h, bool absolute) {
  Vec3 mean{};
  if (!absolute)
    for (const std::uint32_t p : set) mean += v[p];
  mean = mean * (Real(1) / Real(std::max<std::size_t>(set.size(), 1)));
  Real dv2 = 0;
  for (const std::uint32_t p : set) dv2 = std::max(dv2, norm2(v[p] - mean));
  return kMotionFactor * std::sqrt(dv2) * h;
}

namespace {

// The 13 neighbour offsets after (0, 0, 0) in (z, y, x) order: with the cell itself they cover
// each pair of adjacent cells exactly once.
constexpr std::array<std::array<int, 3>, 13> kForward = {{{-1, -1, 1},
                                                          {0, -1, 1},
                                                          {1, -1, 1},
                                                          {-1, 0, 1},
                                                          {0, 0, 1},
                                                          {1, 0, 1},
                                                          {-1, 1, 1},
                                                          {0, 1, 1},
                                                          {1, 1, 1},
                                                          {-1, 1, 0},
                                                          {0, 1, 0},
                                                          {1, 1, 0},
                                                          {1, 0, 0}}};

// After a pass: any thread may find every pair next time (thread_lists.hpp). The callers give
// every sink the same cap.
void make_room(std::vector<Sink>& sinks) {
  if (!sinks.empty()) room_for_any_split(sinks, sinks.front().cap, &Sink::pairs);
}

}  // namespace

Box bounds(const Vec3* x, std::uint32_t n) {
  constexpr Real big = std::numeric_limits<Real>::max();
  Box b{{big, big, big}, {-big, -big, -big}};
  for (std::uint32_t i = 0; i < n; ++i) {
    b.lo = {std::min(b.lo.x, x[i].x), std::min(b.lo.y, x[i].y), std::min(b.lo.z, x[i].z)};
    b.hi = {std::max(b.hi.x, x[i].x), std::max(b.hi.y, x[i].y), std::max(b.hi.z, x[i].z)};
  }
  if (n == 0) b = {{0, 0, 0}, {0, 0, 0}};
  return b;
}

void brute_pairs(const Query& q, std::vector<Sink>& sinks, int threads) {
  const auto n = static_cast<std::int64_t>(q.n);
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (threads > 1)
  for (std::int64_t a = 0; a < n; ++a) {
    Sink& s = sinks[std::size_t(thread_id())];
    for (std::int64_t b = a + 1; b < n; ++b) test_pair(q, std::uint32_t(a), std::uint32_t(b), s);
  }
  make_room(sinks);
}

// ---------------------------------------------------------------------------------------------
// Uniform grid

Real UniformGrid::find(const Query& q, Real c, std::vector<Sink>& sinks, int threads) {
  const std::uint32_t n = q.n;
  const Box box = bounds(q.x, n);
  const Vec3 ext = box.hi - box.lo;
  const double budget = std::max(8.0 * n, 4096.0);
  auto count = [&](Real cs) {
    return (std::floor(double(ext.x / cs)) + 1) * (std::floor(double(ext.y / cs)) + 1) *
           (std::floor(double(ext.z / cs)) + 1);
  };
  // Denormal sizes do not grow by 1.25 (5e-324 * 1.25 rounds back to 5e-324, an endless loop
  // for a radius a scene may give): the growth starts from the smallest normal number there.
  while (count(c) > budget) c = std::max(c * Real(1.25), std::numeric_limits<Real>::min());
  const auto nx = std::uint32_t(ext.x / c) + 1, ny = std::uint32_t(ext.y / c) + 1,
             nz = std::uint32_t(ext.z / c) + 1;
  const std::size_t cells = std::size_t(nx) * ny * nz;
  const Real inv = 1 / c;

  // Binning: cell indices on all threads, then a counting sort (serial, O(n + cells)).
  cell_of_.resize(n);
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (std::int64_t a = 0; a < std::int64_t(n); ++a) {
    const Vec3 p = (q.x[a] - box.lo) * inv;
    const auto ix = std::min(nx - 1, std::uint32_t(p.x)), iy = std::min(ny - 1, std::uint32_t(p.y)),
               iz = std::min(nz - 1, std::uint32_t(p.z));
    cell_of_[std::size_t(a)] = std::uint32_t((std::size_t(iz) * ny + iy) * nx + ix);
  }
  detail::build_rows(cells, start_, order_, [&](auto&& emit) {
    for (std::uint32_t a = 0; a < n; ++a) emit(cell_of_[a], a);
  });
  occupied_.clear();
  for (std::size_t k = 0; k < cells; ++k)
    if (start_[k + 1] != start_[k]) occupied_.push_back(std::uint32_t(k));
  if (q.signatures) {
    sig_.resize(cells);
    for (std::uint32_t k : occupied_) {
      sig_[k] = {};
      for (std::uint32_t s = start_[k]; s < start_[k + 1]; ++s)
        q.exclusion->sign(sig_[k], order_[s]);
    }
  }

  // Pairs: each occupied cell meets itself and its 13 forward neighbours.
  const auto cells_n = static_cast<std::int64_t>(occupied_.size());
#pragma omp parallel for schedule(dynamic, 32) num_threads(threads) if (threads > 1)
  for (std::int64_t k = 0; k < cells_n; ++k) {
    Sink& s = sinks[std::size_t(thread_id())];
    const std::uint32_t cell = occupied_[std::size_t(k)];
    const auto ix = std::int64_t(cell % nx), iy = std::int64_t((cell / nx) % ny),
               iz = std::int64_t(cell / (std::size_t(nx) * ny));
    const std::uint32_t b0 = start_[cell], b1 = start_[cell + 1];
    if (q.signatures && q.exclusion->all_excluded(sig_[cell])) {
      ++s.skipped;
    } else {
      for (std::uint32_t i = b0; i < b1; ++i)
        for (std::uint32_t j = i + 1; j < b1; ++j) test_pair(q, order_[i], order_[j], s);
    }
    for (const auto& o : kForward) {
      const std::int64_t jx = ix + o[0], jy = iy + o[1], jz = iz + o[2];
      if (jx < 0 || jy < 0 || jz < 0 || jx >= nx || jy >= ny || jz >= nz) continue;
      const auto other = std::size_t((jz * ny + jy) * nx + jx);
      const std::uint32_t c0 = start_[other], c1 = start_[other + 1];
      if (c0 == c1) continue;
      if (q.signatures) {
        CellSignature u = sig_[cell];
        u.merge(sig_[other]);
        if (q.exclusion->all_excluded(u)) {
          ++s.skipped;
          continue;
        }
      }
      for (std::uint32_t i = b0; i < b1; ++i)
        for (std::uint32_t j = c0; j < c1; ++j) test_pair(q, order_[i], order_[j], s);
    }
  }
  make_room(sinks);
  return c;
}

// ---------------------------------------------------------------------------------------------
// Hashed grid

namespace {
std::uint32_t hash_cell(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t mask) {
  const auto h =
      std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u ^ std::uint32_t(z) * 83492791u;
  return (h ^ (h >> 16)) & mask;
}
}  // namespace

Real HashedGrid::find(const Query& q, Real c, std::vector<Sink>& sinks, int threads) {
  const std::uint32_t n = q.n;
  const Box box = bounds(q.x, n);
  const Vec3 ext = box.hi - box.lo;
  const Real widest = std::max({ext.x, ext.y, ext.z});
  if (widest / c > Real(1 << 30)) c = widest / Real(1 << 30);  // cell coordinates fit int32
  std::uint32_t buckets = 1024;
  while (buckets < 2 * n) buckets *= 2;
  const std::uint32_t mask = buckets - 1;
  const Real inv = 1 / c;

  std::vector<std::int32_t>& coords = coords_;
  coords.resize(3 * std::size_t(n));
  bucket_of_.resize(n);
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (std::int64_t a = 0; a < std::int64_t(n); ++a) {
    const Vec3 p = (q.x[a] - box.lo) * inv;
    const auto k = std::size_t(a) * 3;
    coords[k] = std::int32_t(p.x), coords[k + 1] = std::int32_t(p.y),
    coords[k + 2] = std::int32_t(p.z);
    bucket_of_[std::size_t(a)] = hash_cell(coords[k], coords[k + 1], coords[k + 2], mask);
  }
  start_.assign(std::size_t(buckets) + 1, 0);
  for (std::uint32_t a = 0; a < n; ++a) ++start_[bucket_of_[a] + 1];
  occupied_ = 0;
  for (std::uint32_t k = 0; k < buckets; ++k) occupied_ += start_[k + 1] != 0;
  for (std::uint32_t k = 0; k < buckets; ++k) start_[k + 1] += start_[k];
  order_.resize(n);
  cell_.resize(3 * std::size_t(n));
  {
    cursor_.assign(start_.begin(), start_.end() - 1);
    for (std::uint32_t a = 0; a < n; ++a) {
      const std::uint32_t slot = cursor_[bucket_of_[a]]++;
      order_[slot] = a;
      std::copy_n(&coords[3 * std::size_t(a)], 3, &cell_[3 * std::size_t(slot)]);
    }
  }
  if (q.signatures) {
    sig_.assign(buckets, CellSignature{});
    for (std::uint32_t s = 0; s < n; ++s) q.exclusion->sign(sig_[bucket_of_[order_[s]]], order_[s]);
  }

  // Pairs, particle by particle: its own cell (later slots of its bucket with the same cell
  // coordinates) and its 13 forward neighbours' cells.
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (threads > 1)
  for (std::int64_t p = 0; p < std::int64_t(n); ++p) {
    Sink& s = sinks[std::size_t(thread_id())];
    const std::uint32_t a = order_[std::size_t(p)];
    const std::int32_t* ca = &cell_[3 * std::size_t(p)];
    const std::uint32_t own = bucket_of_[a];
    auto same = [&](std::uint32_t slot, std::int32_t x, std::int32_t y, std::int32_t z) {
      const std::int32_t* cb = &cell_[3 * std::size_t(slot)];
      return cb[0] == x && cb[1] == y && cb[2] == z;
    };
    auto skip = [&](std::uint32_t other_bucket) {
      if (!q.signatures) return false;
      CellSignature u = sig_[own];
      u.merge(sig_[other_bucket]);
      return q.exclusion->all_excluded(u);
    };
    if (skip(own)) {
      ++s.skipped;
    } else {
      for (std::uint32_t t = std::uint32_t(p) + 1; t < start_[own + 1]; ++t)
        if (same(t, ca[0], ca[1], ca[2])) test_pair(q, a, order_[t], s);
    }
    for (const auto& o : kForward) {
      const std::int32_t x = ca[0] + o[0], y = ca[1] + o[1], z = ca[2] + o[2];
      const std::uint32_t h = hash_cell(x, y, z, mask);
      if (start_[h] == start_[h + 1]) continue;
      if (skip(h)) {
        ++s.skipped;
        continue;
      }
      for (std::uint32_t t = start_[h]; t < start_[h + 1]; ++t)
        if (same(t, x, y, z)) test_pair(q, a, order_[t], s);
    }
  }
  make_room(sinks);
  return c;
}

// ---------------------------------------------------------------------------------------------
// Octree (hierarchical grid)

namespace {

constexpr int kLevels = 20;          // bits per axis of the Morton code
constexpr std::uint32_t kLeaf = 16;  // particles per leaf, at most (unless at the finest level)

std::uint64_t spread(std::uint64_t v) {  // 20 bits -> every third bit
  v &= 0xFFFFF;
  v = (v | v << 32) & 0x1F00000000FFFFull;
  v = (v | v << 16) & 0x1F0000FF0000FFull;
  v = (v | v << 8) & 0x100F00F00F00F00Full;
  v = (v | v << 4) & 0x10C30C30C30C30C3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// LSD radix sort of (key, index) by key, 16 bits per pass.
void radix_sort(std::vector<std::uint64_t>& key, std::vector<std::uint32_t>& idx,
                std::vector<std::uint64_t>& key_tmp, std::vector<std::uint32_t>& idx_tmp,
                std::vector<std::uint32_t>& count) {
  const std::size_t n = key.size();
  key_tmp.resize(n), idx_tmp.resize(n);
  count.resize(1 << 16);
  for (int shift = 0; shift < 64; shift += 16) {
    std::fill(count.begin(), count.end(), 0);
    for (std::size_t i = 0; i < n; ++i) ++count[(key[i] >> shift) & 0xFFFF];
    std::uint32_t sum = 0;
    for (auto& c : count) {
      const std::uint32_t t = c;
      c = sum;
      sum += t;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t slot = count[(key[i] >> shift) & 0xFFFF]++;
      key_tmp[slot] = key[i];
      idx_tmp[slot] = idx[i];
    }
    key.swap(key_tmp);
    idx.swap(idx_tmp);
  }
}

Box merge(const Box& a, const Box& b) {
  return {{std::min(a.lo.x, b.lo.x), std::min(a.lo.y, b.lo.y), std::min(a.lo.z, b.lo.z)},
          {std::max(a.hi.x, b.hi.x), std::max(a.hi.y, b.hi.y), std::max(a.hi.z, b.hi.z)}};
}

}  // namespace

void Octree::find(const Query& q, std::vector<Sink>& sinks, int threads) {
  const std::uint32_t n = q.n;
  nodes_.clear();
  leaves_ = 0;
  if (n == 0) return;
  const Box box = bounds(q.x, n);
  const Vec3 ext = box.hi - box.lo;
  const Real widest = std::max({ext.x, ext.y, ext.z, q.r});
  const Real fine = std::max(q.r, widest / Real(1 << kLevels) * Real(1.0001));
  code_.resize(n);
  order_.resize(n);
  for (std::uint32_t a = 0; a < n; ++a) {
    const Vec3 p = (q.x[a] - box.lo) / fine;
    code_[a] = spread(std::uint64_t(p.x)) | spread(std::uint64_t(p.y)) << 1 |
               spread(std::uint64_t(p.z)) << 2;
    order_[a] = a;
  }
  radix_sort(code_, order_, key_scratch_, order_scratch_, count_);
  nodes_.push_back({});
  build(0, 0, n, 0, q);
  // Parallel work: node pairs small enough to be one task each.
  tasks_.clear();
  tasks(0, 0, 2048);
  const auto t = static_cast<std::int64_t>(tasks_.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1)
  for (std::int64_t k = 0; k < t; ++k) {
    Sink& s = sinks[std::size_t(thread_id())];
    const auto [a, b] = tasks_[std::size_t(k)];
    if (a == b)
      self(a, q, s);
    else
      pair(a, b, q, s);
  }
  make_room(sinks);
}

// Fills node `idx` with particles order_[begin, end), the Morton prefix of `level` bits per
// axis being common to them; children split on the next bits (levels where every particle
// shares them are passed through).
std::uint32_t Octree::build(std::uint32_t idx, std::uint32_t begin, std::uint32_t end, int level,
                            const Query& q) {
  std::array<std::uint32_t, 9> cut{};
  int parts = 0;
  while (end - begin > kLeaf && level < kLevels) {
    const int shift = 3 * (kLevels - 1 - level);
    parts = 0;
    cut[0] = begin;
    for (std::uint32_t i = begin; i < end;) {
      const std::uint64_t digit = (code_[i] >> shift) & 7;
      std::uint32_t j = i;
      while (j < end && ((code_[j] >> shift) & 7) == digit) ++j;
      cut[std::size_t(++parts)] = j;
      i = j;
    }
    ++level;
    if (parts > 1) break;
  }
  Node& node = nodes_[idx];
  node.begin = begin;
  node.end = end;
  if (end - begin <= kLeaf || level >= kLevels || parts <= 1) {
    Box b = {q.x[order_[begin]], q.x[order_[begin]]};
    CellSignature sig;
    for (std::uint32_t i = begin; i < end; ++i) {
      b = merge(b, {q.x[order_[i]], q.x[order_[i]]});
      if (q.signatures) q.exclusion->sign(sig, order_[i]);
    }
    node.box = b;
    node.sig = sig;
    ++leaves_;
    return idx;
  }
  const auto first = std::uint32_t(nodes_.size());
  nodes_[idx].child = first;
  nodes_[idx].children = std::uint32_t(parts);
  nodes_.resize(nodes_.size() + std::size_t(parts));
  for (int c = 0; c < parts; ++c)
    build(first + std::uint32_t(c), cut[std::size_t(c)], cut[std::size_t(c) + 1], level, q);
  Box b = nodes_[first].box;
  CellSignature sig;
  for (int c = 0; c < parts; ++c) {
    b = merge(b, nodes_[first + std::uint32_t(c)].box);
    sig.merge(nodes_[first + std::uint32_t(c)].sig);
  }
  nodes_[idx].box = b;
  nodes_[idx].sig = sig;
  return idx;
}

std::vector<Box> Octree::leaf_boxes() const {
  std::vector<Box> out;
  for (const Node& n : nodes_)
    if (n.children == 0 && n.end > n.begin) out.push_back(n.box);
  return out;
}

bool Octree::far(const Node& a, const Node& b, Real r) const {
  const Real dx = std::max<Real>({0, a.box.lo.x - b.box.hi.x, b.box.lo.x - a.box.hi.x});
  const Real dy = std::max<Real>({0, a.box.lo.y - b.box.hi.y, b.box.lo.y - a.box.hi.y});
  const Real dz = std::max<Real>({0, a.box.lo.z - b.box.hi.z, b.box.lo.z - a.box.hi.z});
  return dx * dx + dy * dy + dz * dz >= r * r;
}

void Octree::tasks(std::uint32_t a, std::uint32_t b, std::size_t want) {
  const Node& na = nodes_[a];
  const Node& nb = nodes_[b];
  const std::size_t size = std::size_t(na.end - na.begin) + (a == b ? 0 : nb.end - nb.begin);
  if (size <= want || (na.children == 0 && nb.children == 0)) {
    tasks_.push_back({a, b});
    return;
  }
  if (a == b) {
    for (std::uint32_t i = 0; i < na.children; ++i) {
      tasks(na.child + i, na.child + i, want);
      for (std::uint32_t j = i + 1; j < na.children; ++j) tasks(na.child + i, na.child + j, want);
    }
    return;
  }
  tasks_.push_back({a, b});  // cross pairs are split inside pair()
}

void Octree::self(std::uint32_t a, const Query& q, Sink& s) const {
  const Node& n = nodes_[a];
  if (q.signatures && q.exclusion->all_excluded(n.sig)) {
    ++s.skipped;
    return;
  }
  if (n.children == 0) {
    for (std::uint32_t i = n.begin; i < n.end; ++i)
      for (std::uint32_t j = i + 1; j < n.end; ++j) test_pair(q, order_[i], order_[j], s);
    return;
  }
  for (std::uint32_t i = 0; i < n.children; ++i) {
    self(n.child + i, q, s);
    for (std::uint32_t j = i + 1; j < n.children; ++j) pair(n.child + i, n.child + j, q, s);
  }
}

void Octree::pair(std::uint32_t a, std::uint32_t b, const Query& q, Sink& s) const {
  const Node& na = nodes_[a];
  const Node& nb = nodes_[b];
  if (far(na, nb, q.r)) return;
  if (q.signatures) {
    CellSignature u = na.sig;
    u.merge(nb.sig);
    if (q.exclusion->all_excluded(u)) {
      ++s.skipped;
      return;
    }
  }
  if (na.children == 0 && nb.children == 0) {
    for (std::uint32_t i = na.begin; i < na.end; ++i)
      for (std::uint32_t j = nb.begin; j < nb.end; ++j) test_pair(q, order_[i], order_[j], s);
    return;
  }
  const bool split_a =
      nb.children == 0 || (na.children != 0 && na.end - na.begin >= nb.end - nb.begin);
  if (split_a) {
    for (std::uint32_t i = 0; i < na.children; ++i) pair(na.child + i, b, q, s);
  } else {
    for (std::uint32_t j = 0; j < nb.children; ++j) pair(a, nb.child + j, q, s);
  }
}

}  // namespace maille::collision
