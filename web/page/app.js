// The playground: the engine (maille.js / maille.wasm, built by scripts/web.sh) stepped in the
// page's frames, drawn by WebGL2 (render.js), with the examples, the scene text, the sliders,
// the stats plot and the sound. window.maille is the page's automation interface (docs/web.md).
import { Renderer } from './render.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);

// ---- the module: threaded where the page may share memory with workers ----------------------
// maille-mt.js (OpenMP on Web Workers, docs/web.md "Threads") needs SharedArrayBuffer, which a
// browser gives only to a cross-origin isolated page (served with COOP: same-origin and COEP:
// require-corp, as scripts/web.sh serve does); elsewhere, or with ?threads=1, maille.js runs
// everything on this thread. A missing maille-mt.js (MAILLE_WEB_THREADS=0) falls back too.
function loadScript(src) {
  return new Promise((resolve, reject) => {
    const s = document.createElement('script');
    s.src = src;
    s.onload = resolve;
    s.onerror = () => { s.remove(); reject(new Error(`cannot load ${src}`)); };
    document.head.append(s);
  });
}
const threadsAsked = params.has('threads') ? Math.max(1, parseInt(params.get('threads'), 10) || 1) : 0;
let threaded = self.crossOriginIsolated === true && threadsAsked !== 1;
if (threaded) await loadScript('maille-mt.js').catch(() => { threaded = false; });
if (!threaded) await loadScript('maille.js');
const Module = await createMaille();
const engine = new Module.Playground();
// Threads per step: all the module offers (the cores, at most 4) unless ?threads=N says fewer.
if (threaded) engine.setThreads(threadsAsked || Module.Playground.maxThreads());
// VBD's sweeps: the scalar sweep by default. The lanes of 2 doubles (f64x2) give the same bits
// but were slower in Chromium here (docs/web.md, "Performance"); ?lanes=2 takes them.
Module.Playground.setVbdLanes(params.has('lanes') ? +params.get('lanes') : 1);
const renderer = new Renderer($('canvas'));
// The smooth surface: the engine's shared math (include/maille/detail/smooth_math.glsl, copied
// next to the page by scripts/web.sh) compiled into the WebGL2 vertex shader (render.js). On by
// default for the scenes named smooth_*, ?smooth=1 / ?smooth=0 and the checkbox say otherwise.
const SMOOTH_LOD = 4;  // sub-segments per physical edge, as `maille render --smooth --lod 4`
const smoothReady = await fetch('smooth_math.glsl').then((r) => r.ok ? r.text() : Promise.reject(new Error(r.statusText)))
  .then((glsl) => renderer.setSmoothMath(glsl))
  .catch((e) => { renderer.smoothError = String(e.message || e); return false; });
if (!smoothReady) console.warn(`smooth surface unavailable: ${renderer.smoothError}`);

// ---- state of the page -------------------------------------------------------------------
let playing = params.get('paused') === null;
let current = null;          // {name, text, source}: the scene running now
let solids = [];
let history = [];            // stats samples for the plot
let frameTimes = [];         // ms of work (steps + drawing) per frame, the last 120 frames
let frameStamps = [];        // rAF timestamps, the last 120
let stepMs = 0, drawMs = 0;
let timing = { h: 1e-3, msPerStep: 0 };  // engine.timing(): cheap, unlike stats() (energies)
let dragging = null;         // {point, pointerId}
let orbiting = null;
let audio = null;            // {context, node}

// ---- examples ----------------------------------------------------------------------------
const examples = Module.FS.readdir('/examples')
  .filter((f) => f.endsWith('.toml')).map((f) => f.slice(0, -5)).sort();
const exampleText = (name) => Module.FS.readFile(`/examples/${name}.toml`, { encoding: 'utf8' });
const refusals = new Map();  // example name -> why the browser build refuses it
// The examples that have a picture in docs/gallery (scripts/web.sh lists them): an example
// without one gets none, rather than a request that fails.
const pictures = new Set(await fetch('gallery/index.json').then((r) => (r.ok ? r.json() : []),
  () => []));

