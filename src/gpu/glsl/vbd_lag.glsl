// The body of vbd_lag_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head, buffers
// and laws before it).
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count || inv_mass[i] == 0.0) return;
  ob_lag(i, LOAD3(x, i), LOAD3(v, i));
}
