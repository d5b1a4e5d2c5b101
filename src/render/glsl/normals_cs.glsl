#version 450 core
// vertex normals: per point, the area-weighted sum of the normals of its faces, normalised
// (vertex_normals in smooth_surface.cpp, in float). A gather over each point's faces (CSR), so
// no atomics; points on no face get a zero normal.
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