function listExamples() {
  const nav = $('examples');
  nav.textContent = '';
  for (const name of examples) {
    const b = document.createElement('button');
    b.dataset.name = name;
    if (pictures.has(name)) {
      const img = document.createElement('img');
      img.src = `gallery/${name}.png`; img.alt = ''; img.loading = 'lazy';
      b.append(img);
    }
    const desc = (exampleText(name).match(/^description\s*=\s*"(.*)"/m) || [])[1] || '';
    b.title = desc;
    b.append(document.createTextNode(name));
    b.onclick = () => openExample(name);
    nav.append(b);
  }
}

function openExample(name) {
  const r = loadText(exampleText(name), `/examples/${name}.toml`);
  if (!r.ok) refusals.set(name, r.error.message);
  const u = new URL(location.href);
  u.searchParams.set('scene', name); u.hash = '';
  history_replace(u);
  return r;
}

function history_replace(u) { try { window.history.replaceState(null, '', u); } catch (e) { /* file: */ } }

// ---- loading -----------------------------------------------------------------------------
// A broken text shows its error and the scene running before goes on.
function loadText(text, source = '/examples/scene.toml') {
  const r = engine.load(text, source);
  showError(r.ok ? null : r.error);
  $('text').value = text; gutter();
  if (r.ok) started(text, source);
  return r;
}

function started(text, source, reframe = true) {
  const info = engine.sceneInfo();
  timing = engine.timing();
  current = { name: info.name, text, source };
  $('scene-title').textContent = `${info.name}: ${info.description}`;
  for (const b of $('examples').children) b.classList.toggle('current', b.dataset.name === info.name);
  renderer.setTopology(engine.topology());
  renderer.setSmooth(smoothReady ? engine.smoothLayout(SMOOTH_LOD) : null);
  const smoothParam = params.get('smooth');
  setSmooth(smoothParam !== null ? smoothParam !== '0' : info.name.startsWith('smooth_'));
  renderer.solidBuffers.clear();
  solids = engine.solids();
  if (reframe) renderer.camera.frame(engine.positions(), renderer.styles, solids);
  history = [];
  $('blowup').hidden = true;
  $('sound').disabled = info.listeners.length === 0;
  $('sound').title = info.listeners.length ? `hear ${info.listeners.join(', ')}` : 'the scene has no [[listen]]';
  makeSliders();
  const s = engine.stats();
  status(`${s.points} points, ${s.links} links, ${s.integrator}`);
}

function showError(e) {
  $('error').textContent = e ? e.text : '';
  errorLine = e && e.line > 0 ? e.line : 0;
  gutter();
  if (e && e.line > 0) {  // put the caret at the error
    const lines = $('text').value.split('\n');
    let at = 0;
    for (let i = 0; i < e.line - 1 && i < lines.length; ++i) at += lines[i].length + 1;
    at += Math.max(0, e.column - 1);
    $('text').setSelectionRange(at, at);
  }
}

let errorLine = 0;
function gutter() {
  const n = $('text').value.split('\n').length;
  const g = $('gutter');
  g.textContent = '';
  for (let i = 1; i <= n; ++i) {
    const s = document.createElement('span');
    s.textContent = `${i}\n`;
    if (i === errorLine) s.className = 'bad';
    g.append(s);
  }
  g.scrollTop = $('text').scrollTop;
}

function status(s) { $('status').textContent = s; }

