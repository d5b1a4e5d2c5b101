// The body of vbd_health_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head, buffers
// and laws before it).
uniform uint u_step;  // the step count after this step (the health flag's value)
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec3 xi = LOAD3(x, i);
  vec3 vi = LOAD3(v, i);
  if (any(isnan(xi)) || any(isinf(xi)) || any(isnan(vi)) || any(isinf(vi)))
    atomicMin(health[0], u_step);
}
