// The step's point pairs inside the GPU's VBD: see gpu_vbd_pairs.hpp.
#include "gpu_vbd_pairs.hpp"

#include <epoxy/gl.h>

#include <bit>
#include <limits>
#include <stdexcept>
#include <string>

#include "../collision/self/self_contact_link.hpp"
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
void VbdGraph::colour(VbdColours& out, std::span<const std::uint32_t> pair_row,
                      std::span<const std::uint32_t> pair_other) {
  colour_.assign(points_, kUncoloured);
  const bool pairs = !pair_row.empty();
  const std::uint32_t count =
      colour_points(free_, colour_, stamp_, [&](std::uint32_t i, auto&& visit) {
        for (std::uint32_t k = row_[i]; k < row_[i + 1]; ++k) visit(other_[k]);
        if (pairs)
          for (std::uint32_t k = pair_row[i]; k < pair_row[i + 1]; ++k) visit(pair_other[k]);
      });
  detail::build_rows(count, out.row, out.order, [&](auto&& emit) {
    for (const std::uint32_t i : free_) emit(colour_[i], i);
  });
}

GpuVbdPairs::GpuVbdPairs() {
  glCreateBuffers(1, &buffer_);
}

GpuVbdPairs::~GpuVbdPairs() {
  if (!forgotten_) glDeleteBuffers(1, &buffer_);
}

void GpuVbdPairs::load(const Model& m, VbdColours& colours) {
  points_ = m.points.size();
  graph_ = VbdGraph(m);
  pack(ContactSet{});
  graph_.colour(colours);
}

std::size_t GpuVbdPairs::update(const ContactSet& set, VbdColours& colours) {
  pack(set);
  graph_.colour(colours, pair_row_, pair_other_);
  return ends_.size() / 2;
}

// vbd_pairs (gpu_layout.hpp): the point count, each point's first entry, its bound (+inf until
// the bounds pass), then the entries: the other point and the pair's law.
void GpuVbdPairs::pack(const ContactSet& set) {
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
  // Entry k = 2 p + e: pair p seen from its end e (0: its first point), in the set's order.
  detail::build_rows(points_, pair_row_, pair_entry_, [&](auto&& emit) {
    for (std::size_t k = 0; k < ends_.size(); ++k) emit(ends_[k], std::uint32_t(k));
  });
  pair_other_.resize(pair_entry_.size());
  for (std::size_t e = 0; e < pair_entry_.size(); ++e) pair_other_[e] = ends_[pair_entry_[e] ^ 1u];
  const std::size_t n = points_, base = 2 * n + 2;
  words_.assign(base + kVbdPairWords * pair_entry_.size(), 0u);
  words_[0] = points_;
  for (std::size_t i = 0; i <= n; ++i) words_[1 + i] = pair_row_[i];
  const std::uint32_t inf = std::bit_cast<std::uint32_t>(std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < n; ++i) words_[n + 2 + i] = inf;
  for (std::size_t e = 0; e < pair_entry_.size(); ++e) {
    std::uint32_t* w = words_.data() + base + kVbdPairWords * e;
    const std::size_t p = pair_entry_[e] / 2;
    w[0] = pair_other_[e];
    for (std::size_t v = 0; v < kLawValues; ++v)
      w[1 + v] = std::bit_cast<std::uint32_t>(laws_[kLawValues * p + v]);
  }
  upload(buffer_, words_);
}

void GpuVbdPairs::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unsigned(Buf::vbd_pairs), buffer_);
}

}  // namespace maille::gpu