// ---- sliders: generated from the engine's declarations of the scene's keys -------------------
// engine.sliderKeys() (web/src/playground_keys.cpp): every number and integer key the engine
// declares for the scene's tables (with the documented range, unit and doc; written in the text
// or not), then the other numbers the text writes. Each slider moves its key as
// `--set KEY=VALUE` (window.maille.set).
const structural = /(^scene\.|duration|output_every|sample_every|publish_every|resolution|seed|\.count$|segments|^audio\.)/;
// How a slider's position s in [0, 1000] maps onto a key's values.
function sliderScale(k) {
  const v = k.value;
  if (k.hi > k.lo) {
    if (k.lo >= 0 && k.hi - k.lo > 100 * Math.max(v, 0)) {
      // A wide range ([0, 1e12] for a stiffness): two decades either side of the value (of the
      // range's top / 1e6 when the value is 0) on a log scale, within the range; the left end
      // is the range's 0 when 0 is allowed.
      const c = v > 0 ? v : k.hi * 1e-6;
      const a = Math.max(c / 100, k.lo), b = Math.min(c * 100, k.hi);
      const zero = k.lo === 0 && !k.loOpen;
      return { at: (s) => (zero && s === 0) ? 0 : a * Math.pow(b / a, s / 1000),
        of: (x) => x > 0 ? 1000 * Math.log(x / a) / Math.log(b / a) : 0 };
    }
    const lo = k.loOpen ? k.lo + (k.hi - k.lo) * 1e-3 : k.lo;
    return { at: (s) => lo + (k.hi - lo) * s / 1000, of: (x) => 1000 * (x - lo) / (k.hi - lo) };
  }
  if (k.bound === 'positive' || k.bound === 'non_negative' || v > 0) {
    // One decade either side of the value (of 1 when the value is 0), on a log scale; a
    // non-negative key reaches 0 at the left end.
    const c = v > 0 ? v : 1;
    return { at: (s) => (k.bound === 'non_negative' && s === 0) ? 0 : c * Math.pow(10, (s - 500) / 500),
      of: (x) => x > 0 ? 500 + 500 * Math.log10(x / c) : 0 };
  }
  const span = Math.max(1, Math.abs(v) * 2);
  return { at: (s) => v + (s - 500) / 500 * span, of: (x) => 500 + 500 * (x - v) / span };
}
// The keys with sliders, each with the values at its slider's two ends (sliderMin, sliderMax).
function sliderList() {
  return engine.sliderKeys().filter((k) => k.declared || !(k.integer || structural.test(k.key)))
    .map((k) => {
      const scale = sliderScale(k), end = (s) => k.integer ? Math.round(scale.at(s)) : scale.at(s);
      return { ...k, sliderMin: end(0), sliderMax: end(1000) };
    });
}
function makeSliders() {
  const box = $('sliders');
  box.textContent = '';
  let group = null;
  for (const k of sliderList()) {
    const title = k.declared ? 'Declared keys' : 'Other numbers of the text';
    if (title !== group) {
      group = title;
      const h = document.createElement('div'); h.className = 'slider-group'; h.textContent = title;
      box.append(h);
    }
    const scale = sliderScale(k);
    const label = document.createElement('label'); label.textContent = k.key;
    label.title = [k.doc, k.unit && `unit: ${k.unit}`, k.range && `range: ${k.range}`,
      k.declared && !k.written && 'not written: the declared default'].filter(Boolean).join('\n') || k.key;
    if (k.declared && !k.written) label.classList.add('default');
    const input = document.createElement('input'); input.type = 'range';
    input.dataset.key = k.key;
    const out = document.createElement('output'); out.textContent = fmt(k.value) + (k.unit ? ' ' + k.unit : '');
    input.min = 0; input.max = 1000;
    input.value = Math.min(1000, Math.max(0, Math.round(scale.of(k.value))));
    const valueAt = (s) => k.integer ? Math.round(scale.at(s)) : scale.at(s);
    input.oninput = () => { out.textContent = fmt(valueAt(+input.value)) + (k.unit ? ' ' + k.unit : ''); };
    input.onchange = () => {
      const r = window.maille.set(k.key, valueAt(+input.value));
      if (!r.ok) showError(r.error);
    };
    box.append(label, input, out);
  }
}
const fmt = (x) => Math.abs(x) >= 1e4 || (Math.abs(x) < 1e-3 && x !== 0) ? x.toExponential(2) : +x.toPrecision(4) + '';

// ---- the frame loop ----------------------------------------------------------------------
function stepsPerFrame() {
  const h = timing.h || 1e-3;
  const realTime = Math.max(1, Math.round(1 / 60 / h));
  // Never more than ~12 ms of stepping per frame: slower than real time rather than frozen.
  const budget = stepMs > 0 ? Math.max(1, Math.floor(12 / stepMs)) : 1;
  return Math.min(realTime, budget);
}

