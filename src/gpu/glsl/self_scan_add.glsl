// The body of self_scan_add_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's
// head, buffers and laws before it).
uniform uint u_in;    // this level's prefix sums (u_count of them)
uniform uint u_sums;  // its blocks' scanned totals
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  sc_cell_start[u_in + i] += sc_cell_start[u_sums + i / kBlock];
}
