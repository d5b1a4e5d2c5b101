#version 450 core
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