let statsCountdown = 0;
function frame(stamp) {
  const t0 = performance.now();
  if (playing && current) {
    const n = stepsPerFrame();
    const done = engine.step(n);
    timing = engine.timing();
    if (done > 0) stepMs = timing.msPerStep;
    if (done < n) blewUp();
  }
  const t1 = performance.now();
  if (current) {
    if (solids.length) solids = engine.solids();
    const smoothOn = renderer.smooth && renderer.smoothLayout;
    renderer.draw(engine.positions(), smoothOn ? null : engine.normals(), solids,
      smoothOn && renderer.smoothLayout.pnTriangles.length ? engine.smoothNormals() : null);
  }
  if (audio) feedAudio(); else engine.listened();  // keep the engine's buffer empty
  const t2 = performance.now();
  drawMs = t2 - t1;
  frameTimes.push(t2 - t0); if (frameTimes.length > 120) frameTimes.shift();
  frameStamps.push(stamp); if (frameStamps.length > 120) frameStamps.shift();
  if (--statsCountdown <= 0 && current) { statsCountdown = 10; sample(); }
  requestAnimationFrame(frame);
}

function frameStats() {
  const n = frameStamps.length;
  const fps = n > 1 ? 1000 * (n - 1) / (frameStamps[n - 1] - frameStamps[0]) : 0;
  const ms = frameTimes.length ? frameTimes.reduce((a, b) => a + b, 0) / frameTimes.length : 0;
  return { fps, msPerFrame: ms, maxMsPerFrame: Math.max(0, ...frameTimes), frames: frameTimes.length,
           stepMs, drawMs, stepsPerFrame: current ? stepsPerFrame() : 0 };
}

function sample() {
  const s = engine.stats();
  history.push(s); if (history.length > 400) history.shift();
  const f = frameStats();
  $('counters').textContent =
    `t=${s.time.toFixed(3)} s  step ${s.step}  ${s.msPerStep.toFixed(3)} ms/step  ` +
    `${f.fps.toFixed(0)} fps  ${f.msPerFrame.toFixed(1)} ms/frame  ` +
    (playing ? `x${(f.stepsPerFrame * s.h * f.fps).toFixed(2)} real time` : 'paused');
  plot();
}

function plot() {
  const c = $('plot'), g = c.getContext('2d');
  const w = c.width = c.clientWidth || 960, h = c.height;
  g.clearRect(0, 0, w, h);
  if (history.length < 2) return;
  const series = [['kinetic', '#e0823a'], ['elastic', '#5fb3e6'], ['energy', '#d9d9d9'], ['msPerStep', '#9ad36a']];
  g.font = '11px monospace';
  series.forEach(([key, colour], k) => {
    const ys = history.map((s) => s[key]).filter((y) => Number.isFinite(y));
    if (ys.length < 2) return;
    const lo = Math.min(...ys), hi = Math.max(...ys), span = hi - lo || 1;
    g.strokeStyle = colour; g.beginPath();
    history.forEach((s, i) => {
      const x = i / (history.length - 1) * w, y = h - 14 - (s[key] - lo) / span * (h - 28);
      i ? g.lineTo(x, y) : g.moveTo(x, y);
    });
    g.stroke();
    g.fillStyle = colour;
    g.fillText(`${key} ${fmt(history[history.length - 1][key])}`, 6 + k * 190, 11);
  });
}

function blewUp() {
  const b = engine.stats().blowUp;
  if (!b) return;
  playing = false; $('play').textContent = 'Play';
  $('blowup').hidden = false;
  $('blowup').textContent = `Blow-up at step ${b.step} (t = ${b.time.toFixed(4)} s) in ${b.module}: paused.\n${b.message}`;
}

