#version 450 core
// active contacts: the conditional links closer than their threshold, compacted into a list of
// ends and an indirect draw command (6 vertices each) for the links pass. A scene may hold
// all-pairs contact links, of which a handful are active: only those are drawn.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 1) readonly buffer Ends { uint ends[]; };            // 2 per link
layout(std430, binding = 2) readonly buffer Threshold { float threshold[]; };
layout(std430, binding = 3) writeonly buffer Active { uint active_ends[]; };       // 2 per contact
// glDrawArraysIndirect's command: vertices (6 per contact, from 0), instances (1), first, base.
layout(std430, binding = 4) buffer Command { uint vertices; uint rest_of_command[3]; };
uniform uint u_links;
vec3 point(uint i) { return vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]); }
void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= u_links) return;
  uint a = ends[2 * c], b = ends[2 * c + 1];
  if (!(length(point(b) - point(a)) < threshold[c])) return;
  uint k = atomicAdd(vertices, 6u) / 6u;
  active_ends[2 * k] = a;
  active_ends[2 * k + 1] = b;
}
