// The self-collision grid's kernels (shaders.hpp lists them in the order a step runs them). The
// contact law is the CPU stage's, pasted from include/maille/detail/link_laws.glsl.
#include "gpu_layout.hpp"
#include "shaders.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// The grid's helpers: the order-preserving bits of a float (for atomicMin / atomicMax on the
// box) and the clamped cell of a position.
const char* kGridHelpers = R"(
uint sc_bits(float f) {
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}
float sc_float(uint u) {
  return uintBitsToFloat((u & 0x80000000u) != 0u ? (u & 0x7fffffffu) : ~u);
}
// Positions outside the grid (or not finite) go to its border cells: they only gain candidates,
// which the distance test then rejects.
uint sc_cell_of(vec3 p, SelfGrid g) {
  vec3 q = (p - vec3(g.origin_x, g.origin_y, g.origin_z)) / g.cell;
  if (any(isnan(q))) q = vec3(0.0);
  q = clamp(q, vec3(0.0), vec3(float(g.nx - 1u), float(g.ny - 1u), float(g.nz - 1u)));
  uvec3 c = uvec3(q);
  return (c.z * g.ny + c.y) * g.nx + c.x;
}
)";

std::string self_head(std::initializer_list<Buf> used) {
  return kernel_head(used) + kGridHelpers;
}

}  // namespace

std::string self_bounds_shader() {
  std::string s = self_head({Buf::x, Buf::sc_particle, Buf::sc_grid});
  s += R"(
shared vec3 s_lo[gl_WorkGroupSize.x];
shared vec3 s_hi[gl_WorkGroupSize.x];
void main() {
  uint a = gl_GlobalInvocationID.x, t = gl_LocalInvocationID.x;
  vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
  if (a < u_count) {
    vec3 p = LOAD3(x, sc_particle[a]);
    if (!any(isnan(p)) && !any(isinf(p))) lo = hi = p;
  }
  s_lo[t] = lo;
  s_hi[t] = hi;
  for (uint d = gl_WorkGroupSize.x / 2u; d > 0u; d >>= 1u) {
    memoryBarrierShared();
    barrier();
    if (t < d) {
      s_lo[t] = min(s_lo[t], s_lo[t + d]);
      s_hi[t] = max(s_hi[t], s_hi[t + d]);
    }
  }
  if (t == 0u && s_lo[0].x <= s_hi[0].x) {
    atomicMin(sc_grid[0].lo_x, sc_bits(s_lo[0].x));
    atomicMin(sc_grid[0].lo_y, sc_bits(s_lo[0].y));
    atomicMin(sc_grid[0].lo_z, sc_bits(s_lo[0].z));
    atomicMax(sc_grid[0].hi_x, sc_bits(s_hi[0].x));
    atomicMax(sc_grid[0].hi_y, sc_bits(s_hi[0].y));
    atomicMax(sc_grid[0].hi_z, sc_bits(s_hi[0].z));
  }
}
)";
  return s;
}

std::string self_grid_shader() {
  std::string s = self_head({Buf::sc_grid});
  s += R"(
uniform float u_cell;   // m: the smallest cell size (>= the contact distance)
uniform uint u_budget;  // cells at most
void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  SelfGrid g = sc_grid[0];
  vec3 lo = vec3(sc_float(g.lo_x), sc_float(g.lo_y), sc_float(g.lo_z));
  vec3 hi = vec3(sc_float(g.hi_x), sc_float(g.hi_y), sc_float(g.hi_z));
  if (!(lo.x <= hi.x)) lo = hi = vec3(0.0);  // no finite position
  vec3 ext = min(hi - lo, vec3(1.0e30));
  // As the CPU's uniform grid: the cell grows by 1.25 until the box fits the budget.
  float c = u_cell;
  uvec3 n = uvec3(1u);
  for (int k = 0; k < 1000; ++k, c *= 1.25) {
    vec3 q = floor(ext / c) + 1.0;
    if (q.x * q.y * q.z > float(u_budget)) continue;
    n = uvec3(q);
    if (n.x * n.y * n.z <= u_budget) break;  // exact (the float product was within rounding)
  }
  g.origin_x = lo.x;
  g.origin_y = lo.y;
  g.origin_z = lo.z;
  g.cell = c;
  g.nx = n.x;
  g.ny = n.y;
  g.nz = n.z;
  g.lo_x = g.lo_y = g.lo_z = 0xffffffffu;  // the next step's box starts empty
  g.hi_x = g.hi_y = g.hi_z = 0u;
  sc_grid[0] = g;
}
)";
  return s;
}

std::string self_zero_shader() {
  std::string s = self_head({Buf::sc_cell_start});
  s += R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < u_count) sc_cell_start[i] = 0u;
}
)";
  return s;
}

std::string self_count_shader() {
  std::string s =
      self_head({Buf::x, Buf::sc_particle, Buf::sc_grid, Buf::sc_slot, Buf::sc_cell_start});
  s += R"(
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  uint cell = sc_cell_of(LOAD3(x, sc_particle[a]), sc_grid[0]);
  sc_slot[2u * a] = cell;
  sc_slot[2u * a + 1u] = atomicAdd(sc_cell_start[cell], 1u);
}
)";
  return s;
}

