// What a link kind (a Link brick) is, and the typed pool that stores and runs one kind.
//
// Checklist for a new kind (see docs/architecture.md, "Adding a link kind"):
//   1. a struct with `keyword`, a plain `Params` record, `fields` (scene keys with unit and bound),
//      and pure functions `force`, `energy`, `stiffness`, `damping` (optionally `is_active`);
//   2. one line `registry.add<YourKind>()` (built-ins: src/links/builtin_kinds.cpp).
// The simulator loop never changes: it folds over the model's pools, one virtual call per pool,
// and each pool runs a tight, inlined loop over its own records.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "maille/mat3.hpp"
#include "maille/vec3.hpp"

namespace maille {

struct LinkEnds {
  std::uint32_t a = 0, b = 0;  // point indices; the force returned by a kind acts on a, -f on b
};

enum class Bound : std::uint8_t { positive, non_negative, any };

// One scene-settable parameter of a link kind.
template <class Params>
struct ParamField {
  std::string_view name;  // scene key
  std::string_view unit;  // SI unit, for docs and messages
  Real Params::*member;
  Bound bound = Bound::positive;
  std::optional<Real> default_value{};  // none: required (unless default_is_distance)
  bool default_is_distance = false;     // omitted: the distance between the points when built
  std::string_view doc{};
  std::string_view default_from{};  // omitted: the value of this other field
};

// The type-erased view of a field, as the scene reader and `maille info` see it.
struct ParamInfo {
  std::string name, unit, doc;
  Bound bound = Bound::positive;
  std::optional<Real> default_value;
  bool default_is_distance = false;
  std::string default_from;
};

template <class K>
concept LinkKind = requires(const Vec3& x, const typename K::Params& p) {
  { K::keyword } -> std::convertible_to<std::string_view>;
  { K::fields.size() } -> std::convertible_to<std::size_t>;
  { K::force(x, x, x, x, p) } -> std::same_as<Vec3>;    // force on a (b receives -force)
  { K::energy(x, x, p) } -> std::convertible_to<Real>;  // potential energy, J
  { K::stiffness(p) } -> std::convertible_to<Real>;     // bound on |df/dx|, N/m (stability)
  { K::damping(p) } -> std::convertible_to<Real>;       // bound on |df/dv|, N.s/m (stability)
};

// Running totals a pool reports after a force pass.
struct LinkCounters {
  std::uint64_t active = 0;  // links that produced a force (conditional kinds)
};

// The link that looks worst after a blow-up: non-finite, or most stretched relative to rest.
struct WorstLink {
  std::size_t index = 0;
  LinkEnds ends{};
  Real badness = 0;  // |d - d0| / d0, or +inf when positions or force are not finite
};

class LinkPoolBase {
 public:
  virtual ~LinkPoolBase() = default;
  virtual std::string_view keyword() const = 0;
  virtual std::size_t size() const = 0;
  virtual LinkEnds ends(std::size_t i) const = 0;
  virtual std::vector<ParamInfo> fields() const = 0;
  // Params in `fields()` order; used by the scene reader and the viewer.
  virtual void add_generic(LinkEnds ends, std::span<const Real> params) = 0;
  virtual Real param(std::size_t i, std::size_t field) const = 0;
  virtual void scale_param(std::size_t field, Real factor) = 0;  // live tuning, between steps
  // Groups links so that no two groups running together share a point (once, after building):
  // they run in parallel without atomics, and the sum order per point is fixed (determinism).
  virtual void prepare(std::uint32_t point_count) = 0;
  // Adds every link's force into f. Callable inside an OpenMP parallel region (orphaned
  // work-sharing): the threads split each group.
  virtual void accumulate(const Vec3* x, const Vec3* v, Vec3* f, LinkCounters& counters) const = 0;
  virtual double energy(const Vec3* x) const = 0;
  // Adds, per point, the stiffness and damping seen through this pool's links, counted twice
  // when the other end is free (Gershgorin bound on the eigenvalues of M^-1 K).
  virtual void stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                               std::span<Real> c_row) const = 0;
  virtual WorstLink worst(const Vec3* x, const Vec3* v) const = 0;
  virtual std::unique_ptr<LinkPoolBase> clone() const = 0;

