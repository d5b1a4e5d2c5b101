#version 450 core
in float v_height;
out vec4 colour;
void main() {
  colour = vec4(mix(vec3(0.60, 0.62, 0.66), vec3(0.89, 0.90, 0.92), clamp(v_height, 0.0, 1.0)), 1.0);
}
