// The body of self_scatter_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's
// head, buffers and laws before it).
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  sc_order[sc_cell_start[sc_slot[2u * a]] + sc_slot[2u * a + 1u]] = a;
}
