// The GPU step's buffers and records, declared once. The host code binds and fills them through
// the C++ names generated here (enum Buf, struct Adjacent, struct DrivenPoint), and every shader
// gets its GLSL declarations generated from the same lists (glsl_records, glsl_buffers), so the
// two sides cannot drift apart. Records hold 32-bit scalars only: their std430 layout is then
// the C++ one, member by member (checked below).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>

namespace maille::gpu {

// Buffer bindings: X(binding, block name, element type, array name, what it holds).
#define MAILLE_GPU_BUFFERS(X)                                                                 \
  X(0, Positions, float, x, "m, 3 per point, packed (the renderer draws from it)")            \
  X(1, Velocities, float, v, "m/s, 3 per point")                                              \
  X(2, Forces, float, f, "N, 3 per point")                                                    \
  X(3, InvMasses, float, inv_mass, "1/kg per point; 0 for fixed and driven points")           \
  X(4, Masses, float, mass, "kg per point")                                                   \
  X(5, AdjacencyOffsets, uint, adjacency_offset, "n + 1: point i's links are [o[i], o[i+1])") \
  X(6, Adjacency, Adjacent, adjacency, "each point's links, as seen from that point")         \
  X(7, LinkParams, float, link_params, "4 per distinct parameter set")                        \
  X(8, FaceOffsets, uint, face_offset, "n + 1: point i's faces are [o[i], o[i+1])")           \
  X(9, FaceIncidence, uint, face_of_point, "the faces of each point")                         \
  X(10, FaceCorners, uint, face_corner, "3 per face")                                         \
  X(11, FaceForces, float, face_force, "N on each corner, 3 per face")                        \
  X(12, DrivenPoints, DrivenPoint, driven, "driven points' positions and velocities at t")    \
  X(13, Health, uint, health, "[0]: first step with a non-finite value; 0xffffffff: none")

// The self-collision grid's buffers (gpu_self_collision.hpp), after the step's: owned and bound
// by each self-collision stage's GPU version. n_c: colliding particles; cells: the grid's cell
// budget (its scan covers cells + 1 counts).
#define MAILLE_GPU_SELF_BUFFERS(X)                                                             \
  X(14, SelfParticles, uint, sc_particle, "n_c: global point id of each colliding particle")   \
  X(15, SelfExclusionOffsets, uint, sc_excluded_offset,                                        \
    "n_c + 1: particle a's excluded partners are [o[a], o[a+1])")                              \
  X(16, SelfExclusions, uint, sc_excluded, "excluded partners, local indices, sorted per row") \
  X(17, SelfSlots, uint, sc_slot, "2 per colliding particle: its cell, its rank in the cell")  \
  X(18, SelfCellStarts, uint, sc_cell_start,                                                   \
    "cells + 1 counts, then their exclusive prefix sums; then the scan's block sums")          \
  X(19, SelfOrder, uint, sc_order, "n_c: local indices sorted by cell, by index in a cell")    \
  X(20, SelfGrids, SelfGrid, sc_grid, "[0]: this step's bounding box and grid")                \
  X(21, SelfContacts, uint, sc_contacts, "n_c: contacts of each particle in the last pass")

// Implicit Euler by vertex block descent (gpu_vbd.hpp), after the self-collision's: owned and
// bound by the backend's GpuVbd.
#define MAILLE_GPU_VBD_BUFFERS(X)                                                            \
  X(22, VbdStart, float, vbd_xn, "m, 3 per point: x_n, the step's start")                    \
  X(23, VbdTarget, float, vbd_y, "m, 3 per point: y = x_n + h v_n + h^2 f_ext / m")          \
  X(24, VbdLastVelocity, float, vbd_vlast, "m/s, 3 per point: v at the last step's start")   \
  X(25, VbdPrevious1, float, vbd_prev1, "m, 3 per point: the last sweep's x (acceleration)") \
  X(26, VbdPrevious2, float, vbd_prev2, "m, 3 per point: the sweep's before (acceleration)") \
  X(27, VbdOrder, uint, vbd_order, "free points by colour, increasing in each colour")       \
  X(28, VbdSolver, uint, vbd_state,                                                          \
    "[0] accelerating, [2] the last sweep's merit (float bits), [3] acceleration resets, "   \
    "[4] the residual's largest |g| (float bits); [8 + s] work group s's merit in a sweep")
// The structured layout's buffers (gpu_structured.hpp), after VBD's: owned and
// bound by the backend's GpuStructured. Grid points: the points of the grids it runs, grid by
// grid.
#define MAILLE_GPU_GRID_BUFFERS(X)                                                           \
  X(29, GridPoints, uint, grid_point,                                                        \
    "per grid point: bit f its link of family f as first end, bit 6 + f as second end; "     \
    "bits 12+: its other links before them")                                                 \
  X(30, GridOtherOffsets, uint, grid_other_offset,                                           \
    "grid points + 1: grid point k's other links are [o[k], o[k+1])")                        \
  X(31, GridOthers, Adjacent, grid_other, "the grid points' links the stencil does not run") \
  X(32, GridLinkSets, uint, grid_link_set,                                                   \
    "6 per grid point: the parameter set of its link of family f as first end")

// Geometric obstacles' buffers (gpu_obstacle.hpp), after the structured layout's: ob_point owned
// by each obstacle's GPU version and bound before its dispatch (n_o: its colliding points); the
// others by the backend's GpuVbd (gpu_vbd_obstacles.hpp), for its solve's contact terms.
#define MAILLE_GPU_OBSTACLE_BUFFERS(X)                                                    \
  X(33, ObstaclePoints, uint, ob_point, "n_o: global point id of each colliding point")   \
  X(34, VbdObstacles, ObstacleRecord, vbd_obstacles,                                      \
    "implicit Euler by VBD: the geometric obstacles placed at t, then placed at t + h")   \
  X(35, VbdObstacleMembers, uint, vbd_ob_member,                                          \
    "per point: bit o set when obstacle o collides with it")                              \
  X(36, VbdObstacleLag, float, vbd_ob_lag,                                                \
    "4 per point and obstacle (point-major): lagged friction's normal force (N), normal") \
  X(37, VbdTouching, uint, vbd_touch, "per point: 1 while it touches an obstacle (a sweep's)")

// The step's contacts under implicit Euler by VBD (gpu_vbd_contacts.hpp), after the obstacles':
// owned and bound by the backend's GpuVbdContacts. One buffer (a sweep may bind at most 16
// storage blocks), n the model's points, kVbdContactHeader words of header: [0] n, then where
// each part starts: [1] each point's bound (float bits, n), [2] each point's first pair entry
// (n + 1), [3] the pair entries (kVbdPairWords each), [4] each point's first stencil entry
// (n + 1), [5] the stencil entries (candidate * 4 + role), [6] the stencils (kVbdStencilWords
// each), [7] each point's drift ball (limit, then its centre: 4 floats).
#define MAILLE_GPU_VBD_CONTACT_BUFFERS(X) \
  X(38, VbdContacts, uint, vbd_contacts,  \
    "the step's contact pairs and stencils seen from each of their points, bounds, drift balls")

enum class Buf : unsigned {
#define MAILLE_GPU_ENUM(binding, block, type, name, doc) name = binding,
  MAILLE_GPU_BUFFERS(MAILLE_GPU_ENUM) MAILLE_GPU_SELF_BUFFERS(MAILLE_GPU_ENUM)
      MAILLE_GPU_VBD_BUFFERS(MAILLE_GPU_ENUM) MAILLE_GPU_GRID_BUFFERS(MAILLE_GPU_ENUM)
          MAILLE_GPU_OBSTACLE_BUFFERS(MAILLE_GPU_ENUM)
              MAILLE_GPU_VBD_CONTACT_BUFFERS(MAILLE_GPU_ENUM)
#undef MAILLE_GPU_ENUM
};
#define MAILLE_GPU_COUNT_BUFFER(binding, block, type, name, doc) +1
// The step's buffers are bindings [0, kBufferCount), the self-collision's the next
// kSelfBufferCount.
inline constexpr unsigned kBufferCount = 0 MAILLE_GPU_BUFFERS(MAILLE_GPU_COUNT_BUFFER);
inline constexpr unsigned kSelfBufferCount = 0 MAILLE_GPU_SELF_BUFFERS(MAILLE_GPU_COUNT_BUFFER);
inline constexpr unsigned kVbdBufferCount = 0 MAILLE_GPU_VBD_BUFFERS(MAILLE_GPU_COUNT_BUFFER);
inline constexpr unsigned kGridBufferCount = 0 MAILLE_GPU_GRID_BUFFERS(MAILLE_GPU_COUNT_BUFFER);
inline constexpr unsigned kObstacleBufferCount =
    0 MAILLE_GPU_OBSTACLE_BUFFERS(MAILLE_GPU_COUNT_BUFFER);
#undef MAILLE_GPU_COUNT_BUFFER
static_assert(unsigned(Buf::health) == kBufferCount - 1 &&
              unsigned(Buf::sc_particle) == kBufferCount &&
              unsigned(Buf::sc_contacts) == kBufferCount + kSelfBufferCount - 1 &&
              unsigned(Buf::vbd_xn) == kBufferCount + kSelfBufferCount &&
              unsigned(Buf::vbd_state) == kBufferCount + kSelfBufferCount + kVbdBufferCount - 1 &&
              unsigned(Buf::grid_point) == kBufferCount + kSelfBufferCount + kVbdBufferCount &&
              unsigned(Buf::grid_link_set) ==
                  kBufferCount + kSelfBufferCount + kVbdBufferCount + kGridBufferCount - 1 &&
              unsigned(Buf::ob_point) ==
                  kBufferCount + kSelfBufferCount + kVbdBufferCount + kGridBufferCount &&
              unsigned(Buf::vbd_touch) == unsigned(Buf::ob_point) + kObstacleBufferCount - 1 &&
              unsigned(Buf::vbd_contacts) == unsigned(Buf::vbd_touch) + 1);

// Records: F(type, member).
// One link seen from one of its ends: the other end, the kind (its index in the model's GPU
// kinds; bit 31 set when this point is the link's b end) and the index of its parameter set.
#define MAILLE_GPU_ADJACENT(F) F(uint, other) F(uint, kind) F(uint, params)
// A driven point's state at t.
#define MAILLE_GPU_DRIVEN(F) \
  F(uint, point) F(float, px) F(float, py) F(float, pz) F(float, vx) F(float, vy) F(float, vz)

// The self-collision grid of a step. The box is accumulated by atomicMin / atomicMax on the
// coordinates' bits mapped to an order-preserving uint (negative floats flipped whole, positive
// ones with their sign bit set); the grid kernel turns it into an origin, a cell size and
// dimensions, and resets it for the next step.
#define MAILLE_GPU_SELF_GRID(F)                                                         \
  F(uint, lo_x)                                                                         \
  F(uint, lo_y)                                                                         \
  F(uint, lo_z)                                                                         \
  F(uint, hi_x)                                                                         \
  F(uint, hi_y)                                                                         \
  F(uint, hi_z) F(float, origin_x) F(float, origin_y) F(float, origin_z) F(float, cell) \
      F(uint, nx) F(uint, ny) F(uint, nz)

// A geometric obstacle placed at a time, for the device's implicit solve
// (gpu_vbd_obstacles.hpp): the shared law's parameters (obstacle_laws.glsl), M_d and M_i
// row-major, the translation, the surface's velocity as a twist (linear + spin x (x - center)),
// the cull.
#define MAILLE_GPU_OBSTACLE(F)                                                                    \
  F(uint, shape)                                                                                  \
  F(float, shape_parameter)                                                                       \
  F(float, stiffness) F(float, damping) F(float, friction) F(float, slip) F(uint, world_normal)   \
      F(uint, moves) F(float, reach2) F(float, d00) F(float, d01) F(float, d02) F(float, d10)     \
          F(float, d11) F(float, d12) F(float, d20) F(float, d21) F(float, d22) F(float, i00)     \
              F(float, i01) F(float, i02) F(float, i10) F(float, i11) F(float, i12) F(float, i20) \
                  F(float, i21) F(float, i22) F(float, tx) F(float, ty) F(float, tz) F(float, lx) \
                      F(float, ly) F(float, lz) F(float, sx) F(float, sy) F(float, sz)            \
                          F(float, cx) F(float, cy) F(float, cz)

inline constexpr std::uint32_t kEndIsB = 0x80000000u;

// vbd_contacts' parts (above). A contact pair seen from one of its points: the other point,
// then the conditional spring-damper's k, z, threshold s, rest length, and the lagged friction's
// mu, F_n and normal (its sign does not matter: the friction projects across it). A stencil (a
// point-triangle or edge-edge candidate of self-collision): its four points, flags (bit 0: an
// edge pair; bits 1 to 4: which of its corners are colliding particles), the first candidate of
// its particle's run (the once-per-feature rule scans back to it), the radius, k, z, mu, the
// lagged F_n and normal.
inline constexpr std::uint32_t kVbdContactHeader = 8;
inline constexpr std::uint32_t kVbdPairWords = 10;
inline constexpr std::uint32_t kVbdStencilWords = 14;

using uint = std::uint32_t;
#define MAILLE_GPU_MEMBER(type, name) type name;
struct Adjacent {
  MAILLE_GPU_ADJACENT(MAILLE_GPU_MEMBER)
};
struct DrivenPoint {
  MAILLE_GPU_DRIVEN(MAILLE_GPU_MEMBER)
};
struct SelfGrid {
  MAILLE_GPU_SELF_GRID(MAILLE_GPU_MEMBER)
};
struct ObstacleRecord {
  MAILLE_GPU_OBSTACLE(MAILLE_GPU_MEMBER)
};
#undef MAILLE_GPU_MEMBER
#define MAILLE_GPU_COUNT(type, name) +1
static_assert(sizeof(Adjacent) == 4 * (0 MAILLE_GPU_ADJACENT(MAILLE_GPU_COUNT)));
static_assert(sizeof(DrivenPoint) == 4 * (0 MAILLE_GPU_DRIVEN(MAILLE_GPU_COUNT)));
static_assert(sizeof(SelfGrid) == 4 * (0 MAILLE_GPU_SELF_GRID(MAILLE_GPU_COUNT)));
static_assert(sizeof(ObstacleRecord) == 4 * (0 MAILLE_GPU_OBSTACLE(MAILLE_GPU_COUNT)));
#undef MAILLE_GPU_COUNT

// GLSL struct declarations of the records.
inline std::string glsl_records() {
#define MAILLE_GPU_GLSL_MEMBER(type, name) " " #type " " #name ";"
  return "struct Adjacent {" MAILLE_GPU_ADJACENT(MAILLE_GPU_GLSL_MEMBER) " };\n"
         "struct DrivenPoint {" MAILLE_GPU_DRIVEN(MAILLE_GPU_GLSL_MEMBER) " };\n"
         "struct SelfGrid {" MAILLE_GPU_SELF_GRID(MAILLE_GPU_GLSL_MEMBER) " };\n"
         "struct ObstacleRecord {" MAILLE_GPU_OBSTACLE(MAILLE_GPU_GLSL_MEMBER) " };\n";
#undef MAILLE_GPU_GLSL_MEMBER
}

// GLSL declarations of the buffers a shader uses (only those: the number of storage blocks a
// compute shader may use is limited, 8 at the least).
inline std::string glsl_buffers(std::initializer_list<Buf> used) {
  std::string out;
  for (Buf b : used) {
#define MAILLE_GPU_DECLARE(binding, block, type, name, doc)                              \
  if (b == Buf::name)                                                                    \
    out += "layout(std430, binding = " #binding ") buffer " #block " { " #type " " #name \
           "[]; };  // " doc "\n";
    MAILLE_GPU_BUFFERS(MAILLE_GPU_DECLARE)
    MAILLE_GPU_SELF_BUFFERS(MAILLE_GPU_DECLARE)
    MAILLE_GPU_VBD_BUFFERS(MAILLE_GPU_DECLARE)
    MAILLE_GPU_GRID_BUFFERS(MAILLE_GPU_DECLARE)
    MAILLE_GPU_OBSTACLE_BUFFERS(MAILLE_GPU_DECLARE)
    MAILLE_GPU_VBD_CONTACT_BUFFERS(MAILLE_GPU_DECLARE)
#undef MAILLE_GPU_DECLARE
  }
  return out;
}

}  // namespace maille::gpu
