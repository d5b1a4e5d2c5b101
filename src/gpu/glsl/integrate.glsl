// The body of integrate_shader (src/gpu/shaders.cpp, which puts the kernel's head, buffers and laws
// before it).
uniform float u_kick;   // s
uniform float u_drift;  // s
uniform uint u_step;    // the step count after this step (the health flag's value)
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  float w = inv_mass[i];
  vec3 vi = LOAD3(v, i) + LOAD3(f, i) * (w * u_kick);
  vec3 xi = LOAD3(x, i) + vi * (w > 0.0 ? u_drift : 0.0);
  STORE3(v, i, vi);
  STORE3(x, i, xi);
  if (any(isnan(xi)) || any(isinf(xi)) || any(isnan(vi)) || any(isinf(vi)))
    atomicMin(health[0], u_step);
}
