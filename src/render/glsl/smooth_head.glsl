#version 450 core
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Positions { float xyz[]; };      // 3 per point
layout(std430, binding = 1) readonly buffer Normals { float normal_xyz[]; };  // 3 per point
struct Grid { uint first; uint nx; uint ny; uint offset; };  // SmoothSurface::Grid, 16 bytes
layout(std430, binding = 2) readonly buffer Grids { Grid grids[]; };
layout(std430, binding = 3) readonly buffer Triangles { uint tri[]; };  // 3 per PN triangle
layout(std430, binding = 4) writeonly buffer Vertices { float vout[]; };  // 6 per vertex
uniform int u_lod;
uniform int u_grid_count;
uniform uint u_grid_vertices;
uniform uint u_total;
#define MAILLE_SHARED
#define MAILLE_OUT(T) out T
