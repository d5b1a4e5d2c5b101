#version 450 core
// plain lines with a colour per vertex: floor grid and overlays
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
uniform mat4 u_view_proj;
out vec3 v_colour;
void main() {
  v_colour = colour;
  gl_Position = u_view_proj * vec4(position, 1.0);
}
