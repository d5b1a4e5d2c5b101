// The body of self_zero_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < u_count) sc_cell_start[i] = 0u;
}
