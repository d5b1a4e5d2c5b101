// GLSL 4.50 sources of the renderer's passes. Positions live in one buffer of 3 floats per
// point, bound as a shader storage buffer (binding 0) for the passes that fetch points by index
// (links, contacts, points: "vertex pulling", no per-pass copies) and as a vertex attribute for
// the surface pass.
#pragma once

#include <string_view>

namespace maille::render::shaders {

// --- background: one triangle covering the viewport, a vertical gradient -----------------------
inline constexpr std::string_view background_vs = R"(#version 450 core
out float v_height;
void main() {
  vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);  // (0,0) (2,0) (0,2)
  v_height = corner.y * 0.5;
  gl_Position = vec4(corner * 2.0 - 1.0, 0.999, 1.0);
}
)";
inline constexpr std::string_view background_fs = R"(#version 450 core
in float v_height;
out vec4 colour;
void main() {
  colour = vec4(mix(vec3(0.60, 0.62, 0.66), vec3(0.89, 0.90, 0.92), clamp(v_height, 0.0, 1.0)), 1.0);
}
)";

// --- plain lines with a colour per vertex: floor grid and overlays -------------------------------
inline constexpr std::string_view lines_vs = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
uniform mat4 u_view_proj;
out vec3 v_colour;
void main() {
  v_colour = colour;
  gl_Position = u_view_proj * vec4(position, 1.0);
}
)";
inline constexpr std::string_view lines_fs = R"(#version 450 core
in vec3 v_colour;
out vec4 colour;
void main() { colour = vec4(v_colour, 1.0); }
)";

// --- cloth surfaces: per-vertex normals, lit on both sides --------------------------------------
inline constexpr std::string_view surface_vs = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 u_view_proj;
uniform mat4 u_view;
out vec3 v_normal;  // view space
out vec3 v_position;
void main() {
  v_normal = mat3(u_view) * normal;
  v_position = (u_view * vec4(position, 1.0)).xyz;
  gl_Position = u_view_proj * vec4(position, 1.0);
}
)";
inline constexpr std::string_view surface_fs = R"(#version 450 core
in vec3 v_normal;
in vec3 v_position;
out vec4 colour;
const vec3 front = vec3(0.86, 0.30, 0.12);
const vec3 back = vec3(0.93, 0.68, 0.16);
void main() {
  vec3 n = length(v_normal) > 0.0 ? normalize(v_normal) : vec3(0.0, 0.0, 1.0);
  // Each side is lit as seen: the back face turns its normal toward the eye.
  if (!gl_FrontFacing) n = -n;
  vec3 base = gl_FrontFacing ? front : back;
  vec3 key = normalize(vec3(0.45, 0.65, 0.60));   // view space, upper right, toward the eye
  vec3 fill = normalize(vec3(-0.6, -0.2, 0.75));
  vec3 eye = normalize(-v_position);
  float diffuse = max(dot(n, key), 0.0) * 0.65 + max(dot(n, fill), 0.0) * 0.2;
  float specular = pow(max(dot(n, normalize(key + eye)), 0.0), 40.0) * 0.12;
  colour = vec4(base * (0.32 + diffuse) + vec3(specular), 1.0);
}
)";

// --- solids (obstacles): a mesh in its own frame, placed by a uniform, translucent -------------
// x_world = u_model x; normals go through the inverse transpose of the placement's linear part
// (u_normal), so a scaled sphere still shades as an ellipsoid.
inline constexpr std::string_view solid_vs = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 u_view_proj;
uniform mat4 u_view;
uniform mat4 u_model;
uniform mat3 u_normal;
out vec3 v_normal;  // view space
out vec3 v_position;
void main() {
  vec4 world = u_model * vec4(position, 1.0);
  v_normal = mat3(u_view) * (u_normal * normal);
  v_position = (u_view * world).xyz;
  gl_Position = u_view_proj * world;
}
)";
inline constexpr std::string_view solid_fs = R"(#version 450 core
in vec3 v_normal;
in vec3 v_position;
uniform vec4 u_colour;  // RGBA, alpha: opacity of one layer
out vec4 colour;
void main() {
  vec3 eye = normalize(-v_position);
  vec3 n = length(v_normal) > 0.0 ? normalize(v_normal) : eye;
  // The inside (back faces, drawn first) is lit as seen and a little darker, so the far wall
  // reads as the inside of the solid through the near one.
  if (!gl_FrontFacing) n = -n;
  vec3 base = gl_FrontFacing ? u_colour.rgb : u_colour.rgb * 0.75;
  vec3 key = normalize(vec3(0.45, 0.65, 0.60));  // the cloth's lights
  vec3 fill = normalize(vec3(-0.6, -0.2, 0.75));
  float diffuse = max(dot(n, key), 0.0) * 0.65 + max(dot(n, fill), 0.0) * 0.2;
  float specular = pow(max(dot(n, normalize(key + eye)), 0.0), 40.0) * 0.12;
  colour = vec4(base * (0.32 + diffuse) + vec3(specular), u_colour.a);
}
)";

