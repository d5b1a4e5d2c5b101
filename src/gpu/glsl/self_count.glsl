// The body of self_count_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  uint cell = sc_cell_of(LOAD3(x, sc_particle[a]), sc_grid[0]);
  sc_slot[2u * a] = cell;
  sc_slot[2u * a + 1u] = atomicAdd(sc_cell_start[cell], 1u);
}
