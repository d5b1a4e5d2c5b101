// WebGL2 drawing of a Maille scene: cloth surfaces lit from two sides, links as lines, masses
// as points, obstacles as translucent solids; an orbit camera. Positions come from the engine's
// Float64Array view each frame (converted to float32 for the GPU).

const VS_SURFACE = `#version 300 es
layout(location=0) in vec3 p; layout(location=1) in vec3 n;
uniform mat4 viewProj; uniform mat3 direct; uniform vec3 translation;
out vec3 vN; out vec3 vP;
void main() { vec3 w = direct * p + translation; vP = w; vN = direct * n;
  gl_Position = viewProj * vec4(w, 1.0); }`;
const FS_SURFACE = `#version 300 es
precision highp float;
in vec3 vN; in vec3 vP; uniform vec3 eye; uniform vec4 front; uniform vec4 back;
out vec4 colour;
void main() {
  vec3 v = normalize(eye - vP);
  vec3 n = length(vN) > 0.0 ? normalize(vN) : v;
  bool facing = dot(n, v) >= 0.0; if (!facing) n = -n;
  vec4 base = facing ? front : back;
  vec3 l1 = normalize(vec3(0.4, 1.0, 0.6)), l2 = normalize(vec3(-0.6, 0.3, -0.5));
  float d = 0.25 + 0.65 * max(dot(n, l1), 0.0) + 0.25 * max(dot(n, l2), 0.0);
  float s = pow(max(dot(n, normalize(l1 + v)), 0.0), 32.0) * 0.25;
  colour = vec4(base.rgb * d + s, base.a);
}`;
// The smooth surface (include/maille/smooth_surface.hpp), evaluated in the vertex shader from
// the shared math include/maille/detail/smooth_math.glsl, pasted between this head and main as
// the native renderer pastes it into its compute shader (src/render/smooth_shader.hpp). WebGL2
// has no compute shaders nor storage buffers, so what that shader reads from buffers comes from
// textures here (positions and vertex normals as RGB32F, grids and PN triangles as RGBA32UI,
// fetched with texelFetch), and each vertex of the smooth mesh is evaluated where it is drawn
// (gl_VertexID is its index in the smooth mesh) instead of into a vertex buffer first. Its main
// is the compute shader's, line for line, but for those reads and its output.
const TEX_W = 1024;  // texels per row of the data textures
const VS_SMOOTH_HEAD = `#version 300 es
precision highp float; precision highp int; precision highp sampler2D; precision highp usampler2D;
uniform sampler2D u_positions; uniform sampler2D u_normals;
uniform usampler2D u_grids; uniform usampler2D u_tris;
uniform int u_lod; uniform int u_grid_count; uniform uint u_grid_vertices;
uniform mat4 viewProj;
out vec3 vN; out vec3 vP;
#define MAILLE_SHARED
#define MAILLE_OUT(T) out T
`;
const VS_SMOOTH_MAIN = `
ivec2 texel(uint k) { return ivec2(int(k) % ${TEX_W}, int(k) / ${TEX_W}); }
vec3 point_at(uint k) { return texelFetch(u_positions, texel(k), 0).xyz; }
vec3 normal_at(uint k) { return texelFetch(u_normals, texel(k), 0).xyz; }
struct Grid { uint first; uint nx; uint ny; uint offset; };
Grid grid_at(int i) { uvec4 g = texelFetch(u_grids, ivec2(i, 0), 0); return Grid(g.x, g.y, g.z, g.w); }
// Control point (c, d) of a grid, extrapolated linearly beyond its border (as on the CPU).
vec3 fetch(Grid g, int c, int d) { return point_at(g.first + uint(d * int(g.nx) + c)); }
vec3 column(Grid g, int c, int d) {
  int ny = int(g.ny);
  if (d < 0) return fetch(g, c, 0) * 2.0f - fetch(g, c, 1);
  if (d >= ny) return fetch(g, c, ny - 1) * 2.0f - fetch(g, c, ny - 2);
  return fetch(g, c, d);
}
vec3 control(Grid g, int a, int b) {
  int nx = int(g.nx);
  if (a < 0) return column(g, 0, b) * 2.0f - column(g, 1, b);
  if (a >= nx) return column(g, nx - 1, b) * 2.0f - column(g, nx - 2, b);
  return column(g, a, b);
}
void main() {
  uint id = uint(gl_VertexID);
  vec3 s, t1, t2;
  float step = 1.0f / float(u_lod);
  uint lod = uint(u_lod);
  if (id < u_grid_vertices) {
    int gi = 0;
    while (gi + 1 < u_grid_count && grid_at(gi + 1).offset <= id) ++gi;
    Grid g = grid_at(gi);
    uint local = id - g.offset;
    uint cols = lod * (g.nx - 1u) + 1u;
    uint a = local % cols, b = local / cols;
    uint i = min(a / lod, g.nx - 2u), j = min(b / lod, g.ny - 2u);
    float u = float(a - i * lod) * step, v = float(b - j * lod) * step;
    vec3 p[16];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) p[4 * r + c] = control(g, int(i) - 1 + c, int(j) - 1 + r);
    cr_patch(p, u, v, s, t1, t2);
  } else {
    uint per = uint((u_lod + 1) * (u_lod + 2) / 2);
    uint k = id - u_grid_vertices;
    uint t = k / per;
    int local = int(k % per), j = 0;
    while (local > u_lod - j) { local -= u_lod + 1 - j; ++j; }
    uvec4 c = texelFetch(u_tris, texel(t), 0);
    pn_triangle(point_at(c.x), point_at(c.y), point_at(c.z), normal_at(c.x), normal_at(c.y),
                normal_at(c.z), float(local) * step, float(j) * step, s, t1, t2);
  }
  vec3 n = unit_normal(t1, t2);
  vP = s; vN = n;
  gl_Position = viewProj * vec4(s, 1.0);
}`;
const FS_PLAIN = `#version 300 es
precision highp float; out vec4 colour; void main() { colour = vec4(1.0); }`;

