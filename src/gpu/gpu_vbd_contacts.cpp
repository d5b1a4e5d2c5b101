// The step's point pairs inside the GPU's VBD: see gpu_vbd_contacts.hpp.
#include "gpu_vbd_contacts.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>
#include <string>

#include "../collision/self/self_contact_link.hpp"
#include "../collision/self/triangle_contact_terms.hpp"
#include "gl_buffers.hpp"
#include "gpu_layout.hpp"
#include "maille/colouring.hpp"
#include "maille/detail/csr.hpp"
#include "maille/link_pool.hpp"
#include "maille/links/conditional.hpp"

namespace maille::gpu {

namespace {

constexpr std::size_t kLawValues = kVbdPairWords - 1;  // the entry's words after the other point

// A pair pool's law values for slot `slot`: k, z, threshold, rest, mu, F_n, normal.
void law_of(const LinkPoolBase& pool, std::size_t slot, float* out) {
  using Frictional = LinkPool<collision::FrictionalContact>;
  if (const auto* fc = dynamic_cast<const Frictional*>(&pool)) {
    const collision::FrictionalContact::Params& p = fc->slot_params()[slot];
    const Real values[kLawValues] = {p.normal.stiffness,   p.normal.damping, p.normal.threshold,
                                     p.normal.rest_length, p.friction,       p.lag_force,
                                     p.lag_normal.x,       p.lag_normal.y,   p.lag_normal.z};
    for (std::size_t k = 0; k < kLawValues; ++k) out[k] = float(values[k]);
    return;
  }
  if (pool.shared_law() != ConditionalSpringDamper::shared_law || pool.fields().size() != 4)
    throw std::runtime_error("contact pairs of kind '" + std::string(pool.keyword()) +
                             "' have no law in the GPU's VBD (it runs conditional spring-dampers "
                             "with lagged friction): run this scene with --backend cpu");
  const std::size_t id = pool.id_of_slot(slot);
  for (std::size_t f = 0; f < 4; ++f) out[f] = float(pool.param(id, f));
  for (std::size_t k = 4; k < kLawValues; ++k) out[k] = 0.0f;  // no friction
}

}  // namespace

VbdGraph::VbdGraph(const Model& m) : points_(m.points.size()) {
  for (std::uint32_t i = 0; i < points_; ++i)
    if (m.points.inv_mass[i] > 0) free_.push_back(i);
  detail::build_neighbour_rows(points_, row_, other_, [&](auto&& edge) {
    for (const auto& pool : m.links.pools())
      for (const LinkEnds& e : pool->slot_ends()) edge(e.a, e.b);
  });
}

// Fixed and driven points are never coloured, so links and pairs to them constrain nothing.
void VbdGraph::colour(VbdColours& out, std::span<const std::uint32_t> contact_row,
                      std::span<const std::uint32_t> contact_other) {
  colour_.assign(points_, kUncoloured);
  const bool contacts = !contact_row.empty();
  const std::uint32_t count =
      colour_points(free_, colour_, stamp_, [&](std::uint32_t i, auto&& visit) {
        for (std::uint32_t k = row_[i]; k < row_[i + 1]; ++k) visit(other_[k]);
        if (contacts)
          for (std::uint32_t k = contact_row[i]; k < contact_row[i + 1]; ++k)
            visit(contact_other[k]);
      });
  detail::build_rows(count, out.row, out.order, [&](auto&& emit) {
    for (const std::uint32_t i : free_) emit(colour_[i], i);
  });
}

GpuVbdContacts::GpuVbdContacts(double max_block) : max_block_(max_block) {
  glCreateBuffers(1, &buffer_);
}

GpuVbdContacts::~GpuVbdContacts() {
  if (!forgotten_) glDeleteBuffers(1, &buffer_);
}

void GpuVbdContacts::load(const Model& m, VbdColours& colours) {
  points_ = m.points.size();
  graph_ = VbdGraph(m);
  pack(ContactSet{});
  graph_.colour(colours);
}

GpuVbdContacts::Counts GpuVbdContacts::update(const ContactSet& set, VbdColours& colours) {
  pack(set);
  // Every contact's points are neighbours of each other: a pair's two, a stencil's four.
  detail::build_neighbour_rows(points_, row_, other_, [&](auto&& edge) {
    for (std::size_t k = 0; k + 1 < ends_.size(); k += 2) edge(ends_[k], ends_[k + 1]);
    for (std::size_t w = 0; w < stencils_.size(); w += kVbdStencilWords)
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = i + 1; j < 4; ++j) edge(stencils_[w + i], stencils_[w + j]);
  });
  graph_.colour(colours, row_, other_);
  return counts_;
}

