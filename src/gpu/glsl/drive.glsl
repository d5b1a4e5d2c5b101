// The body of drive_shader (src/gpu/shaders.cpp, which puts the kernel's head, buffers and laws
// before it).
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= u_count) return;
  DrivenPoint d = driven[k];
  STORE3(x, d.point, vec3(d.px, d.py, d.pz));
  STORE3(v, d.point, vec3(d.vx, d.vy, d.vz));
}