// ---- mouse: orbit, zoom, drag a point through the viewer's drag spring ---------------------
const canvas = $('canvas');
canvas.addEventListener('pointerdown', (e) => {
  if (!current) return;
  const r = canvas.getBoundingClientRect(), x = e.clientX - r.left, y = e.clientY - r.top;
  canvas.setPointerCapture(e.pointerId);
  const pos = engine.positions();
  const point = e.button === 0 && !e.shiftKey ? renderer.pick(pos, x, y) : -1;
  if (point >= 0) {
    const p = [pos[3 * point], pos[3 * point + 1], pos[3 * point + 2]];
    dragging = { point, depth: p };
    engine.grab(point, ...renderer.unproject(x, y, p));
  } else {
    orbiting = { x: e.clientX, y: e.clientY, pan: e.button !== 0 || e.shiftKey };
  }
});
canvas.addEventListener('pointermove', (e) => {
  const r = canvas.getBoundingClientRect(), x = e.clientX - r.left, y = e.clientY - r.top;
  if (dragging) {
    engine.moveTo(...renderer.unproject(x, y, dragging.depth));
  } else if (orbiting) {
    const dx = e.clientX - orbiting.x, dy = e.clientY - orbiting.y;
    orbiting.x = e.clientX; orbiting.y = e.clientY;
    const cam = renderer.camera;
    if (orbiting.pan) {
      const s = cam.distance / canvas.clientHeight, a = cam.azimuth;
      cam.target[0] -= (Math.cos(a) * dx) * s; cam.target[2] += (Math.sin(a) * dx) * s;
      cam.target[1] += dy * s;
    } else {
      cam.azimuth -= dx * 0.01;
      cam.elevation = Math.max(-1.5, Math.min(1.5, cam.elevation + dy * 0.01));
    }
  }
});
const endPointer = () => { if (dragging) engine.release(); dragging = null; orbiting = null; };
canvas.addEventListener('pointerup', endPointer);
canvas.addEventListener('pointercancel', endPointer);
canvas.addEventListener('wheel', (e) => {
  e.preventDefault();
  renderer.camera.distance *= Math.exp(e.deltaY * 0.001);
}, { passive: false });
canvas.addEventListener('contextmenu', (e) => e.preventDefault());

// ---- buttons -------------------------------------------------------------------------------
function setPlaying(on) { playing = on; $('play').textContent = on ? 'Pause' : 'Play'; }
$('play').onclick = () => setPlaying(!playing);
$('step').onclick = () => { setPlaying(false); if (engine.step(stepsPerFrame()) < stepsPerFrame()) blewUp(); };
$('reset').onclick = () => { engine.reset(); $('blowup').hidden = true; history = []; };
// The smooth-surface toggle (only where the scene has a surface and the shader compiled).
function setSmooth(on) {
  renderer.smooth = !!on && !!renderer.smoothLayout;
  $('smooth').checked = renderer.smooth;
  $('smooth').disabled = !renderer.smoothLayout;
  $('smooth').parentElement.title = renderer.smoothLayout
    ? 'draw cloth as the smooth surface (Catmull-Rom patches on grids, PN triangles elsewhere)'
    : smoothReady ? 'the scene has no surface to smooth' : `unavailable: ${renderer.smoothError}`;
}
$('smooth').onchange = () => setSmooth($('smooth').checked);
// Threads: a choice of 1 to the module's maximum (only 1 in the one-thread module).
function showThreads() {
  const sel = $('threads');
  const max = threaded ? Module.Playground.maxThreads() : 1;
  if (sel.options.length !== max) {
    sel.textContent = '';
    for (let n = 1; n <= max; ++n) sel.append(new Option(String(n), String(n)));
  }
  sel.value = String(engine.threads());
  sel.disabled = !threaded;
  $('threads-box').title = threaded ? 'threads per step (OpenMP on Web Workers)'
    : 'one thread: the page is not cross-origin isolated (scripts/web.sh serve sends the headers)';
}
$('threads').onchange = () => { engine.setThreads(+$('threads').value); showThreads(); };
showThreads();
$('run').onclick = () => loadText($('text').value, current ? current.source : undefined);
$('text').addEventListener('keydown', (e) => {
  if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) { e.preventDefault(); $('run').click(); }
});
$('text').addEventListener('input', gutter);
$('text').addEventListener('scroll', () => { $('gutter').scrollTop = $('text').scrollTop; });
document.addEventListener('keydown', (e) => {
  if (e.key === ' ' && e.target === document.body) { e.preventDefault(); $('play').click(); }
});
$('share').onclick = async () => {
  const u = new URL(location.href);
  u.search = ''; u.hash = await compress($('text').value);
  history_replace(u);
  try { await navigator.clipboard.writeText(u.href); status('link copied'); } catch (e) { status('link in the address bar'); }
};
$('sound').onclick = () => toggleSound();