const VS_FLAT = `#version 300 es
layout(location=0) in vec3 p; layout(location=2) in float style;
uniform mat4 viewProj; uniform float pointScale; flat out int vStyle;
void main() { gl_Position = viewProj * vec4(p, 1.0); vStyle = int(style);
  gl_PointSize = style < 0.5 ? 0.0 : clamp(pointScale / gl_Position.w, 2.0, 24.0); }`;
const FS_FLAT = `#version 300 es
precision highp float; flat in int vStyle; uniform vec4 tint; uniform bool points; out vec4 colour;
void main() {
  if (points) {
    if (vStyle == 0) discard;  // a point of a cloth surface: the surface shows it
    vec2 c = gl_PointCoord * 2.0 - 1.0; if (dot(c, c) > 1.0) discard;
    vec3 base = vStyle == 2 ? vec3(0.85, 0.25, 0.25) : vStyle == 3 ? vec3(0.95, 0.8, 0.2) : vec3(0.85, 0.9, 0.95);
    colour = vec4(base * (1.0 - 0.35 * dot(c, c)), 1.0);
  } else colour = tint;
}`;

function compile(gl, vs, fs, feedback = null) {
  const prog = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const sh = gl.createShader(type);
    gl.shaderSource(sh, src); gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    gl.attachShader(prog, sh);
  }
  if (feedback) gl.transformFeedbackVaryings(prog, feedback, gl.INTERLEAVED_ATTRIBS);
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  const u = {};
  for (let i = 0; i < gl.getProgramParameter(prog, gl.ACTIVE_UNIFORMS); ++i) {
    const name = gl.getActiveUniform(prog, i).name;
    u[name] = gl.getUniformLocation(prog, name);
  }
  return { prog, u };
}

