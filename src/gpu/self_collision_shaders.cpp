// The self-collision grid's kernels (shaders.hpp lists them in the order a step runs them). The
// contact law is the CPU stage's, pasted from include/maille/detail/link_laws.glsl.
#include "gpu_glsl.hpp"
#include "gpu_layout.hpp"
#include "shaders.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// A grid kernel's source: the head, the grid's helpers, then `parts`.
std::string self_kernel(std::initializer_list<Buf> used,
                        std::initializer_list<std::string_view> parts) {
  std::string s = kernel_source(used, {glsl::grid_helpers});
  for (const std::string_view part : parts) s += part;
  return s;
}

}  // namespace

std::vector<KernelSource> self_collision_kernels() {
  // The scan's block: the counts one work group scans.
  const std::string block = "const uint kBlock = " + std::to_string(kScanBlock) + "u;\n";
  return {
      {"bounds", self_kernel({Buf::x, Buf::sc_particle, Buf::sc_grid}, {glsl::self_bounds})},
      {"grid", self_kernel({Buf::sc_grid}, {glsl::self_grid})},
      {"zero", self_kernel({Buf::sc_cell_start}, {glsl::self_zero})},
      {"count",
       self_kernel({Buf::x, Buf::sc_particle, Buf::sc_grid, Buf::sc_slot, Buf::sc_cell_start},
                   {glsl::self_count})},
      // Blelloch's work-efficient scan of one block in shared memory: an up-sweep builds
      // partial sums in a balanced tree, the root (the block's total) is saved and cleared, a
      // down-sweep turns the tree into exclusive prefix sums. 2 (B - 1) additions for B counts.
      {"scan", self_kernel({Buf::sc_cell_start}, {block, glsl::self_scan})},
      {"scan add", self_kernel({Buf::sc_cell_start}, {block, glsl::self_scan_add})},
      {"scatter",
       self_kernel({Buf::sc_slot, Buf::sc_cell_start, Buf::sc_order}, {glsl::self_scatter})},
      {"sort", self_kernel({Buf::sc_cell_start, Buf::sc_order}, {glsl::self_sort})},
      {"contacts", self_kernel({Buf::x, Buf::v, Buf::f, Buf::sc_particle, Buf::sc_excluded_offset,
                                Buf::sc_excluded, Buf::sc_slot, Buf::sc_cell_start, Buf::sc_order,
                                Buf::sc_grid, Buf::sc_contacts},
                               {shared::link_laws, glsl::self_contacts})},
  };
}

}  // namespace maille::gpu
