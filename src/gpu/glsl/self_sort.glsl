// The body of self_sort_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= u_count) return;
  uint begin = sc_cell_start[c], end = sc_cell_start[c + 1u];
  for (uint i = begin + 1u; i < end; ++i) {
    uint key = sc_order[i], j = i;
    for (; j > begin && sc_order[j - 1u] > key; --j) sc_order[j] = sc_order[j - 1u];
    sc_order[j] = key;
  }
}
