#version 450 core
// cloth surfaces: per-vertex normals, lit on both sides
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