// vbd_contacts (gpu_layout.hpp): the header, the bounds (+inf until the bounds pass), the pairs
// and the stencils by point, the drift balls.
void GpuVbdContacts::pack(const ContactSet& set) {
  ends_.clear();
  laws_.clear();
  for (const LinkPoolBase* pool : set.pairs()) {
    const auto ends = pool->slot_ends();
    for (std::size_t slot = 0; slot < ends.size(); ++slot) {
      ends_.push_back(ends[slot].a);
      ends_.push_back(ends[slot].b);
      laws_.resize(laws_.size() + kLawValues);
      law_of(*pool, slot, laws_.data() + laws_.size() - kLawValues);
    }
  }
  pack_stencils(set);
  pack_guard(set);
  const std::size_t stencils = stencils_.size() / kVbdStencilWords;
  counts_.pairs = ends_.size() / 2;
  counts_.stencils = stencils;
  // Pair entry k = 2 p + e: pair p seen from its end e (0: its first point), in the set's order;
  // stencil entry 4 s + j: stencil s seen from its point j.
  detail::build_rows(points_, pair_row_, pair_entry_, [&](auto&& emit) {
    for (std::size_t k = 0; k < ends_.size(); ++k) emit(ends_[k], std::uint32_t(k));
  });
  detail::build_rows(points_, stencil_row_, stencil_entry_, [&](auto&& emit) {
    for (std::size_t k = 0; k < 4 * stencils; ++k)
      emit(stencils_[kVbdStencilWords * (k / 4) + k % 4], std::uint32_t(k));
  });
  const std::size_t n = points_;
  std::uint32_t part[8] = {points_};
  part[1] = kVbdContactHeader;
  part[2] = part[1] + std::uint32_t(n);
  part[3] = part[2] + std::uint32_t(n + 1);
  part[4] = part[3] + std::uint32_t(kVbdPairWords * pair_entry_.size());
  part[5] = part[4] + std::uint32_t(n + 1);
  part[6] = part[5] + std::uint32_t(stencil_entry_.size());
  part[7] = part[6] + std::uint32_t(stencils_.size());
  const double bytes = 4.0 * (double(part[7]) + double(guard_.size()));
  if (bytes > max_block_)
    throw std::runtime_error(
        "the step's contacts (" + std::to_string(counts_.pairs) + " pairs, " +
        std::to_string(stencils) + " point-triangle and edge-edge candidates) need a " +
        std::to_string(bytes / (1 << 20)) + " MiB storage buffer, more than this driver's " +
        "limit of " + std::to_string(max_block_ / (1 << 20)) +
        " MiB: run this scene with --backend cpu");
  words_.assign(part[7] + guard_.size(), 0u);
  std::copy(part, part + kVbdContactHeader, words_.begin());
  const std::uint32_t inf = std::bit_cast<std::uint32_t>(std::numeric_limits<float>::infinity());
  std::fill_n(words_.begin() + part[1], n, inf);
  std::copy(pair_row_.begin(), pair_row_.end(), words_.begin() + part[2]);
  for (std::size_t e = 0; e < pair_entry_.size(); ++e) {
    std::uint32_t* w = words_.data() + part[3] + kVbdPairWords * e;
    const std::size_t p = pair_entry_[e] / 2;
    w[0] = ends_[pair_entry_[e] ^ 1u];
    for (std::size_t k = 0; k < kLawValues; ++k)
      w[1 + k] = std::bit_cast<std::uint32_t>(laws_[kLawValues * p + k]);
  }
  std::copy(stencil_row_.begin(), stencil_row_.end(), words_.begin() + part[4]);
  std::copy(stencil_entry_.begin(), stencil_entry_.end(), words_.begin() + part[5]);
  std::copy(stencils_.begin(), stencils_.end(), words_.begin() + part[6]);
  for (std::size_t k = 0; k < guard_.size(); ++k)
    words_[part[7] + k] = std::bit_cast<std::uint32_t>(guard_[k]);
  upload(buffer_, words_);
}

// Each stage's candidates with their law and lag, and the first candidate of each particle's
// run (TriangleContactTerms::evaluate scans back to it for the once-per-feature rule).
void GpuVbdContacts::pack_stencils(const ContactSet& set) {
  stencils_.clear();
  for (const TriangleContacts* t : set.stencils()) {
    const auto* terms = dynamic_cast<const collision::TriangleContactTerms*>(t);
    if (!terms)
      throw std::runtime_error(
          "stencil contacts other than self-collision's have no law in the "
          "GPU's VBD: run this scene with --backend cpu");
    const auto cand = terms->candidates();
    const std::size_t base = stencils_.size() / kVbdStencilWords;
    std::uint32_t first = 0;
    for (std::size_t e = 0; e < cand.size(); ++e) {
      const bool edge = e >= terms->edge_begin();
      if (edge || e == 0 || cand[e - 1][0] != cand[e][0]) first = std::uint32_t(base + e);
      std::uint32_t flags = edge ? 1u | (std::uint32_t(terms->edge_particle_bits(e)) << 1) : 0u;
      const Vec3 n = terms->lag_normal(e);
      const float law[8] = {float(terms->radius()),
                            float(terms->stiffness()),
                            float(terms->damping()),
                            float(terms->friction()),
                            float(terms->lag_force(e)),
                            float(n.x),
                            float(n.y),
                            float(n.z)};
      stencils_.insert(stencils_.end(), cand[e].begin(), cand[e].end());
      stencils_.push_back(flags);
      stencils_.push_back(first);
      for (const float f : law) stencils_.push_back(std::bit_cast<std::uint32_t>(f));
    }
  }
}

// Each stage's drift limits (TriangleContacts::drift_limit, points): a point's smallest; the
// begin pass puts each ball's centre at the point's prediction x_n + h v_n (DriftGuard::
// first_search, with no common displacement: smaller balls, the same guarantee). Fixed and
// driven points are never moved by the solve: their balls are not read.
void GpuVbdContacts::pack_guard(const ContactSet& set) {
  guard_.clear();
  counts_.guarded = false;
  for (const TriangleContacts* t : set.stencils())
    if (t->drift_limit() < std::numeric_limits<Real>::infinity() && !t->points().empty())
      counts_.guarded = true;
  if (!counts_.guarded) return;
  guard_.assign(4 * std::size_t(points_), 0.0f);
  for (std::size_t i = 0; i < points_; ++i) guard_[4 * i] = std::numeric_limits<float>::infinity();
  for (const TriangleContacts* t : set.stencils())
    for (const std::uint32_t p : t->points())
      guard_[4 * std::size_t(p)] = std::min(guard_[4 * std::size_t(p)], float(t->drift_limit()));
}

void GpuVbdContacts::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unsigned(Buf::vbd_contacts), buffer_);
}

}  // namespace maille::gpu
