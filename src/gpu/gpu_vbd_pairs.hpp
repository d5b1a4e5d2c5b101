// The step's point pairs inside the GPU's vertex block descent (gpu_vbd.hpp): the contact set's
// point-point pairs (self-collision with primitive = "points", [[contact]] through the broad
// phase), found on the host at the step's start by the stages themselves (Simulator::
// find_pairs_for_backend, at their reach plus the step's motion margin, as the CPU's step finds
// them) and uploaded, not found again on the device. Per step:
//   pack     each pair seen from both of its points (CSR by point, in the set's order) with its
//            law: the conditional spring-damper (k, z, threshold, rest length) and the lagged
//            friction (mu, F_n and the normal of the step's start), into vbd_pairs
//   colour   the CPU's greedy rule over the model's links and this step's pairs, so that no two
//            points of a colour share a link or a pair: a point's partners never move while it
//            reads them, and the sweeps are the CPU's Gauss-Seidel (no race, the same bits on
//            every run)
// and in the kernels (glsl/vbd_pairs.glsl, glsl/vbd_bounds.glsl): each pair's force and block
// from the shared laws (conditional_law, conditional_law_block, lagged_friction_scale in
// include/maille/detail/link_laws.glsl, which the CPU's kinds call), and the CPU's conservative
// bounds (implicit_vbd.hpp, kBoundFraction): before the guess and before every sweep, each
// point of a pair may move at most 0.4 of its distance to its nearest partner in one update,
// and is not extrapolated.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/contact_set.hpp"
#include "maille/model.hpp"

namespace maille::gpu {

// Free points by colour (the CPU's greedy rule over every link of the model, and a step's pairs).
struct VbdColours {
  std::vector<std::uint32_t> order;  // free points, colour by colour, increasing in each
  std::vector<std::uint32_t> row;    // colour c: order[row[c] .. row[c + 1])
  std::uint32_t count() const { return row.empty() ? 0 : std::uint32_t(row.size() - 1); }
};

// The model's free points and link graph (both ends of every link, conditional links included
// as if active: the device does not search them), coloured with or without a step's pairs.
class VbdGraph {
 public:
  VbdGraph() = default;
  explicit VbdGraph(const Model& m);
  // Greedy in point order: the smallest colour none of the point's coloured neighbours holds,
  // its links' and, when given, its pairs' (`pair_row`: CSR by point of `pair_other`).
  void colour(VbdColours& out, std::span<const std::uint32_t> pair_row = {},
              std::span<const std::uint32_t> pair_other = {});

 private:
  std::uint32_t points_ = 0;
  std::vector<std::uint32_t> free_, row_, other_, colour_, stamp_;
};

class GpuVbdPairs {
 public:
  GpuVbdPairs();  // the context must be current
  ~GpuVbdPairs();
  GpuVbdPairs(const GpuVbdPairs&) = delete;
  GpuVbdPairs& operator=(const GpuVbdPairs&) = delete;
  void forget() { forgotten_ = true; }  // the context is gone: nothing to delete

  // The model's graph, and an empty buffer of its shape (no pairs); its colours into `colours`.
  void load(const Model& m, VbdColours& colours);
  // This step's pairs from `set` into the device's buffer, and the colours of the links and
  // the pairs into `colours`. Returns the number of pairs. Throws std::runtime_error for a pair
  // pool whose law has no device version (a kind other than the two above).
  std::size_t update(const ContactSet& set, VbdColours& colours);
  void bind() const;

 private:
  void pack(const ContactSet& set);

  bool forgotten_ = false;
  unsigned buffer_ = 0;
  std::uint32_t points_ = 0;
  VbdGraph graph_;
  std::vector<std::uint32_t> ends_;                   // per pair: its two points
  std::vector<float> laws_;                           // per pair: its law's values
  std::vector<std::uint32_t> pair_row_, pair_entry_;  // the pairs' ends, CSR by point
  std::vector<std::uint32_t> pair_other_;             // per entry: the other point
  std::vector<std::uint32_t> words_;                  // vbd_pairs' contents
};

}  // namespace maille::gpu
