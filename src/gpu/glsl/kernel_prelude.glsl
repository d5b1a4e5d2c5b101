// The prelude of every kernel, after the version, work group, records and buffers
// (kernel_head in src/gpu/shaders.cpp): the shared laws' macros with float as `real`, and the
// packed-vec3 helpers LOAD3 / STORE3 and LOAD_PARAMS for a link parameter set.
#define real float
#define MAILLE_SHARED
#define MAILLE_UNUSED(x)
#define MAILLE_OUT(T) out T
#define MAILLE_INOUT(T) inout T
float largest_real() { return uintBitsToFloat(0x7f7fffffu); }
vec3 zero3() { return vec3(0.0); }
mat3 outer3(vec3 a, vec3 b) { return outerProduct(a, b); }
mat3 identity3() { return mat3(1.0); }
// A link parameter set's four values (a kernel that reads link_params).
#define LOAD_PARAMS(s) vec4(link_params[4u * (s)], link_params[4u * (s) + 1u], \
  link_params[4u * (s) + 2u], link_params[4u * (s) + 3u])
#define LOAD3(buf, i) vec3(buf[3u * (i)], buf[3u * (i) + 1u], buf[3u * (i) + 2u])
#define STORE3(buf, i, value) { vec3 s_ = (value); uint k_ = 3u * (i); \
  buf[k_] = s_.x; buf[k_ + 1u] = s_.y; buf[k_ + 2u] = s_.z; }
uniform uint u_count;  // points, faces or driven points: the invocations that work