// Blelloch's work-efficient scan of one block in shared memory: an up-sweep builds partial sums
// in a balanced tree, the root (the block's total) is saved and cleared, a down-sweep turns the
// tree into exclusive prefix sums. 2 (B - 1) additions for B counts.
std::string self_scan_shader() {
  std::string s = self_head({Buf::sc_cell_start});
  s += "const uint kBlock = " + std::to_string(kScanBlock) + "u;\n";
  s += R"(
uniform uint u_in;        // where this level's counts start in sc_cell_start (u_count of them)
uniform uint u_sums;      // where their blocks' totals go
uniform bool u_has_sums;  // false on the top level (a single block)
shared uint s_tmp[kBlock];
void main() {
  uint t = gl_LocalInvocationID.x, base = gl_WorkGroupID.x * kBlock;
  uint i0 = base + t, i1 = base + t + kBlock / 2u;
  s_tmp[t] = i0 < u_count ? sc_cell_start[u_in + i0] : 0u;
  s_tmp[t + kBlock / 2u] = i1 < u_count ? sc_cell_start[u_in + i1] : 0u;
  uint step = 1u;
  for (uint d = kBlock / 2u; d > 0u; d >>= 1u, step <<= 1u) {
    memoryBarrierShared();
    barrier();
    if (t < d) s_tmp[step * (2u * t + 2u) - 1u] += s_tmp[step * (2u * t + 1u) - 1u];
  }
  memoryBarrierShared();
  barrier();
  if (t == 0u) {
    if (u_has_sums) sc_cell_start[u_sums + gl_WorkGroupID.x] = s_tmp[kBlock - 1u];
    s_tmp[kBlock - 1u] = 0u;
  }
  for (uint d = 1u; d < kBlock; d <<= 1u) {
    step >>= 1u;
    memoryBarrierShared();
    barrier();
    if (t < d) {
      uint ai = step * (2u * t + 1u) - 1u, bi = step * (2u * t + 2u) - 1u;
      uint left = s_tmp[ai];
      s_tmp[ai] = s_tmp[bi];
      s_tmp[bi] += left;
    }
  }
  memoryBarrierShared();
  barrier();
  if (i0 < u_count) sc_cell_start[u_in + i0] = s_tmp[t];
  if (i1 < u_count) sc_cell_start[u_in + i1] = s_tmp[t + kBlock / 2u];
}
)";
  return s;
}

std::string self_scan_add_shader() {
  std::string s = self_head({Buf::sc_cell_start});
  s += "const uint kBlock = " + std::to_string(kScanBlock) + "u;\n";
  s += R"(
uniform uint u_in;    // this level's prefix sums (u_count of them)
uniform uint u_sums;  // its blocks' scanned totals
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  sc_cell_start[u_in + i] += sc_cell_start[u_sums + i / kBlock];
}
)";
  return s;
}

std::string self_scatter_shader() {
  std::string s = self_head({Buf::sc_slot, Buf::sc_cell_start, Buf::sc_order});
  s += R"(
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  sc_order[sc_cell_start[sc_slot[2u * a]] + sc_slot[2u * a + 1u]] = a;
}
)";
  return s;
}

std::string self_sort_shader() {
  std::string s = self_head({Buf::sc_cell_start, Buf::sc_order});
  s += R"(
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
)";
  return s;
}

std::string self_contacts_shader() {
  std::string s = self_head({Buf::x, Buf::v, Buf::f, Buf::sc_particle, Buf::sc_excluded_offset,
                             Buf::sc_excluded, Buf::sc_slot, Buf::sc_cell_start, Buf::sc_order,
                             Buf::sc_grid, Buf::sc_contacts});
  s += shared::link_laws;
  s += R"(
uniform float u_radius;     // s, m: contact distance and the law's rest length
uniform float u_stiffness;  // N/m
uniform float u_damping;    // N.s/m
uniform float u_friction;   // mu
uniform float u_slip;       // m/s: friction is viscous below
uniform bool u_exclude;     // apply the exclusion rows
bool sc_excluded_pair(uint a, uint b) {
  uint lo = sc_excluded_offset[a], hi = sc_excluded_offset[a + 1u];
  while (lo < hi) {
    uint mid = (lo + hi) >> 1u, m = sc_excluded[mid];
    if (m == b) return true;
    if (m < b) lo = mid + 1u; else hi = mid;
  }
  return false;
}
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  SelfGrid g = sc_grid[0];
  uint pa = sc_particle[a];
  vec3 xa = LOAD3(x, pa), va = LOAD3(v, pa);
  uint cell = sc_slot[2u * a];
  ivec3 c = ivec3(int(cell % g.nx), int((cell / g.nx) % g.ny), int(cell / (g.nx * g.ny)));
  ivec3 dims = ivec3(int(g.nx), int(g.ny), int(g.nz));
  float s2 = u_radius * u_radius;
  vec3 fi = vec3(0.0);
  uint found = 0u;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 o = c + ivec3(dx, dy, dz);
        if (any(lessThan(o, ivec3(0))) || any(greaterThanEqual(o, dims))) continue;
        uint other = uint((o.z * dims.y + o.y) * dims.x + o.x);
        uint end = sc_cell_start[other + 1u];
        for (uint e = sc_cell_start[other]; e < end; ++e) {
          uint b = sc_order[e];
          if (b == a) continue;
          uint pb = sc_particle[b];
          vec3 xb = LOAD3(x, pb);
          vec3 d = xb - xa;
          if (dot(d, d) >= s2) continue;
          if (u_exclude && sc_excluded_pair(a, b)) continue;
          vec3 vb = LOAD3(v, pb);
          vec3 fn = contact_normal_law(xa, xb, va, vb, u_stiffness, u_damping, u_radius);
          fi += fn;
          if (u_friction > 0.0)
            fi += contact_friction_law(xa, xb, va, vb, fn, u_friction, u_slip);
          ++found;
        }
      }
  STORE3(f, pa, LOAD3(f, pa) + fi);
  sc_contacts[a] = found;
}
)";
  return s;
}

}  // namespace maille::gpu