// Column-major 4x4 matrices.
function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
}
function lookAt(e, t, up) {
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const norm = (a) => { const l = Math.hypot(...a) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const z = norm(sub(e, t)), x = norm(cross(up, z)), y = cross(z, x);
  return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, -dot(x, e), -dot(y, e), -dot(z, e), 1];
}
function mul(a, b) {
  const o = new Array(16).fill(0);
  for (let c = 0; c < 4; ++c) for (let r = 0; r < 4; ++r)
    for (let k = 0; k < 4; ++k) o[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return o;
}
function invert(m) {  // general 4x4 inverse (column-major)
  const inv = new Array(16), a = m;
  inv[0] = a[5]*a[10]*a[15]-a[5]*a[11]*a[14]-a[9]*a[6]*a[15]+a[9]*a[7]*a[14]+a[13]*a[6]*a[11]-a[13]*a[7]*a[10];
  inv[4] = -a[4]*a[10]*a[15]+a[4]*a[11]*a[14]+a[8]*a[6]*a[15]-a[8]*a[7]*a[14]-a[12]*a[6]*a[11]+a[12]*a[7]*a[10];
  inv[8] = a[4]*a[9]*a[15]-a[4]*a[11]*a[13]-a[8]*a[5]*a[15]+a[8]*a[7]*a[13]+a[12]*a[5]*a[11]-a[12]*a[7]*a[9];
  inv[12] = -a[4]*a[9]*a[14]+a[4]*a[10]*a[13]+a[8]*a[5]*a[14]-a[8]*a[6]*a[13]-a[12]*a[5]*a[10]+a[12]*a[6]*a[9];
  inv[1] = -a[1]*a[10]*a[15]+a[1]*a[11]*a[14]+a[9]*a[2]*a[15]-a[9]*a[3]*a[14]-a[13]*a[2]*a[11]+a[13]*a[3]*a[10];
  inv[5] = a[0]*a[10]*a[15]-a[0]*a[11]*a[14]-a[8]*a[2]*a[15]+a[8]*a[3]*a[14]+a[12]*a[2]*a[11]-a[12]*a[3]*a[10];
  inv[9] = -a[0]*a[9]*a[15]+a[0]*a[11]*a[13]+a[8]*a[1]*a[15]-a[8]*a[3]*a[13]-a[12]*a[1]*a[11]+a[12]*a[3]*a[9];
  inv[13] = a[0]*a[9]*a[14]-a[0]*a[10]*a[13]-a[8]*a[1]*a[14]+a[8]*a[2]*a[13]+a[12]*a[1]*a[10]-a[12]*a[2]*a[9];
  inv[2] = a[1]*a[6]*a[15]-a[1]*a[7]*a[14]-a[5]*a[2]*a[15]+a[5]*a[3]*a[14]+a[13]*a[2]*a[7]-a[13]*a[3]*a[6];
  inv[6] = -a[0]*a[6]*a[15]+a[0]*a[7]*a[14]+a[4]*a[2]*a[15]-a[4]*a[3]*a[14]-a[12]*a[2]*a[7]+a[12]*a[3]*a[6];
  inv[10] = a[0]*a[5]*a[15]-a[0]*a[7]*a[13]-a[4]*a[1]*a[15]+a[4]*a[3]*a[13]+a[12]*a[1]*a[7]-a[12]*a[3]*a[5];
  inv[14] = -a[0]*a[5]*a[14]+a[0]*a[6]*a[13]+a[4]*a[1]*a[14]-a[4]*a[2]*a[13]-a[12]*a[1]*a[6]+a[12]*a[2]*a[5];
  inv[3] = -a[1]*a[6]*a[11]+a[1]*a[7]*a[10]+a[5]*a[2]*a[11]-a[5]*a[3]*a[10]-a[9]*a[2]*a[7]+a[9]*a[3]*a[6];
  inv[7] = a[0]*a[6]*a[11]-a[0]*a[7]*a[10]-a[4]*a[2]*a[11]+a[4]*a[3]*a[10]+a[8]*a[2]*a[7]-a[8]*a[3]*a[6];
  inv[11] = -a[0]*a[5]*a[11]+a[0]*a[7]*a[9]+a[4]*a[1]*a[11]-a[4]*a[3]*a[9]-a[8]*a[1]*a[7]+a[8]*a[3]*a[5];
  inv[15] = a[0]*a[5]*a[10]-a[0]*a[6]*a[9]-a[4]*a[1]*a[10]+a[4]*a[2]*a[9]+a[8]*a[1]*a[6]-a[8]*a[2]*a[5];
  const det = a[0] * inv[0] + a[1] * inv[4] + a[2] * inv[8] + a[3] * inv[12];
  return inv.map((v) => v / det);
}

export class OrbitCamera {
  constructor() { this.target = [0, 0, 0]; this.distance = 3; this.azimuth = 0.6; this.elevation = 0.35; }
  // Looks at the bounding box of the cloth's points (style 0: on a surface) when there is a
  // cloth, else of every point: a flag, not its pole, fills the view.
  // Obstacles no larger than a few times that box are added to it (a ball under a cloth, not
  // the ground plane).
  frame(positions, styles, solids = []) {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    const cloth = styles && styles.some((s) => s === 0);
    for (let i = 0; i < positions.length; i += 3) {
      if (cloth && styles[i / 3] !== 0) continue;
      for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], positions[i + k]); hi[k] = Math.max(hi[k], positions[i + k]); }
    }
    const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.1);
    for (const solid of solids) {
      const v = solid.vertices, m = solid.placement;
      const slo = [Infinity, Infinity, Infinity], shi = [-Infinity, -Infinity, -Infinity];
      for (let i = 0; i < v.length; i += 6)
        for (let r = 0; r < 3; ++r) {
          const w = m[3 * r] * v[i] + m[3 * r + 1] * v[i + 1] + m[3 * r + 2] * v[i + 2] + m[9 + r];
          slo[r] = Math.min(slo[r], w); shi[r] = Math.max(shi[r], w);
        }
      if (Math.max(shi[0] - slo[0], shi[1] - slo[1], shi[2] - slo[2]) > 3 * size) continue;
      for (let k = 0; k < 3; ++k) { lo[k] = Math.min(lo[k], slo[k]); hi[k] = Math.max(hi[k], shi[k]); }
    }
    if (!(lo[0] <= hi[0])) return;
    this.target = [0, 1, 2].map((k) => (lo[k] + hi[k]) / 2);
    this.distance = Math.max(0.5, 1.0 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
  }
  eye() {
    const c = Math.cos(this.elevation);
    return [this.target[0] + this.distance * c * Math.sin(this.azimuth),
            this.target[1] + this.distance * Math.sin(this.elevation),
            this.target[2] + this.distance * c * Math.cos(this.azimuth)];
  }
  viewProj(aspect) {
    return mul(perspective(Math.PI / 4, aspect, this.distance / 100, this.distance * 50),
               lookAt(this.eye(), this.target, [0, 1, 0]));
  }
}