// --- links: 6 vertices (two triangles) per link, a screen-space ribbon of fixed pixel width ------
inline constexpr std::string_view links_vs = R"(#version 450 core
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 1) readonly buffer Ends { uint ends[]; };
layout(std430, binding = 2) readonly buffer Rest { float rest[]; };
uniform mat4 u_view_proj;
uniform vec2 u_viewport;     // pixels
uniform float u_width;       // pixels
uniform float u_strain_range;
uniform int u_first;         // first link drawn
uniform int u_strain;        // 1: colour by strain; 0: u_colour
uniform vec3 u_colour;
out vec3 v_colour;
vec3 point(uint i) { return vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]); }
vec3 strain_colour(float s) {  // s in [-1, 1]: blue, grey, red
  vec3 rest_colour = vec3(0.22, 0.23, 0.26);
  return s >= 0.0 ? mix(rest_colour, vec3(0.92, 0.08, 0.06), s)
                  : mix(rest_colour, vec3(0.10, 0.35, 0.98), -s);
}
void main() {
  int link = u_first + gl_VertexID / 6;
  int corner = gl_VertexID % 6;
  vec3 a = point(ends[2 * link]);
  vec3 b = point(ends[2 * link + 1]);
  vec4 ca = u_view_proj * vec4(a, 1.0);
  vec4 cb = u_view_proj * vec4(b, 1.0);
  vec2 sa = ca.xy / ca.w * u_viewport, sb = cb.xy / cb.w * u_viewport;
  vec2 along = sb - sa;
  along = length(along) > 1e-6 ? normalize(along) : vec2(1.0, 0.0);
  vec2 across = vec2(-along.y, along.x);
  const int at_b[6] = int[6](0, 1, 1, 0, 1, 0);
  const float side[6] = float[6](-1.0, -1.0, 1.0, -1.0, 1.0, 1.0);
  vec4 c = at_b[corner] == 1 ? cb : ca;
  // Offsets in normalised device coordinates span 2 per viewport: half a width each side.
  gl_Position = c + vec4(across * side[corner] * u_width / u_viewport * c.w, 0.0, 0.0);
  if (u_strain == 1) {
    float strain = length(b - a) / rest[link] - 1.0;
    v_colour = strain_colour(clamp(strain / u_strain_range, -1.0, 1.0));
  } else {
    v_colour = u_colour;
  }
}
)";
inline constexpr std::string_view links_fs = lines_fs;

// --- points: sprites shaded as spheres
// ------------------------------------------------------------
inline constexpr std::string_view points_vs = R"(#version 450 core
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 3) readonly buffer Styles { uint style[]; };
uniform mat4 u_view_proj;
uniform float u_pixels_per_metre;  // at unit clip w: viewport height / 2 * projection[1][1]
uniform float u_radius;            // m
out vec3 v_colour;
void main() {
  uint s = style[gl_VertexID];
  vec3 p = vec3(pos[3 * gl_VertexID], pos[3 * gl_VertexID + 1], pos[3 * gl_VertexID + 2]);
  vec4 c = u_view_proj * vec4(p, 1.0);
  if (s == 0u) {  // hidden: outside the clip volume, never rasterised
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = 1.0;
    v_colour = vec3(0.0);
    return;
  }
  float r = s == 1u ? u_radius : u_radius * 1.4;
  gl_Position = c;
  gl_PointSize = clamp(2.0 * r * u_pixels_per_metre / c.w, 3.0, 64.0);
  v_colour = s == 1u ? vec3(0.45, 0.55, 0.72) : (s == 2u ? vec3(0.12, 0.12, 0.14)
                                                         : vec3(0.80, 0.15, 0.75));
}
)";
inline constexpr std::string_view points_fs = R"(#version 450 core
in vec3 v_colour;
out vec4 colour;
void main() {
  vec2 q = gl_PointCoord * 2.0 - 1.0;
  float r2 = dot(q, q);
  if (r2 > 1.0) discard;
  vec3 n = vec3(q.x, -q.y, sqrt(1.0 - r2));
  float light = 0.45 + 0.55 * max(dot(n, normalize(vec3(0.4, 0.6, 0.7))), 0.0);
  colour = vec4(v_colour * light + vec3(0.08) * pow(n.z, 8.0), 1.0);
}
)";