  // Implicit integration (kinds that define `jacobian`; others return false / do nothing).
  virtual bool has_jacobian() const = 0;
  virtual LinkJacobian jacobian(std::size_t i, const Vec3* x, const Vec3* v,
                                JacobianMode mode) const = 0;
  // For every link l: C_l = h dv + h^2 dx (definite mode) into blocks[l], and, when rhs is not
  // null, the right-hand side term h^2 (df/dx v): rhs_a += h^2 dx (v_b - v_a), rhs_b -= it.
  virtual void implicit_blocks(const Vec3* x, const Vec3* v, Real h, Mat3* blocks,
                               Vec3* rhs) const = 0;
  // out -= (h df/dv + h^2 df/dx) u, link by link: w = C_l (u_b - u_a); out_a -= w; out_b += w.
  virtual void apply_blocks(const Mat3* blocks, const Vec3* u, Vec3* out) const = 0;
  // Adds every C_l to the diagonal blocks of its two points (block-Jacobi preconditioner).
  virtual void add_block_diagonal(const Mat3* blocks, Mat3* diagonal) const = 0;
};

// Greedy colouring of point sets (set e holds indices[offsets[e] .. offsets[e+1])) so that no
// two sets of one colour share a point. Returns the sets in colour order and colour offsets.
struct Colouring {
  std::vector<std::uint32_t> order;    // set indices, grouped by colour
  std::vector<std::uint32_t> offsets;  // colour c spans order[offsets[c] .. offsets[c+1])
};
Colouring colour_sets(std::span<const std::uint32_t> offsets,
                      std::span<const std::uint32_t> indices, std::uint32_t point_count);
// The same for sets of a fixed size (triangles: arity 3).
Colouring colour_elements(std::span<const std::uint32_t> indices, int arity,
                          std::uint32_t point_count);

template <LinkKind K>
class LinkPool final : public LinkPoolBase {
 public:
  using Params = typename K::Params;

  std::string_view keyword() const override { return K::keyword; }
  std::size_t size() const override { return ends_.size(); }
  LinkEnds ends(std::size_t i) const override { return ends_[i]; }
  const Params& params(std::size_t i) const { return params_[i]; }

  void add(LinkEnds e, const Params& p) {
    ends_.push_back(e);
    params_.push_back(p);
    groups_.clear();  // needs prepare() again
    band_order_.clear();
    band_begin_.clear();
    chunk_begin_.clear();
    chunk_is_run_.clear();
  }

  std::vector<ParamInfo> fields() const override {
    std::vector<ParamInfo> out;
    for (const auto& f : K::fields)
      out.push_back({std::string(f.name), std::string(f.unit), std::string(f.doc), f.bound,
                     f.default_value, f.default_is_distance, std::string(f.default_from)});
    return out;
  }

  void add_generic(LinkEnds e, std::span<const Real> values) override {
    Params p{};
    for (std::size_t k = 0; k < K::fields.size() && k < values.size(); ++k)
      p.*(K::fields[k].member) = values[k];
    add(e, p);
  }

  Real param(std::size_t i, std::size_t field) const override {
    return params_[i].*(K::fields[field].member);
  }

  void scale_param(std::size_t field, Real factor) override {
    for (auto& p : params_) p.*(K::fields[field].member) *= factor;
  }

