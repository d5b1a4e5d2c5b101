// The body of vbd_decide_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head, buffers
// and laws before it).
uniform uint u_k;      // the sweep just run, from 1
uniform uint u_slots;  // the sweep's work groups
uniform float u_growth;
void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  float merit = 0.0;
  for (uint s_ = 0u; s_ < u_slots; ++s_) merit += uintBitsToFloat(vbd_state[8u + s_]);
  if (vbd_state[0] != 0u && u_k >= 3u && merit > u_growth * uintBitsToFloat(vbd_state[2])) {
    vbd_state[0] = 0u;
    vbd_state[3] += 1u;
  }
  vbd_state[2] = floatBitsToUint(merit);
}