// --- vertex normals: per point, the area-weighted sum of the normals of its faces, normalised --
// (vertex_normals in smooth_surface.cpp, in float). A gather over each point's faces (CSR), so
// no atomics; points on no face get a zero normal.
inline constexpr std::string_view normals_cs = R"(#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 1) writeonly buffer Normals { float normal[]; };
layout(std430, binding = 2) readonly buffer Triangles { uint tri[]; };      // 3 per face
layout(std430, binding = 3) readonly buffer FaceOffset { uint face_offset[]; };  // n + 1
layout(std430, binding = 4) readonly buffer FacesOf { uint face_of[]; };
uniform uint u_points;
vec3 point(uint i) { return vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]); }
void main() {
  uint p = gl_GlobalInvocationID.x;
  if (p >= u_points) return;
  vec3 sum = vec3(0.0);
  for (uint k = face_offset[p]; k < face_offset[p + 1]; ++k) {
    uint f = face_of[k];
    vec3 a = point(tri[3 * f]), b = point(tri[3 * f + 1]), c = point(tri[3 * f + 2]);
    sum += cross(b - a, c - a);  // twice the area, along the normal
  }
  float l = length(sum);
  vec3 n = l > 0.0 && !isinf(l) && !isnan(l) ? sum / l : vec3(0.0);
  normal[3 * p] = n.x;
  normal[3 * p + 1] = n.y;
  normal[3 * p + 2] = n.z;
}
)";

// --- active contacts: the conditional links closer than their threshold, compacted into a list of
// ends and an indirect draw command (6 vertices each) for the links pass. A scene may hold
// all-pairs contact links, of which a handful are active: only those are drawn.
inline constexpr std::string_view contacts_cs = R"(#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 1) readonly buffer Ends { uint ends[]; };            // 2 per link
layout(std430, binding = 2) readonly buffer Threshold { float threshold[]; };
layout(std430, binding = 3) writeonly buffer Active { uint active_ends[]; };       // 2 per contact
// glDrawArraysIndirect's command: vertices (6 per contact, from 0), instances (1), first, base.
layout(std430, binding = 4) buffer Command { uint vertices; uint rest_of_command[3]; };
uniform uint u_links;
vec3 point(uint i) { return vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]); }
void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= u_links) return;
  uint a = ends[2 * c], b = ends[2 * c + 1];
  if (!(length(point(b) - point(a)) < threshold[c])) return;
  uint k = atomicAdd(vertices, 6u) / 6u;
  active_ends[2 * k] = a;
  active_ends[2 * k + 1] = b;
}
)";

// --- bounds of the finite positions: one work group, a strided loop then a tree in shared memory.
// Written as (lo.xyz, any, hi.xyz, 0): any = 0 when no position is finite. For framing a
// device's positions without reading them back; one work group is plenty for a bound read
// once a frame.
inline constexpr std::string_view bounds_cs = R"(#version 450 core
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 1) writeonly buffer Box { vec4 box[2]; };
uniform uint u_points;
shared vec3 s_lo[256];
shared vec3 s_hi[256];
shared uint s_count[256];
void main() {
  uint t = gl_LocalInvocationID.x;
  vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
  uint count = 0u;
  for (uint i = t; i < u_points; i += 256u) {
    vec3 p = vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    if (any(isnan(p)) || any(isinf(p))) continue;
    lo = min(lo, p);
    hi = max(hi, p);
    ++count;
  }
  s_lo[t] = lo;
  s_hi[t] = hi;
  s_count[t] = count;
  barrier();
  for (uint half_size = 128u; half_size > 0u; half_size >>= 1) {
    if (t < half_size) {
      s_lo[t] = min(s_lo[t], s_lo[t + half_size]);
      s_hi[t] = max(s_hi[t], s_hi[t + half_size]);
      s_count[t] += s_count[t + half_size];
    }
    barrier();
  }
  if (t == 0u) {
    box[0] = vec4(s_lo[0], s_count[0] > 0u ? 1.0 : 0.0);
    box[1] = vec4(s_hi[0], 0.0);
  }
}
)";

}  // namespace maille::render::shaders
