#version 450 core
// solids (obstacles): a mesh in its own frame, placed by a uniform, translucent
// x_world = u_model x; normals go through the inverse transpose of the placement's linear part
// (u_normal), so a scaled sphere still shades as an ellipsoid.
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
