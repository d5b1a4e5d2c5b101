#version 450 core
// points: sprites shaded as spheres
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