// ---- sharing: the scene text deflated (CompressionStream), base64url, after '#' ------------
async function compress(text) {
  const s = new Blob([text]).stream().pipeThrough(new CompressionStream('deflate-raw'));
  const bytes = new Uint8Array(await new Response(s).arrayBuffer());
  let bin = '';
  for (const b of bytes) bin += String.fromCharCode(b);
  return btoa(bin).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}
async function decompress(code) {
  const b64 = code.replace(/-/g, '+').replace(/_/g, '/');
  const bin = atob(b64 + '='.repeat((4 - b64.length % 4) % 4));
  const bytes = Uint8Array.from(bin, (c) => c.charCodeAt(0));
  const s = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate-raw'));
  return await new Response(s).text();
}

// ---- sound: the listened channels through an AudioWorklet ----------------------------------
async function toggleSound() {
  if (audio) { await audio.context.close(); audio = null; $('sound').textContent = 'Sound'; return; }
  // The context runs at the scene's [audio] rate: the engine's samples are played one for one.
  const rate = engine.listened().rate || 44100;
  const context = new AudioContext({ sampleRate: rate });
  await context.audioWorklet.addModule('audio-worklet.js');
  const node = new AudioWorkletNode(context, 'maille-listen', { outputChannelCount: [2] });
  node.connect(context.destination);
  audio = { context, node };
  engine.listened();  // start from now
  $('sound').textContent = 'Mute';
}
function feedAudio() {
  const l = engine.listened();
  if (l.channels > 0 && l.samples.length > 0)
    audio.node.port.postMessage({ samples: l.samples, channels: l.channels }, [l.samples.buffer]);
}

