// The GPU's structured layout for grid cloth: the links the CPU's structured kernel takes
// (detail/structured_grid.hpp: structural, shear and bend links of a regular grid, found by
// neighbour offset) run per point by fixed offsets instead of through the per-point adjacency.
//
// One forces dispatch per grid: each point of the grid finds its stencil neighbours by row and
// column arithmetic (point first + j nx + i), reads which of its 12 stencil links exist from
// one word (holes: a missing link is a clear bit), their parameters from one set per family
// where the grid's family is uniform (else per link, as the CPU does), and its other links
// (off the families, duplicates, other kinds) from a short adjacency of its own. The points off
// the grids run the general forces kernel over the ranges between the grids. Nothing else of
// the step changes: faces, integration, stages and the full adjacency stay as they are.
//
// The sum of a point's forces is taken in the general path's order: its adjacency lists a
// grid point's links by storage slot, and the CPU stores the structured links row by row, family
// by family, column by column, so the stencil visits them in that order (second end from row
// j - 2, then j - 1, then row j's families) between the other links of the kinds stored before
// and after. Each link's force is the same shared law on the same floats, so the two layouts
// agree bit for bit unless the shader compiler contracts multiply-adds differently in the two
// kernels; the stated bound (tests/gpu/test_gpu_structured.cpp) is the float bound of one
// link's force per link.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "maille/gpu.hpp"
#include "maille/model.hpp"
#include "non_copyable.hpp"
#include "shaders.hpp"

namespace maille::gpu {

// MAILLE_GPU_LAYOUT (auto | structured | general; unset: automatic); throws
// std::invalid_argument naming the variable for another value.
GridLayout grid_layout_from_environment();
std::string_view to_string(GridLayout layout);

// What the backend's packing knows of each link: its parameter set (an index in the LinkParams
// buffer), by pool (m.links.pools() order) and storage slot, and each pool's kind index in the
// forces kernel's switch (-1 for an empty pool).
struct LinkSets {
  std::vector<std::uint32_t> set_of_slot;  // every pool's slots, pool after pool
  std::vector<std::size_t> pool_base;      // [pools] where each pool's slots start
  std::vector<int> pool_kind;              // [pools]
};

class GpuStructured : NonCopyable {
 public:
  struct Range {
    std::uint32_t first = 0, count = 0;
  };
  // The structured layout for m, or null when it takes no grid (layout general, no grid links,
  // or, automatic, no grid of kStructuredMinPoints). The step's context is current. `previous`
  // (the last load's, or null) gives up its buffers and, when the kernel's source is the same,
  // its program.
  static std::unique_ptr<GpuStructured> make(const Model& m, const LinkSets& sets,
                                             const std::vector<KindLaw>& kinds, GridLayout layout,
                                             GpuStructured* previous);
  ~GpuStructured();
  // Frees nothing: the context is gone or not current (its objects go with it).
  void forget();

  // The points the general forces kernel still runs (between and after the grids).
  const std::vector<Range>& general_ranges() const { return general_; }
  std::vector<StructuredGridInfo> grids() const;
  // The forces of the grids' points into f (the step's buffers bound, the faces' forces ready).
  void evaluate(const Vec3& gravity, float drag, bool wind);

 private:
  struct Grid;
  GpuStructured() = default;
  void set_grid(const Grid& grid);  // its uniforms
  std::vector<Grid> grids_;
  std::vector<Range> general_;
  std::string source_;  // the kernel's
  unsigned program_ = 0;
  unsigned buffers_[4] = {};
  int loc_[9] = {};  // the kernel's uniforms (gpu_structured.cpp: Uniform)
};

}  // namespace maille::gpu
