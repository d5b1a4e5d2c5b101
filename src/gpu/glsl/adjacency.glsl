// A point's links as its adjacency row lists them, read alike by forces.glsl and vbd_sweep.glsl
// (pasted before their bodies, after the buffers x, v, adjacency and link_params): entry e's
// law, the other end's position and velocity, the law's parameters, and whether the point is
// the link's b end (the laws give the force on the a end: called with the ends swapped, and
// the force negated).
struct Neighbour {
  uint kind;
  bool b_end;
  vec3 x;
  vec3 v;
  vec4 p;
};
Neighbour neighbour(uint e) {
  Adjacent l = adjacency[e];
  Neighbour n;
  n.kind = l.kind & 0x7fffffffu;
  n.b_end = (l.kind & 0x80000000u) != 0u;
  n.x = LOAD3(x, l.other);
  n.v = LOAD3(v, l.other);
  n.p = LOAD_PARAMS(l.params);
  return n;
}
