// The step's contacts inside the GPU's vertex block descent (gpu_vbd.hpp): the contact set's
// point-point pairs (self-collision with primitive = "points", [[contact]] through the broad
// phase) and stencils (self-collision with primitive = "triangles": point-triangle and edge-edge
// candidates), found on the host at the step's start by the stages themselves
// (Simulator::find_contacts_for_backend, at their reach plus the step's motion margin, as the
// CPU's step finds them, their friction lagged there) and uploaded, not found again on the
// device. Per step:
//   pack     each pair and each stencil seen from each of its points (CSR by point, in the set's
//            order) with its law, and each guarded point's drift ball, into vbd_contacts
//   colour   the CPU's greedy rule over the model's links and this step's contacts, so that no
//            two points of a colour share a link, a pair or a stencil: a point's partners never
//            move while it reads them, and the sweeps are the CPU's Gauss-Seidel (no race, the
//            same bits on every run)
// and in the kernels (glsl/vbd_contacts.glsl, glsl/vbd_bounds.glsl), from the shared laws
// (link_laws.glsl: conditional_law and its block, the lagged friction; contact_laws.glsl: the
// closest points, the once-per-feature rule's triangle_feature, the stencil's force, the drift
// guard's ball_hold), which the CPU's kinds and TriangleContactTerms call:
//   terms    each pair's and stencil's force and block at the iterate
//   bounds   before the guess and before every sweep, each point of a contact moves at most 0.4
//            of its smallest contact distance in one update (the CPU's conservative bounds,
//            implicit_vbd.hpp) and is not extrapolated
//   guard    with stencils, each guarded point stays within its drift limit of its prediction
//            (x_n + h v_n; x_n for fixed and driven points): the guarantee of the step's search
//            (docs/implicit.md, "Intersection-free cloth: what holds"). The CPU searches again
//            when a point reaches its limit; the device holds it there for the rest of the step
//            (the next step's search renews the balls): a smaller move, the same guarantee.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/contact_set.hpp"
#include "maille/model.hpp"
#include "maille/vec3.hpp"
#include "non_copyable.hpp"

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
  // its links' and, when given, its contacts' (`contact_row`: CSR by point of
  // `contact_other`).
  void colour(VbdColours& out, std::span<const std::uint32_t> contact_row = {},
              std::span<const std::uint32_t> contact_other = {});

 private:
  std::uint32_t points_ = 0;
  std::vector<std::uint32_t> free_, row_, other_, colour_, stamp_;
};

class GpuVbdContacts : NonCopyable {
 public:
  // The context must be current; `max_block`: the driver's largest storage block, bytes (a
  // step whose contacts need a larger buffer throws std::runtime_error saying so).
  explicit GpuVbdContacts(double max_block);
  ~GpuVbdContacts();
  void forget() { forgotten_ = true; }  // the context is gone: nothing to delete

  // The model's graph, and an empty buffer of its shape (no contacts); its colours into
  // `colours`.
  void load(const Model& m, VbdColours& colours);
  // What this step's contacts hold.
  struct Counts {
    std::size_t pairs = 0, stencils = 0;
    bool guarded = false;  // the stencils keep drift balls
    bool any() const { return pairs + stencils > 0; }
  };
  // This step's contacts from `set` into the device's buffer, and the colours of the links and
  // the contacts into `colours`. Throws std::runtime_error for a pair pool or a stencil stage
  // whose law has no device version (other than the kinds above).
  Counts update(const ContactSet& set, VbdColours& colours);
  void bind() const;

 private:
  void pack(const ContactSet& set);
  void pack_stencils(const ContactSet& set);
  void pack_guard(const ContactSet& set);

  bool forgotten_ = false;
  unsigned buffer_ = 0;
  double max_block_ = 0;
  std::uint32_t points_ = 0;
  VbdGraph graph_;
  std::vector<std::uint32_t> ends_;                         // per pair: its two points
  std::vector<float> laws_;                                 // per pair: its law's values
  std::vector<std::uint32_t> stencils_;                     // per stencil: its kVbdStencilWords
  std::vector<std::uint32_t> pair_row_, pair_entry_;        // the pairs' ends, CSR by point
  std::vector<std::uint32_t> stencil_row_, stencil_entry_;  // the stencils' roles, CSR by point
  std::vector<std::uint32_t> row_, other_;  // every contact neighbour, CSR by point (colouring)
  std::vector<float> guard_;                // per point: limit, centre (the begin pass's)
  std::vector<std::uint32_t> words_;        // vbd_contacts' contents
  Counts counts_;
};

}  // namespace maille::gpu