// ---- window.maille: the automation interface (docs/web.md) ---------------------------------
const tomlValue = (v) => typeof v === 'string' ? v : Array.isArray(v) ? JSON.stringify(v) : String(v);
window.maille = {
  load(text) {
    const r = loadText(text);
    return { ok: r.ok, error: r.ok ? null : { line: r.error.line, column: r.error.column,
      key: r.error.key, message: r.error.message, text: r.error.text } };
  },
  step(n = 1) {
    const done = engine.step(n);
    if (done < n) blewUp();
    return done;
  },
  positions: () => engine.positions(),
  stateHash: () => engine.stateHash(),
  set(key, value) {
    const r = engine.set(key, tomlValue(value));
    if (r.ok) started(current.text, current.source, false); else showError(r.error);
    return { ok: r.ok, error: r.ok ? null : { line: r.error.line, column: r.error.column,
      key: r.error.key, message: r.error.message, text: r.error.text } };
  },
  stats: () => Object.assign(engine.stats(), { frame: frameStats() }),
  // Beyond the list, for tests and for the console.
  examples: () => examples.slice(),
  exampleText,
  open: (name) => { const r = openExample(name); return { ok: r.ok, error: r.ok ? null : r.error }; },
  refused: () => Object.fromEntries(refusals),
  play: () => setPlaying(true),
  pause: () => setPlaying(false),
  reset: () => $('reset').click(),
  frameStats,
  dragged: () => dragging ? dragging.point : -1,
  // Where point i is drawn, in CSS pixels from the canvas's top-left corner (after a frame).
  project(i) {
    const vp = renderer.viewProj, p = engine.positions(), c = renderer.canvas;
    const x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
    const w = vp[3] * x + vp[7] * y + vp[11] * z + vp[15];
    return [((vp[0] * x + vp[4] * y + vp[8] * z + vp[12]) / w * 0.5 + 0.5) * c.clientWidth,
            (0.5 - (vp[1] * x + vp[5] * y + vp[9] * z + vp[13]) / w * 0.5) * c.clientHeight];
  },
  // Canvas pixels in the middle fifth of the canvas that have the cloth's colour (orange-red
  // front, lit), and the number of pixels looked at.
  clothPixels() {
    const c = renderer.canvas, g = document.createElement('canvas');
    g.width = c.width; g.height = c.height;
    const ctx = g.getContext('2d'); ctx.drawImage(c, 0, 0);
    const x0 = Math.floor(c.width * 0.4), y0 = Math.floor(c.height * 0.4);
    const d = ctx.getImageData(x0, y0, Math.floor(c.width * 0.2), Math.floor(c.height * 0.2)).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] > 90 && d[i] > d[i + 1] + 30 && d[i] > d[i + 2] + 45) ++n;
    return { cloth: n, total: d.length / 4 };
  },
  text: () => current ? current.text : '',
  // The listened channels since the last call (the frame loop takes them each frame): {channels,
  // rate (the scene's [audio] rate), sampling (exact / resampled), samples (interleaved
  // Float32Array, before any gain, as `maille run --audio` computes them)}; and the sound's
  // AudioContext state.
  listened: () => engine.listened(),
  // The smooth surface: whether it is drawn (on = true/false sets it), and the shader's
  // evaluation of every smooth vertex against the engine's CPU evaluation (SmoothSurface::
  // evaluate, the native renderer's oracle): largest differences of position (m) and normal.
  smooth(on) { if (on !== undefined) setSmooth(on); return renderer.smooth; },
  smoothCheck() {
    if (!renderer.smoothLayout) return { available: !!smoothReady, error: renderer.smoothError || null, vertices: 0 };
    const L = renderer.smoothLayout;
    const gpu = renderer.smoothFeedback(engine.positions(), L.pnTriangles.length ? engine.smoothNormals() : null);
    const cpu = engine.smoothEvaluate(L.lod);
    let dp = 0, dn = 0, extent = 0;
    for (let i = 0; i < cpu.length; i += 6)
      for (let k = 0; k < 3; ++k) {
        dp = Math.max(dp, Math.abs(gpu[i + k] - cpu[i + k]));
        dn = Math.max(dn, Math.abs(gpu[i + 3 + k] - cpu[i + 3 + k]));
        extent = Math.max(extent, Math.abs(cpu[i + k]));
      }
    return { available: true, vertices: cpu.length / 6, gpuVertices: gpu.length / 6, lod: L.lod,
      grids: L.grids.length / 4, pnTriangles: L.pnTriangles.length / 3, positionDiff: dp, normalDiff: dn, extent };
  },
  // FNV-1a 64 of a Float32Array's bytes (little-endian), as hex: the tests' hash of samples.
  fnv1a(samples) {
    const bytes = new Uint8Array(samples.buffer, samples.byteOffset, samples.byteLength);
    let h = 0xcbf29ce484222325n;
    for (const b of bytes) h = BigInt.asUintN(64, (h ^ BigInt(b)) * 0x100000001b3n);
    return h.toString(16).padStart(16, '0');
  },
  // Threads: whether the threaded module runs (cross-origin isolated page), the threads per
  // step now, and a new count (the run goes on from its state; 1 in the one-thread module).
  threaded,
  threads: () => engine.threads(),
  // VBD's lanes (2: f64x2, 1: the scalar sweep, the page's default; 0: the engine's default,
  // the widest) and the simulator's time per stage since the load (ns): the benchmark's.
  setVbdLanes: (w) => Module.Playground.setVbdLanes(w),
  profile: () => engine.profile(),
  setThreads: (n) => { const got = engine.setThreads(n); showThreads(); return got; },
  // The sliders' keys (declared with their documented ranges, then the text's other numbers).
  sliders: () => sliderList(),
  sound: () => audio ? audio.context.state : 'off',
  compress, decompress,
};

// ---- start -------------------------------------------------------------------------------
listExamples();
let opened = false;
if (location.hash.length > 1) {
  try { opened = loadText(await decompress(location.hash.slice(1))).ok; } catch (e) { showError({ text: `shared scene: ${e}` }); }
}
if (!opened) {
  const name = params.get('scene') || 'flag_in_wind';
  if (examples.includes(name)) openExample(name);
  else { showError({ text: `no example named '${name}'` }); openExample('flag_in_wind'); }
}
setPlaying(playing);
window.maille.ready = true;
document.dispatchEvent(new Event('maille-ready'));
requestAnimationFrame(frame);
