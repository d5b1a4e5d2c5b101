#version 450 core
// links: 6 vertices (two triangles) per link, a screen-space ribbon of fixed pixel width
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
