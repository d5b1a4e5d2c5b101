#version 450 core
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