  // Links are grouped into bands by their first point (about kBands bands over the points'
  // range, whatever the thread count), and inside a band always-active kinds are sorted by
  // (b - a, a): links of one family (every horizontal link of a grid, say) then follow each
  // other with both ends advancing by one point, and such runs are computed with contiguous
  // loads instead of gathers. Bands are coloured so that no two bands of one colour share a
  // point: on a grid, a band touches only its neighbours, so two colours suffice and a step
  // costs two barriers per pool (each barrier is a futex wake-up with OMP_WAIT_POLICY=passive,
  // tens of microseconds on a busy machine; colouring small chunks instead gave ~20 colours
  // and made two threads slower than one at 128^2). Serial runs use the same order, so every
  // point sums its forces in the same order whatever the thread count.
  void prepare(std::uint32_t point_count) override {
    sort_into_bands();
    cut_chunks();
    std::vector<std::uint32_t> offsets(band_begin_.size(), 0), idx;
    idx.reserve(ends_.size() * 2);
    for (std::size_t b = 0; b + 1 < band_begin_.size(); ++b) {
      for (std::size_t l = chunk_begin_[band_begin_[b]]; l < chunk_begin_[band_begin_[b + 1]];
           ++l) {
        idx.push_back(ends_[l].a);
        idx.push_back(ends_[l].b);
      }
      offsets[b + 1] = static_cast<std::uint32_t>(idx.size());
    }
    Colouring col = colour_sets(offsets, idx, point_count);
    band_order_ = std::move(col.order);
    groups_ = std::move(col.offsets);
  }

  // Runs f(chunk) over every chunk, colour by colour. Callable inside an OpenMP parallel region
  // (the threads split each colour's bands) or outside it (serially, in the same order).
  template <class F>
  void for_each_chunk(F&& f) const {
    for (std::size_t g = 0; g + 1 < groups_.size(); ++g) {
      const auto begin = static_cast<std::int64_t>(groups_[g]);
      const auto end = static_cast<std::int64_t>(groups_[g + 1]);
#pragma omp for schedule(static)
      for (std::int64_t k = begin; k < end; ++k) {
        const std::uint32_t band = band_order_[static_cast<std::size_t>(k)];
        for (std::uint32_t c = band_begin_[band]; c < band_begin_[band + 1]; ++c) f(c);
      }
    }
  }

  void accumulate(const Vec3* x, const Vec3* v, Vec3* f, LinkCounters& counters) const override {
    std::uint64_t active = 0;  // this thread's count
    for_each_chunk([&](std::uint32_t c) { active += run_chunk(c, x, v, f); });
    if constexpr (requires { K::is_active(x[0], x[0], params_[0]); }) {
#pragma omp atomic
      counters.active += active;
    }
  }

  static constexpr bool kHasJacobian = requires(const Vec3& q, const Params& p) {
    K::jacobian(q, q, q, q, p, JacobianMode::exact);
  };
  bool has_jacobian() const override {
    return kHasJacobian;
  }

  LinkJacobian jacobian(std::size_t i, const Vec3* x, const Vec3* v,
                        JacobianMode mode) const override {
    if constexpr (kHasJacobian) {
      const auto [a, b] = ends_[i];
      return K::jacobian(x[a], x[b], v[a], v[b], params_[i], mode);
    } else {
      return {};
    }
  }

  void implicit_blocks(const Vec3* x, const Vec3* v, Real h, Mat3* blocks,
                       Vec3* rhs) const override {
    if constexpr (kHasJacobian) {
      for_each_chunk([&](std::uint32_t c) {
        for (std::size_t l = chunk_begin_[c]; l < chunk_begin_[c + 1]; ++l) {
          const auto [a, b] = ends_[l];
          const LinkJacobian j =
              K::jacobian(x[a], x[b], v[a], v[b], params_[l], JacobianMode::definite);
          blocks[l] = j.dv * h + j.dx * (h * h);
          if (!rhs) continue;
          const Vec3 r = (j.dx * (v[b] - v[a])) * (h * h);
          rhs[a] += r;
          rhs[b] -= r;
        }
      });
    }
  }

  void apply_blocks(const Mat3* blocks, const Vec3* u, Vec3* out) const override {
    if constexpr (kHasJacobian) {
      for_each_chunk([&](std::uint32_t c) {
        for (std::size_t l = chunk_begin_[c]; l < chunk_begin_[c + 1]; ++l) {
          const auto [a, b] = ends_[l];
          const Vec3 w = blocks[l] * (u[b] - u[a]);
          out[a] -= w;
          out[b] += w;
        }
      });
    }
  }

