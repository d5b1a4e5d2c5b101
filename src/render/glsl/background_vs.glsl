#version 450 core
// background: one triangle covering the viewport, a vertical gradient
out float v_height;
void main() {
  vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);  // (0,0) (2,0) (0,2)
  v_height = corner.y * 0.5;
  gl_Position = vec4(corner * 2.0 - 1.0, 0.999, 1.0);
}