export class Renderer {
  constructor(canvas) {
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL2 is not available in this browser');
    this.gl = gl; this.canvas = canvas; this.camera = new OrbitCamera();
    this.surface = compile(gl, VS_SURFACE, FS_SURFACE);
    this.flat = compile(gl, VS_FLAT, FS_FLAT);
    this.pos = gl.createBuffer(); this.nrm = gl.createBuffer(); this.sty = gl.createBuffer();
    this.tri = gl.createBuffer(); this.lin = gl.createBuffer();
    this.solidBuffers = new Map();
    this.f32 = new Float32Array(0);
  }
  // The shared smooth-surface math (smooth_math.glsl's text): compiles the smooth programs, the
  // drawing one and one that writes the evaluated vertices back (transform feedback: the test's
  // comparison with the engine's CPU evaluation). False, with the reason in smoothError, when
  // this WebGL2 cannot compile it.
  setSmoothMath(glsl) {
    const gl = this.gl;
    try {
      this.smoothProg = compile(gl, VS_SMOOTH_HEAD + glsl + VS_SMOOTH_MAIN, FS_SURFACE);
      this.smoothFeedbackProg = compile(gl, VS_SMOOTH_HEAD + glsl + VS_SMOOTH_MAIN, FS_PLAIN, ['vP', 'vN']);
    } catch (e) {
      this.smoothError = String(e.message || e);
      return false;
    }
    const tex = () => {
      const t = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, t);
      for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
      return t;
    };
    this.smoothTex = { positions: tex(), normals: tex(), grids: tex(), tris: tex() };
    this.smoothIdx = gl.createBuffer();
    this.smoothVao = gl.createVertexArray();
    return true;
  }
  // The smooth layout of the scene (engine.smoothLayout(lod)); null: none.
  setSmooth(layout) {
    this.smoothLayout = layout && layout.vertexCount > 0 ? layout : null;
    if (!this.smoothLayout || !this.smoothProg) return;
    const gl = this.gl, L = this.smoothLayout;
    const upload = (t, w, h, internal, format, type, data) => {
      gl.bindTexture(gl.TEXTURE_2D, t);
      gl.texImage2D(gl.TEXTURE_2D, 0, internal, w, h, 0, format, type, data);
    };
    const grids = L.grids.length ? L.grids : new Uint32Array(4);
    upload(this.smoothTex.grids, grids.length / 4, 1, gl.RGBA32UI, gl.RGBA_INTEGER, gl.UNSIGNED_INT, grids);
    const nt = Math.max(1, L.pnTriangles.length / 3), h = Math.ceil(nt / TEX_W);
    const tris = new Uint32Array(TEX_W * h * 4);
    for (let t = 0; t < L.pnTriangles.length / 3; ++t)
      for (let k = 0; k < 3; ++k) tris[4 * t + k] = L.pnTriangles[3 * t + k];
    upload(this.smoothTex.tris, TEX_W, h, gl.RGBA32UI, gl.RGBA_INTEGER, gl.UNSIGNED_INT, tris);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.smoothIdx);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, L.triangles, gl.STATIC_DRAW);
    this.smoothTriangles = L.triangles.length;
  }
  // Positions (and, for PN triangles, the vertex normals) into the smooth programs' textures.
  uploadSmoothInputs(positions32, normals) {
    const gl = this.gl, n = positions32.length / 3, h = Math.max(1, Math.ceil(n / TEX_W));
    if (!this.smoothData || this.smoothData.length !== TEX_W * h * 3) this.smoothData = new Float32Array(TEX_W * h * 3);
    this.smoothData.set(positions32);
    gl.bindTexture(gl.TEXTURE_2D, this.smoothTex.positions);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, TEX_W, h, 0, gl.RGB, gl.FLOAT, this.smoothData);
    if (this.smoothLayout.pnTriangles.length && normals) {
      this.smoothData.fill(0); this.smoothData.set(normals);
      gl.bindTexture(gl.TEXTURE_2D, this.smoothTex.normals);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGB32F, TEX_W, h, 0, gl.RGB, gl.FLOAT, this.smoothData);
    }
  }
  bindSmooth(p) {
    const gl = this.gl, L = this.smoothLayout;
    gl.useProgram(p.prog);
    [this.smoothTex.positions, this.smoothTex.normals, this.smoothTex.grids, this.smoothTex.tris].forEach((t, i) => {
      gl.activeTexture(gl.TEXTURE0 + i); gl.bindTexture(gl.TEXTURE_2D, t);
    });
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform1i(p.u.u_positions, 0); gl.uniform1i(p.u.u_normals, 1);
    gl.uniform1i(p.u.u_grids, 2); gl.uniform1i(p.u.u_tris, 3);
    gl.uniform1i(p.u.u_lod, L.lod); gl.uniform1i(p.u.u_grid_count, L.grids.length / 4);
    gl.uniform1ui(p.u.u_grid_vertices, L.gridVertices);
  }
  // The smooth mesh's vertices as the shader evaluates them (6 floats each: position, normal),
  // read back through transform feedback: what the test compares with the CPU's evaluation.
  smoothFeedback(positions, normals) {
    const gl = this.gl, L = this.smoothLayout;
    if (!L || !this.smoothFeedbackProg) return null;
    this.uploadSmoothInputs(Float32Array.from(positions), normals);
    const p = this.smoothFeedbackProg;
    this.bindSmooth(p);
    if (p.u.viewProj) gl.uniformMatrix4fv(p.u.viewProj, false, [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.TRANSFORM_FEEDBACK_BUFFER, buf);
    gl.bufferData(gl.TRANSFORM_FEEDBACK_BUFFER, L.vertexCount * 24, gl.STREAM_READ);
    const tf = gl.createTransformFeedback();
    gl.bindTransformFeedback(gl.TRANSFORM_FEEDBACK, tf);
    gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, buf);
    gl.bindVertexArray(this.smoothVao);
    gl.enable(gl.RASTERIZER_DISCARD);
    gl.beginTransformFeedback(gl.POINTS);
    gl.drawArrays(gl.POINTS, 0, L.vertexCount);
    gl.endTransformFeedback();
    gl.disable(gl.RASTERIZER_DISCARD);
    gl.bindVertexArray(null);
    gl.bindTransformFeedback(gl.TRANSFORM_FEEDBACK, null);
    gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, null);
    const out = new Float32Array(L.vertexCount * 6);
    gl.bindBuffer(gl.TRANSFORM_FEEDBACK_BUFFER, buf);
    gl.getBufferSubData(gl.TRANSFORM_FEEDBACK_BUFFER, 0, out);
    gl.bindBuffer(gl.TRANSFORM_FEEDBACK_BUFFER, null);
    gl.deleteBuffer(buf); gl.deleteTransformFeedback(tf);
    return out;
  }
  setTopology(topo) {
    const gl = this.gl;
    this.triangleCount = topo.triangles.length;
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.tri);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(topo.triangles), gl.STATIC_DRAW);
    const lines = [];  // links not on a cloth surface (the surface shows those)
    for (let i = 0; i < topo.linkOnSurface.length; ++i)
      if (!topo.linkOnSurface[i]) lines.push(topo.links[2 * i], topo.links[2 * i + 1]);
    this.lineCount = lines.length;
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.lin);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(lines), gl.STATIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.sty);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(topo.pointStyle), gl.STATIC_DRAW);
    this.pointCount = topo.pointStyle.length;
    this.pointRadius = topo.pointRadius;
    this.styles = Uint32Array.from(topo.pointStyle);
  }
  draw(positions, normals, solids, smoothNormals = null) {
    const gl = this.gl, c = this.canvas;
    const w = c.clientWidth | 0, h = c.clientHeight | 0;
    if (w > 0 && (c.width !== w || c.height !== h)) { c.width = w; c.height = h; }
    gl.viewport(0, 0, c.width, c.height);
    gl.clearColor(0.23, 0.26, 0.31, 1); gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    if (this.f32.length !== positions.length) this.f32 = new Float32Array(positions.length);
    this.f32.set(positions);
    const vp = this.viewProj = this.camera.viewProj(c.width / c.height);
    const eye = this.camera.eye();
    gl.bindBuffer(gl.ARRAY_BUFFER, this.pos); gl.bufferData(gl.ARRAY_BUFFER, this.f32, gl.DYNAMIC_DRAW);
    gl.enableVertexAttribArray(0); gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    const s = this.surface;
    gl.useProgram(s.prog);
    gl.uniformMatrix4fv(s.u.viewProj, false, vp);
    gl.uniformMatrix3fv(s.u.direct, false, [1, 0, 0, 0, 1, 0, 0, 0, 1]);
    gl.uniform3f(s.u.translation, 0, 0, 0);
    gl.uniform3fv(s.u.eye, eye);
    if (this.smooth && this.smoothLayout && this.smoothProg) {
      // The cloth as the smooth surface (the physical mesh's triangles are not drawn).
      this.uploadSmoothInputs(this.f32, smoothNormals);
      const sp = this.smoothProg;
      this.bindSmooth(sp);
      gl.uniformMatrix4fv(sp.u.viewProj, false, vp);
      gl.uniform3fv(sp.u.eye, eye);
      gl.uniform4f(sp.u.front, 0.88, 0.45, 0.2, 1); gl.uniform4f(sp.u.back, 0.72, 0.33, 0.16, 1);
      gl.disableVertexAttribArray(0);
      gl.bindVertexArray(this.smoothVao);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.smoothIdx);
      gl.drawElements(gl.TRIANGLES, this.smoothTriangles, gl.UNSIGNED_INT, 0);
      gl.bindVertexArray(null);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.pos);
      gl.enableVertexAttribArray(0); gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
      gl.useProgram(s.prog);
    } else if (this.triangleCount > 0) {
      gl.bindBuffer(gl.ARRAY_BUFFER, this.nrm); gl.bufferData(gl.ARRAY_BUFFER, normals, gl.DYNAMIC_DRAW);
      gl.enableVertexAttribArray(1); gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, 0);
      gl.uniform4f(s.u.front, 0.88, 0.45, 0.2, 1); gl.uniform4f(s.u.back, 0.72, 0.33, 0.16, 1);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.tri);
      gl.drawElements(gl.TRIANGLES, this.triangleCount, gl.UNSIGNED_INT, 0);
      gl.disableVertexAttribArray(1);
    }
    const f = this.flat;
    gl.useProgram(f.prog);
    gl.uniformMatrix4fv(f.u.viewProj, false, vp);
    gl.uniform1f(f.u.pointScale, this.pointRadius * c.height * 2.4);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.sty);
    gl.enableVertexAttribArray(2); gl.vertexAttribPointer(2, 1, gl.FLOAT, false, 0, 0);
    if (this.lineCount > 0) {
      gl.uniform1i(f.u.points, 0); gl.uniform4f(f.u.tint, 0.75, 0.8, 0.85, 1);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.lin);
      gl.drawElements(gl.LINES, this.lineCount, gl.UNSIGNED_INT, 0);
    }
    gl.uniform1i(f.u.points, 1);
    gl.drawArrays(gl.POINTS, 0, this.pointCount);
    gl.disableVertexAttribArray(2);
    // Obstacles last, translucent, without writing depth.
    gl.useProgram(s.prog);
    // Pushed back a little in depth: a cloth resting on an obstacle lies within millimetres of
    // its surface, and would otherwise show the solid through it in specks.
    gl.enable(gl.BLEND); gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA); gl.depthMask(false);
    gl.enable(gl.POLYGON_OFFSET_FILL); gl.polygonOffset(4, 16);
    for (const solid of solids) this.drawSolid(solid);
    gl.disable(gl.POLYGON_OFFSET_FILL);
    gl.depthMask(true); gl.disable(gl.BLEND);
  }
  drawSolid(solid) {
    const gl = this.gl, s = this.surface;
    let b = this.solidBuffers.get(solid.name);
    if (!b || b.count !== solid.vertices.length / 6) {
      b = { buf: b ? b.buf : gl.createBuffer(), count: solid.vertices.length / 6 };
      gl.bindBuffer(gl.ARRAY_BUFFER, b.buf);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(solid.vertices), gl.STATIC_DRAW);
      this.solidBuffers.set(solid.name, b);
    }
    const m = solid.placement;  // row-major 3x3, then translation
    gl.uniformMatrix3fv(s.u.direct, false, [m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]]);
    gl.uniform3f(s.u.translation, m[9], m[10], m[11]);
    const c = solid.colour;
    gl.uniform4f(s.u.front, c[0], c[1], c[2], Math.max(c[3], 0.35));
    gl.uniform4f(s.u.back, c[0], c[1], c[2], Math.max(c[3], 0.35));
    gl.bindBuffer(gl.ARRAY_BUFFER, b.buf);
    gl.enableVertexAttribArray(0); gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 24, 0);
    gl.enableVertexAttribArray(1); gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 24, 12);
    gl.drawArrays(gl.TRIANGLES, 0, b.count);
    gl.disableVertexAttribArray(1);
  }
  // The free point drawn nearest to canvas pixel (x, y), within `radius` pixels, or -1.
  pick(positions, x, y, radius = 16) {
    const vp = this.viewProj, c = this.canvas;
    let best = -1, bestD = radius * radius, bestW = Infinity;
    for (let i = 0; i < positions.length / 3; ++i) {
      const st = this.styles[i];
      if (st === 2 || st === 3) continue;  // fixed and driven points do not follow the mouse
      const px = positions[3 * i], py = positions[3 * i + 1], pz = positions[3 * i + 2];
      const cw = vp[3] * px + vp[7] * py + vp[11] * pz + vp[15];
      if (cw <= 0) continue;
      const sx = ((vp[0] * px + vp[4] * py + vp[8] * pz + vp[12]) / cw * 0.5 + 0.5) * c.clientWidth;
      const sy = (0.5 - (vp[1] * px + vp[5] * py + vp[9] * pz + vp[13]) / cw * 0.5) * c.clientHeight;
      const d = (sx - x) ** 2 + (sy - y) ** 2;
      if (d < bestD || (d <= bestD + 4 && cw < bestW)) { best = i; bestD = d; bestW = cw; }
    }
    return best;
  }
  // The point under canvas pixel (x, y) at the depth of world point p (the plane through p
  // facing the camera): where a dragged point is pulled.
  unproject(x, y, p) {
    const vp = this.viewProj, c = this.canvas;
    const cw = vp[3] * p[0] + vp[7] * p[1] + vp[11] * p[2] + vp[15];
    const cz = vp[2] * p[0] + vp[6] * p[1] + vp[10] * p[2] + vp[14];
    const ndc = [x / c.clientWidth * 2 - 1, 1 - y / c.clientHeight * 2, cz / cw];
    const inv = invert(vp);
    const v = [0, 1, 2, 3].map((r) => inv[r] * ndc[0] + inv[4 + r] * ndc[1] + inv[8 + r] * ndc[2] + inv[12 + r]);
    return [v[0] / v[3], v[1] / v[3], v[2] / v[3]];
  }
}