  void add_block_diagonal(const Mat3* blocks, Mat3* diagonal) const override {
    for (std::size_t l = 0; l < ends_.size(); ++l) {
      diagonal[ends_[l].a] += blocks[l];
      diagonal[ends_[l].b] += blocks[l];
    }
  }

  double energy(const Vec3* x) const override {
    double sum = 0;
    for (std::size_t l = 0; l < ends_.size(); ++l)
      sum += K::energy(x[ends_[l].a], x[ends_[l].b], params_[l]);
    return sum;
  }

  void stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    if constexpr (requires { K::is_active(Vec3{}, Vec3{}, params_[0]); }) {
      conditional_stability_terms(inv_mass, k_row, c_row);
    } else {
      for (std::size_t l = 0; l < ends_.size(); ++l) {
        const auto [a, b] = ends_[l];
        const Real k = K::stiffness(params_[l]), c = K::damping(params_[l]);
        const Real wa = inv_mass[b] > 0 ? 2 : 1, wb = inv_mass[a] > 0 ? 2 : 1;
        k_row[a] += wa * k;
        c_row[a] += wa * c;
        k_row[b] += wb * k;
        c_row[b] += wb * c;
      }
    }
  }

  // A point may hold hundreds of conditional links (one per floor point) of which only a few
  // can be active at once: counting them all would make the bound uselessly small. A point is
  // assumed to touch at most kSimultaneousContacts partners at a time (4: a point resting in the
  // hollow of a square bed of spheres), each as stiff as its stiffest conditional link.
  static constexpr Real kSimultaneousContacts = 4;
  void conditional_stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                                   std::span<Real> c_row) const {
    std::vector<Real> k_max(k_row.size(), 0), c_max(k_row.size(), 0);
    for (std::size_t l = 0; l < ends_.size(); ++l) {
      const auto [a, b] = ends_[l];
      const Real k = K::stiffness(params_[l]), c = K::damping(params_[l]);
      const Real wa = inv_mass[b] > 0 ? 2 : 1, wb = inv_mass[a] > 0 ? 2 : 1;
      k_max[a] = std::max(k_max[a], wa * k);
      c_max[a] = std::max(c_max[a], wa * c);
      k_max[b] = std::max(k_max[b], wb * k);
      c_max[b] = std::max(c_max[b], wb * c);
    }
    for (std::size_t i = 0; i < k_row.size(); ++i) {
      k_row[i] += kSimultaneousContacts * k_max[i];
      c_row[i] += kSimultaneousContacts * c_max[i];
    }
  }

  WorstLink worst(const Vec3* x, const Vec3* v) const override {
    WorstLink w;
    w.badness = -1;
    for (std::size_t l = 0; l < ends_.size(); ++l) {
      const auto [a, b] = ends_[l];
      const Vec3 fa = K::force(x[a], x[b], v[a], v[b], params_[l]);
      Real bad;
      if (!is_finite(x[a]) || !is_finite(x[b]) || !is_finite(fa)) {
        bad = INFINITY;
      } else {
        const Real d = norm(x[b] - x[a]), d0 = rest_hint(l);
        bad = std::abs(d - d0) / std::max<Real>(d0, Real(1e-9));
      }
      if (bad > w.badness) w = {l, ends_[l], bad};
    }
    return w;
  }

  std::unique_ptr<LinkPoolBase> clone() const override {
    return std::make_unique<LinkPool<K>>(*this);
  }

  // The distance scale of link l, for strain in diagnostics: a field named rest_length or
  // threshold when the kind has one, else 1 m.
  Real rest_hint(std::size_t l) const {
    for (const auto& f : K::fields)
      if (f.name == "rest_length" || f.name == "threshold") return params_[l].*(f.member);
    return 1;
  }

 private:
  static constexpr std::size_t kChunk = 256;
  static constexpr std::size_t kMinRun = 8;  // shorter runs are not worth a chunk of their own

  static constexpr std::uint32_t kBands = 16;
  static constexpr std::uint32_t kMinBandPoints = 256;

  std::uint32_t band_of(std::uint32_t a) const {
    return (a - band_origin_) / band_points_;
  }

  void sort_into_bands() {
    std::uint32_t lo = ~0u, hi = 0;
    for (const auto& e : ends_) lo = std::min(lo, e.a), hi = std::max(hi, e.a);
    band_origin_ = ends_.empty() ? 0 : lo;
    const std::uint32_t span = ends_.empty() ? 1 : hi - lo + 1;
    band_points_ = std::max(kMinBandPoints, (span + kBands - 1) / kBands);
    std::vector<std::uint32_t> order(ends_.size());
    for (std::size_t l = 0; l < order.size(); ++l) order[l] = static_cast<std::uint32_t>(l);
    constexpr bool always_active = !requires {
      K::is_active(Vec3{}, Vec3{}, params_[0]);
    };
    auto key = [&](std::uint32_t l) {
      const std::int64_t reach = always_active ? std::int64_t(ends_[l].b) - ends_[l].a : 0;
      return std::tuple{band_of(ends_[l].a), reach, ends_[l].a};
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t i, std::uint32_t j) { return key(i) < key(j); });
    std::vector<LinkEnds> e(ends_.size());
    std::vector<Params> p(params_.size());
    for (std::size_t l = 0; l < order.size(); ++l) {
      e[l] = ends_[order[l]];
      p[l] = params_[order[l]];
    }
    ends_ = std::move(e);
    params_ = std::move(p);
  }

  // Cuts each band into chunks: a run (both ends advance by one, at least kMinRun links, at
  // most kChunk) or up to kChunk other links. run[l]: links from l on that continue l's run.
  void cut_chunks() {
    const std::size_t n = ends_.size();
    std::vector<std::uint32_t> run(n + 1, 0);
    for (std::size_t l = n; l-- > 0;) {
      const bool next = l + 1 < n && ends_[l + 1].a == ends_[l].a + 1 &&
                        ends_[l + 1].b == ends_[l].b + 1 &&
                        band_of(ends_[l + 1].a) == band_of(ends_[l].a);
      run[l] = next ? run[l + 1] + 1 : 1;
    }
    chunk_begin_.assign(1, 0);
    chunk_is_run_.clear();
    band_begin_.assign(1, 0);
    for (std::size_t l = 0; l < n;) {
      const std::uint32_t band = band_of(ends_[l].a);
      std::size_t end = l;
      const bool is_run = run[l] >= kMinRun;
      if (is_run) {
        end = l + std::min<std::size_t>(run[l], kChunk);
      } else {
        while (end < n && end - l < kChunk && band_of(ends_[end].a) == band &&
               (end == l || run[end] < kMinRun))
          ++end;
      }
      chunk_begin_.push_back(static_cast<std::uint32_t>(end));
      chunk_is_run_.push_back(is_run);
      l = end;
      if (l == n || band_of(ends_[l].a) != band)
        band_begin_.push_back(static_cast<std::uint32_t>(chunk_is_run_.size()));
    }
  }

  // Forces of one chunk of links. Kinds that are always active compute all forces first in a
  // loop the compiler vectorises (packed sqrt and division; contiguous loads on runs, gathers
  // otherwise), then scatter them: the fused gather-compute-scatter loop is bound by the scalar
  // sqrt/div chain and by store-to-load forwarding between links sharing a point. Conditional
  // kinds test cheaply first and compute only the few active links.
  std::uint64_t run_chunk(std::size_t c, const Vec3* x, const Vec3* v, Vec3* f) const {
    const std::size_t begin = chunk_begin_[c], end = chunk_begin_[c + 1];
    const LinkEnds* e = ends_.data();
    const Params* p = params_.data();
    if constexpr (requires { K::is_active(x[0], x[0], p[0]); }) {
      std::uint64_t active = 0;
      for (std::size_t l = begin; l < end; ++l) {
        const std::uint32_t a = e[l].a, b = e[l].b;
        if (!K::is_active(x[a], x[b], p[l])) continue;
        ++active;
        const Vec3 fa = K::force(x[a], x[b], v[a], v[b], p[l]);
        f[a] += fa;
        f[b] -= fa;
      }
      return active;
    } else {
      Real fx[kChunk], fy[kChunk], fz[kChunk];  // uninitialised on purpose: fully written
      const std::size_t n = end - begin;
      if (chunk_is_run_[c]) {
        const std::uint32_t a0 = e[begin].a, b0 = e[begin].b;
        const Vec3 *xa = x + a0, *xb = x + b0, *va = v + a0, *vb = v + b0;
#pragma omp simd
        for (std::size_t k = 0; k < n; ++k) {
          const Vec3 fa = K::force(xa[k], xb[k], va[k], vb[k], p[begin + k]);
          fx[k] = fa.x;
          fy[k] = fa.y;
          fz[k] = fa.z;
        }
        Vec3* fa = f + a0;
        Vec3* fb = f + b0;
        for (std::size_t k = 0; k < n; ++k) fa[k] += Vec3{fx[k], fy[k], fz[k]};
        for (std::size_t k = 0; k < n; ++k) fb[k] -= Vec3{fx[k], fy[k], fz[k]};
        return 0;
      }
#pragma omp simd
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t a = e[begin + k].a, b = e[begin + k].b;
        const Vec3 fa = K::force(x[a], x[b], v[a], v[b], p[begin + k]);
        fx[k] = fa.x;
        fy[k] = fa.y;
        fz[k] = fa.z;
      }
      for (std::size_t k = 0; k < n; ++k) {
        const Vec3 fa{fx[k], fy[k], fz[k]};
        f[e[begin + k].a] += fa;
        f[e[begin + k].b] -= fa;
      }
      return 0;
    }
  }

  std::vector<LinkEnds> ends_;
  std::vector<Params> params_;
  std::uint32_t band_origin_ = 0, band_points_ = 1;  // band of point a: (a - origin) / points
  std::vector<std::uint32_t> chunk_begin_;           // chunk c spans links [begin[c], begin[c+1])
  std::vector<std::uint8_t> chunk_is_run_;           // chunk c is a run: a and b advance by one
  std::vector<std::uint32_t> band_begin_;            // band b spans chunks [begin[b], begin[b+1])
  std::vector<std::uint32_t> band_order_;            // bands grouped by colour (prepare())
  std::vector<std::uint32_t> groups_;  // colour c spans band_order_[groups_[c]..[c+1])
};

// The model's links: one pool per kind, in the order kinds were first used.
class LinkSet {
 public:
  LinkSet() = default;
  LinkSet(const LinkSet& other);
  LinkSet& operator=(const LinkSet& other);
  LinkSet(LinkSet&&) noexcept = default;
  LinkSet& operator=(LinkSet&&) noexcept = default;

  template <LinkKind K>
  LinkPool<K>& pool() {
    for (auto& p : pools_)
      if (auto* typed = dynamic_cast<LinkPool<K>*>(p.get())) return *typed;
    pools_.push_back(std::make_unique<LinkPool<K>>());
    return static_cast<LinkPool<K>&>(*pools_.back());
  }
  LinkPoolBase* find(std::string_view keyword);
  const LinkPoolBase* find(std::string_view keyword) const;
  LinkPoolBase& adopt(std::unique_ptr<LinkPoolBase> pool);

  std::span<const std::unique_ptr<LinkPoolBase>> pools() const { return pools_; }
  std::size_t total() const;
  void prepare(std::uint32_t point_count);

 private:
  std::vector<std::unique_ptr<LinkPoolBase>> pools_;
};

}  // namespace maille
