// The self-collision grid's kernels (shaders.hpp lists them in the order a step runs them). The
// contact law is the CPU stage's, pasted from include/maille/detail/link_laws.glsl.
#include "gpu_glsl.hpp"
#include "gpu_layout.hpp"
#include "shaders.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

std::string self_head(std::initializer_list<Buf> used) {
  return kernel_head(used) + std::string(glsl::grid_helpers);
}

}  // namespace

std::string self_bounds_shader() {
  std::string s = self_head({Buf::x, Buf::sc_particle, Buf::sc_grid});
  s += glsl::self_bounds;
  return s;
}

std::string self_grid_shader() {
  std::string s = self_head({Buf::sc_grid});
  s += glsl::self_grid;
  return s;
}

std::string self_zero_shader() {
  std::string s = self_head({Buf::sc_cell_start});
  s += glsl::self_zero;
  return s;
}

std::string self_count_shader() {
  std::string s =
      self_head({Buf::x, Buf::sc_particle, Buf::sc_grid, Buf::sc_slot, Buf::sc_cell_start});
  s += glsl::self_count;
  return s;
}

// Blelloch's work-efficient scan of one block in shared memory: an up-sweep builds partial sums
// in a balanced tree, the root (the block's total) is saved and cleared, a down-sweep turns the
// tree into exclusive prefix sums. 2 (B - 1) additions for B counts.
std::string self_scan_shader() {
  std::string s = self_head({Buf::sc_cell_start});
  s += "const uint kBlock = " + std::to_string(kScanBlock) + "u;\n";
  s += glsl::self_scan;
  return s;
}

std::string self_scan_add_shader() {
  std::string s = self_head({Buf::sc_cell_start});
  s += "const uint kBlock = " + std::to_string(kScanBlock) + "u;\n";
  s += glsl::self_scan_add;
  return s;
}

std::string self_scatter_shader() {
  std::string s = self_head({Buf::sc_slot, Buf::sc_cell_start, Buf::sc_order});
  s += glsl::self_scatter;
  return s;
}

std::string self_sort_shader() {
  std::string s = self_head({Buf::sc_cell_start, Buf::sc_order});
  s += glsl::self_sort;
  return s;
}

std::string self_contacts_shader() {
  std::string s = self_head({Buf::x, Buf::v, Buf::f, Buf::sc_particle, Buf::sc_excluded_offset,
                             Buf::sc_excluded, Buf::sc_slot, Buf::sc_cell_start, Buf::sc_order,
                             Buf::sc_grid, Buf::sc_contacts});
  s += shared::link_laws;
  s += glsl::self_contacts;
  return s;
}

}  // namespace maille::gpu
