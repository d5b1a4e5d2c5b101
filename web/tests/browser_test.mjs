// The browser test of Maille's page (scripts/web.sh test): build/web served by a static server
// in this process, opened in Debian's Chromium (headless, WebGL2 on SwiftShader), driven by
// playwright-core (which never downloads a browser). Checks, in order:
//   1. flag_in_wind stepped 1 s: stateHash() equals the native single-thread build's hash of the
//      same run (web/tests/reference_hashes.txt, checked natively by
//      tests/regression/test_web_reference.cpp);
//   2. every example: loaded and stepped as many steps as its golden test
//      (tests/golden/NAME.hash), the hash compared, then on to 100 steps at least without a
//      blow-up; an example the browser build cannot run is refused by name, with its reason;
//   3. a point dragged with the mouse follows it (against the same run without the drag);
//   4. broken scene texts: line and column, and the last good scene goes on running;
//   5. a blow-up shows its step and module and pauses the page;
//   6. `?scene=NAME` and `#<compressed text>` open scenes; set(key, value) as --set;
//      sound: the listened samples equal the native Recorder's (web/tests/reference_audio.txt:
//      exact, sinc and linear resampling) and, where a native build exists, a float32 WAV of
//      `maille run --audio`; sliders: every declared key of the scene's tables with its
//      documented range, the ends accepted by set(); the smooth surface: the WebGL2 shader's
//      evaluation (transform feedback) against the engine's CPU evaluation, and drawn;
//   7. a frame drawn: pixels of the cloth's colour in the middle of the canvas (screenshot kept);
//   8. the page's own frame counter on the 64^2 cloth on a sphere by VBD at 1/60 s (reported,
//      not asserted: performance is measured, never a pass/fail condition);
//   9. threads: served with the cross-origin isolation headers the page runs the threaded
//      module; flag_in_wind's 1 s hash and every example's hash on 2 threads equal those on one
//      thread; ms per step on 1 and 2 threads reported (flag_64, the 64^2 VBD cloth).
// Usage: node web/tests/browser_test.mjs [--quick] [--out DIR]
//   --quick   examples: hash and 100 steps only for those under 5000 points
// Exit status 0 when every check passes; each failure is printed with what differed.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { launch, openPage, root, serve } from './harness.mjs';

const args = process.argv.slice(2);
const quick = args.includes('--quick');
const outDir = args.includes('--out') ? args[args.indexOf('--out') + 1] : path.join(root, 'build/web-test');
fs.mkdirSync(outDir, { recursive: true });

let failures = 0;
const check = (ok, what, detail = '') => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? `: ${detail}` : ''}`);
  if (!ok) ++failures;
};

const { server, base } = await serve();
const { page, close } = await launch();
const consoleErrors = [];
page.on('pageerror', (e) => consoleErrors.push(String(e)));
page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
// A failed request's console message does not name the resource: name it here.
page.on('response', (r) => { if (r.status() >= 400) consoleErrors.push(`${r.status()} ${r.url()}`); });
const open = (query = '') => openPage(page, base, query);

// Every example: loaded, stepped its golden test's steps (tests/golden/NAME.hash) and hashed,
// then on to 100 steps at least without a blow-up; refused examples by name. `tag` prefixes the
// lines (the threaded page's run).
async function goldenAll(tag) {
  const examples = await page.evaluate(() => maille.examples());
  const out = { refused: [], equal: 0, compared: 0, differing: [], hashes: {} };
  for (const name of examples) {
    const golden = fs.readFileSync(path.join(root, `tests/golden/${name}.hash`), 'utf8').trim().split(' ');
    const steps = +golden[0], hash = golden[2];
    const r = await page.evaluate(({ name, steps, quick }) => {
      const o = maille.open(name);
      if (!o.ok) return { refused: o.error.text };
      maille.pause();
      const points = maille.stats().points;
      if (quick && points > 5000) return { skipped: points };
      const t = performance.now();
      const done = maille.step(steps);
      const hash = maille.stateHash();
      const more = maille.step(Math.max(0, 100 - steps));
      const s = maille.stats();
      return { done, hash, more, blowUp: s.blowUp, points, ms: performance.now() - t };
    }, { name, steps, quick });
    if (r.refused) { out.refused.push(name); check(true, `${tag}${name}: refused by name`, r.refused); continue; }
    if (r.skipped) { console.log(`skip ${tag}${name} (${r.skipped} points, --quick)`); continue; }
    const stepped = r.done === steps && r.done + r.more >= 100 && !r.blowUp;
    check(stepped, `${tag}${name}: loaded and stepped ${r.done + r.more} steps`, r.blowUp ? r.blowUp.message : `${r.ms.toFixed(0)} ms`);
    ++out.compared;
    out.hashes[name] = r.hash;
    if (r.hash === hash) ++out.equal; else out.differing.push(`${name} (${r.hash} vs native ${hash} after ${steps} steps)`);
  }
  return out;
}

const t0 = Date.now();
try {
  await open('?scene=flag_in_wind&paused');
  check(true, 'page opened', `${((Date.now() - t0) / 1000).toFixed(1)} s`);

  // 1. flag_in_wind for 1 s against the native hash.
  const refs = Object.fromEntries(fs.readFileSync(path.join(root, 'web/tests/reference_hashes.txt'), 'utf8')
    .split('\n').filter((l) => l && !l.startsWith('#')).map((l) => l.trim().split(/\s+/))
    .map(([id, example, steps, hash]) => [id, { example, steps: +steps, hash }]));
  {
    const ref = refs.flag_in_wind_1s;
    const r = await page.evaluate(({ example, steps }) => {
      maille.pause();
      const l = maille.load(maille.exampleText(example));
      const t = performance.now();
      const done = maille.step(steps);
      return { ok: l.ok, done, hash: maille.stateHash(), ms: performance.now() - t, time: maille.stats().time };
    }, ref);
    check(r.ok && r.done === ref.steps && r.hash === ref.hash, 'flag_in_wind, 1 s: stateHash equals the native hash',
      `${r.hash} vs ${ref.hash} (t = ${r.time} s, ${r.done} steps in ${r.ms.toFixed(0)} ms)`);
  }

  // 2. Every example: golden hash, then 100 steps; refusals by name.
  const golden1 = await goldenAll('');
  const refused = golden1.refused;
  // The laws are the same; where the floating-point operations differ the bits may too
  // (docs/web.md: libm's sin/cos/exp/pow in Emscripten's musl against glibc's).
  console.log(`golden hashes: ${golden1.equal} of ${golden1.compared} examples equal to the native build's bit for bit`);
  for (const d of golden1.differing) console.log(`     differs: ${d}`);
  check(refused.length <= 1 && (refused.length === 0 || refused[0] === 'gpu_cloth_512'),
    'only gpu_cloth_512 (the GPU compute backend) is refused', refused.join(', '));
  fs.writeFileSync(path.join(outDir, 'golden.txt'), `equal ${golden1.equal} of ${golden1.compared}\n${golden1.differing.join('\n')}\n`);
  // VBD's sweeps in lanes of 2 doubles (f64x2; the page runs the scalar sweep by default): the
  // implicit examples' golden hashes again, bit for bit.
  for (const name of ['cloth_on_sphere_vbd', 'cloth_heap_vbd']) {
    const golden = fs.readFileSync(path.join(root, `tests/golden/${name}.hash`), 'utf8').trim().split(' ');
    const r = await page.evaluate(({ name, steps }) => {
      maille.setVbdLanes(2);
      maille.open(name); maille.pause();
      const done = maille.step(steps);
      const out = { done, hash: maille.stateHash(), lanes: maille.stats().vbdLanes };
      maille.setVbdLanes(1);
      return out;
    }, { name, steps: +golden[0] });
    check(r.lanes === 2 && r.hash === golden[2], `${name} with VBD in lanes of 2 doubles: the golden hash`,
      `${r.hash} vs ${golden[2]} after ${r.done} steps (${r.lanes} lanes)`);
  }
  const oneThread = await page.evaluate(() => ({ threaded: maille.threaded, threads: maille.threads(),
    isolated: self.crossOriginIsolated }));
  check(!oneThread.isolated && !oneThread.threaded && oneThread.threads === 1,
    'a page served without the isolation headers runs the one-thread module', JSON.stringify(oneThread));

  // 3. Drag a point with the mouse: it follows, against the same run without the drag.
  {
    await open('?scene=flag_in_wind&paused');
    const free = await page.evaluate(() => {
      maille.step(400);  // the flag spread by the wind
      const p = maille.positions();
      let best = 0;  // the free corner farthest from the pole: the largest x
      for (let i = 0; i < p.length / 3; ++i) if (p[3 * i] > p[3 * best]) best = i;
      return best;
    });
    // Reference: the same 400 further steps without the drag.
    const plain = await page.evaluate((i) => {
      maille.open('flag_in_wind'); maille.pause(); maille.step(800);
      const p = maille.positions(); return [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
    }, free);
    await page.evaluate(() => { maille.open('flag_in_wind'); maille.pause(); maille.step(400); });
    await page.waitForTimeout(100);  // a frame drawn with the camera's matrices
    const box = await page.locator('#canvas').boundingBox();
    const [sx, sy] = await page.evaluate((i) => maille.project(i), free);
    await page.mouse.move(box.x + sx, box.y + sy);
    await page.mouse.down();
    await page.mouse.move(box.x + sx, box.y + sy - 120, { steps: 4 });  // 120 px up
    const grabbed = await page.evaluate(() => maille.dragged());
    const dragged = await page.evaluate((i) => {
      maille.step(400);
      const p = maille.positions(); return [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
    }, free);
    await page.mouse.up();
    const lift = dragged[1] - plain[1];
    check(grabbed === free, 'the mouse grabs the point under it', `point ${grabbed} (expected ${free})`);
    check(lift > 0.05, 'a dragged point follows the mouse up', `${(lift * 100).toFixed(1)} cm above the run without the drag`);
  }

  // 4. Broken texts: line and column; the last good scene keeps running.
  {
    const r = await page.evaluate(() => {
      maille.open('flag_in_wind'); maille.pause(); maille.step(10);
      const good = maille.text();
      const before = { scene: maille.stats().scene, step: maille.stats().step };
      const lines = good.split('\n');
      const at = lines.findIndex((l) => /^mass\s*=/.test(l));
      lines[at] = 'mass = -1.0';
      const badValue = maille.load(lines.join('\n'));
      const syntax = maille.load(good.replace('[simulation]', '[simulation]\nstep = = 2'));
      const after = maille.step(5);
      return { at: at + 1, badValue, syntax, before, after, stats: maille.stats(),
               shown: document.getElementById('error').textContent,
               marked: document.querySelector('#gutter .bad')?.textContent.trim() };
    });
    check(!r.badValue.ok && r.badValue.error.line === r.at && r.badValue.error.column > 0,
      'a bad value: its line and column', `${r.badValue.error?.text} (expected line ${r.at})`);
    const synLine = 1 + (await page.evaluate(() => maille.exampleText('flag_in_wind').split('\n').findIndex((l) => l === '[simulation]'))) + 1;
    check(!r.syntax.ok && r.syntax.error.line === synLine && r.syntax.error.column > 0,
      'a TOML syntax error: its line and column', `${r.syntax.error?.text} (expected line ${synLine})`);
    check(r.stats.scene === r.before.scene && r.after === 5 && r.stats.step === r.before.step + 5,
      'the last good scene goes on running', `${r.stats.scene} at step ${r.stats.step}`);
    check(r.shown.includes(`:${synLine}:`) && r.marked === String(synLine), 'the page shows the error at its line',
      `${r.shown.split('\n')[0]}; gutter mark ${r.marked}`);
  }

  // 5. A blow-up: its step and module shown, the page paused.
  {
    const r = await page.evaluate(() => {
      maille.play();
      const text = maille.exampleText('flag_in_wind').replace(/^step = .*$/m, 'step = 6e-3');
      const l = maille.load(text);
      const done = maille.step(5000);
      return { ok: l.ok, done, blowUp: maille.stats().blowUp,
               shown: !document.getElementById('blowup').hidden, banner: document.getElementById('blowup').textContent,
               button: document.getElementById('play').textContent };
    });
    check(r.ok && r.done < 5000 && r.blowUp && r.blowUp.step > 0 && r.blowUp.module.length > 0,
      'an unstable step blows up with its step and module', r.blowUp ? `step ${r.blowUp.step}, ${r.blowUp.module}` : 'no blow-up');
    check(r.shown && r.banner.includes(`step ${r.blowUp?.step}`) && r.button === 'Play', 'the blow-up is shown and the page paused',
      r.banner.split('\n')[0]);
  }

  // 6. ?scene=NAME, #<compressed text>, set(key, value).
  {
    await open('?scene=rope_bridge&paused');
    const scene = await page.evaluate(() => maille.stats().scene);
    check(scene === 'rope_bridge', '?scene=rope_bridge opens the example', scene);
    const text = (await page.evaluate(() => maille.exampleText('pendulum_chain'))).replace(/^description = .*$/m, 'description = "shared by URL"');
    const code = await page.evaluate((t) => maille.compress(t), text);
    await open(`?paused#${code}`);
    const shared = await page.evaluate(() => ({ text: maille.text(), scene: maille.stats().scene }));
    check(shared.text === text && shared.scene === 'pendulum_chain', '#<compressed text> opens the shared scene',
      `${code.length} characters for ${text.length}`);
    const s = await page.evaluate(() => {
      maille.open('flag_in_wind'); maille.pause(); maille.step(100);
      const before = maille.stats();
      const r = maille.set('fields.gravity', [0, -1.62, 0]);
      const after = maille.stats();
      const bad = maille.set('flag[0].mass', -2);
      const unknown = maille.set('flag[7].mass', 1);
      return { r, bad, unknown, before, after };
    });
    check(s.r.ok && s.after.step === s.before.step && s.after.time === s.before.time,
      'set(key, value) applies like --set and the run goes on', `step ${s.after.step}`);
    check(!s.bad.ok && s.bad.error.text.includes('mass'), 'set: a bad value is refused with the key', s.bad.error?.text);
    check(!s.unknown.ok, 'set: a key that does not exist is refused', s.unknown.error?.text);
  }

  // 6b. Sound: the listened points' values per step, and the AudioWorklet started by the button.
  {
    await open('?scene=sound_plucked_string&paused');
    const l = await page.evaluate(() => {
      maille.load(maille.exampleText('sound_plucked_string'));  // listening starts with the load
      maille.step(1000);
      const r = maille.listened();
      let peak = 0;
      for (const x of r.samples) peak = Math.max(peak, Math.abs(x));
      return { channels: r.channels, n: r.samples.length, rate: r.rate, sampling: r.sampling, peak,
               button: !document.getElementById('sound').disabled };
    });
    check(l.channels >= 1 && l.n === 1000 * l.channels && l.peak > 0 && l.button && l.rate === 44100,
      'a [[listen]] scene at 1/44100 s gives one sample per step and channel at 44.1 kHz',
      `${l.channels} channel(s), ${l.n} values at ${l.rate} Hz (${l.sampling}), peak ${l.peak.toExponential(2)}`);
    // The samples equal the native Recorder's (`maille run --audio`), exact and resampled.
    const audioRefs = fs.readFileSync(path.join(root, 'web/tests/reference_audio.txt'), 'utf8')
      .split('\n').filter((x) => x && !x.startsWith('#')).map((x) => x.trim().split(/\s+/));
    for (const [id, example, steps, frames, hash, ...sets] of audioRefs) {
      const r = await page.evaluate(({ example, steps, frames, sets }) => {
        maille.pause();
        const l = maille.load(maille.exampleText(example));
        for (const kv of sets) {
          const eq = kv.indexOf('=');
          const r = maille.set(kv.slice(0, eq), kv.slice(eq + 1));
          if (!r.ok) return { error: r.error.text };
        }
        maille.step(steps);
        const got = maille.listened();
        if (got.samples.length < frames * got.channels) return { short: got.samples.length / got.channels };
        return { hash: maille.fnv1a(got.samples.subarray(0, frames * got.channels)), sampling: got.sampling,
          ok: l.ok };
      }, { example, steps: +steps, frames: +frames, sets });
      check(r.hash === hash, `sound ${id}: the page's samples equal \`maille run --audio\`'s (native Recorder)`,
        r.error || (r.short !== undefined ? `only ${r.short} frames` : `${r.hash} vs ${hash}, ${frames} frames, ${r.sampling}`));
    }
    // Where a native build is at hand, against `maille run --audio` itself: a float32 WAV at
    // gain 1 holds the very samples (the Recorder's float values).
    const native = ['build/dev', 'build/release', 'build/portable'].map((d) => path.join(root, d, 'apps/maille/maille'))
      .find((p) => fs.existsSync(p));
    if (native) {
      const wav = path.join(outDir, 'plucked.wav');
      execFileSync(native, ['run', path.join(root, 'examples/sound_plucked_string.toml'), '--audio', wav,
        '--set', 'audio.format="float32"', '--set', 'audio.gain=1', '--set', 'simulation.duration=0.1',
        '--out', path.join(outDir, 'plucked-run')], { stdio: 'ignore', env: { ...process.env, OMP_WAIT_POLICY: 'passive' } });
      const bytes = fs.readFileSync(wav);
      const at = bytes.indexOf('data');
      const cli = new Float32Array(bytes.buffer.slice(bytes.byteOffset + at + 8, bytes.byteOffset + at + 8 + bytes.readUInt32LE(at + 4)));
      const pageSamples = await page.evaluate(() => {
        maille.load(maille.exampleText('sound_plucked_string'));
        maille.step(4410);
        return Array.from(maille.listened().samples);
      });
      let same = 0;
      for (let i = 0; i < pageSamples.length; ++i) same += Object.is(Math.fround(pageSamples[i]), cli[i]) ? 1 : 0;
      check(same === pageSamples.length && cli.length >= pageSamples.length,
        'sound: the page\'s samples equal a float32 WAV of `maille run --audio` (0.1 s)',
        `${same} of ${pageSamples.length} values bit for bit (${path.relative(root, native)})`);
    } else {
      console.log('skip sound against `maille run --audio`: no native build (build/dev/apps/maille/maille)');
    }
    await page.click('#sound');
    await page.waitForTimeout(500);
    const state = await page.evaluate(() => maille.sound());
    check(state === 'running' || state === 'suspended', 'the Sound button starts the AudioWorklet', state);
  }

  // 6c. Sliders from the declared keys: a scene's stage tables give every key their method uses,
  // written or not, with the documented range; each accepted by set() at its range's ends.
  {
    await open('?scene=cloth_heap&paused');
    const r = await page.evaluate(() => {
      const list = maille.sliders();
      const declared = list.filter((k) => k.declared);
      const unwritten = declared.filter((k) => !k.written);
      const ranged = declared.filter((k) => k.hi > k.lo);
      const refused = [], slid = [];
      for (const k of ranged) {
        for (const v of [k.loOpen ? k.lo + (k.hi - k.lo) / 1000 : k.lo, k.hi]) {
          const x = k.integer ? Math.round(v) : v;
          const r = maille.set(k.key, x);
          if (!r.ok) refused.push(`${k.key}=${x}: ${r.error.text}`);
        }
        maille.set(k.key, k.value);
      }
      // Every declared slider's two ends are values the engine accepts.
      for (const k of declared) {
        for (const x of [k.sliderMin, k.sliderMax]) {
          const r = maille.set(k.key, x);
          if (!r.ok) refused.push(`slider ${k.key}=${x}: ${r.error.text}`);
        }
        slid.push(`${k.key} ${+k.sliderMin.toPrecision(3)}..${+k.sliderMax.toPrecision(3)}`);
        maille.set(k.key, k.value);
      }
      const shown = [...document.querySelectorAll('#sliders input[type=range]')].map((i) => i.dataset.key);
      return { n: list.length, declared: declared.length, unwritten: unwritten.map((k) => k.key),
        ranged: ranged.length, refused, shown: shown.length,
        sample: ranged.slice(0, 3).map((k) => `${k.key} ${k.range}`), slid };
    });
    check(r.declared > 0 && r.unwritten.length > 0 && r.shown >= r.declared,
      'sliders for the declared keys of the scene\'s tables, written in the text or not',
      `${r.declared} declared (${r.unwritten.length} not written, e.g. ${r.unwritten.slice(0, 3).join(', ')}), ${r.n} in all, ${r.shown} shown`);
    check(r.ranged > 0 && r.refused.length === 0, 'each declared range\'s ends and each slider\'s ends are accepted by set()',
      r.refused.slice(0, 2).join(' | ') || `${r.ranged} keys with a range, e.g. ${r.sample.join('; ')}; sliders ${r.slid.slice(0, 4).join(', ')}`);
  }

  // 6d. The smooth surface in WebGL2: the shared math's evaluation in the page's vertex shader
  // (read back by transform feedback) against the engine's CPU evaluation, on a grid cloth
  // (Catmull-Rom patches) and on a membrane (PN triangles); then drawn with the toggle on.
  {
    for (const scene of ['smooth_flag_16', 'smooth_drum']) {
      await open(`?scene=${scene}&paused`);
      const r = await page.evaluate(() => { maille.step(200); return { check: maille.smoothCheck(), on: maille.smooth() }; });
      const c = r.check;
      // Bound: float32 evaluations of the same formulas; a GPU may contract a*b+c into one
      // rounding, so allow 1e-5 of the surface's extent for positions and 1e-4 for unit normals.
      check(c.available && c.vertices > 0 && c.gpuVertices === c.vertices && c.positionDiff <= 1e-5 * c.extent &&
        c.normalDiff <= 1e-4 && r.on,
        `${scene}: the WebGL2 smooth surface equals the engine's CPU evaluation`,
        c.error || `${c.vertices} vertices at lod ${c.lod} (${c.grids} grid(s), ${c.pnTriangles} PN triangles): ` +
        `position ${c.positionDiff.toExponential(2)} m (extent ${c.extent.toFixed(2)} m), normal ${c.normalDiff.toExponential(2)}`);
    }
    await page.waitForTimeout(300);
    const px = await page.evaluate(() => maille.clothPixels());
    await page.locator('#canvas').screenshot({ path: path.join(outDir, 'smooth.png') });
    check(px.cloth > px.total * 0.05, 'the smooth surface is drawn', `${px.cloth} of ${px.total} pixels of the cloth's colour; smooth.png`);
  }

  // 7. A frame drawn: the cloth in the middle of the canvas.
  {
    await open('?scene=flag_in_wind&paused');
    await page.evaluate(() => { maille.step(2000); });
    await page.waitForTimeout(300);
    const px = await page.evaluate(() => maille.clothPixels());
    await page.locator('#canvas').screenshot({ path: path.join(outDir, 'canvas.png') });
    await page.screenshot({ path: path.join(outDir, 'page.png') });
    check(px.cloth > px.total * 0.05, 'the cloth is drawn in the middle of the canvas',
      `${px.cloth} of ${px.total} pixels of the cloth's colour; ${path.join(outDir, 'canvas.png')}`);
  }

  // 8. The page's own frame counter: the 64^2 cloth on a sphere by VBD at 1/60 s, playing.
  {
    await open('?scene=cloth_on_sphere&paused');
    const r = await page.evaluate(async () => {
      for (const [k, v] of [['flag[0].resolution', [64, 64]], ['simulation.integrator', 'implicit_euler'],
        ['simulation.implicit.solver', 'vbd'], ['simulation.step', 1 / 60]]) {
        const r = maille.set(k, v);
        if (!r.ok) return { error: r.error.text };
      }
      maille.play();
      await new Promise((res) => setTimeout(res, 4000));
      maille.pause();
      return { frame: maille.frameStats(), stats: maille.stats() };
    });
    if (r.error) check(false, '64^2 cloth on a sphere by VBD loads', r.error);
    else {
      const f = r.frame;
      console.log(`perf: 64^2 cloth on a sphere, VBD, 1/60 s, in the page: ${f.fps.toFixed(1)} frames/s, ` +
        `${f.msPerFrame.toFixed(2)} ms per frame (step ${f.stepMs.toFixed(2)} ms + drawing ${f.drawMs.toFixed(2)} ms), ` +
        `max ${f.maxMsPerFrame.toFixed(1)} ms over ${f.frames} frames; ${r.stats.points} points, t = ${r.stats.time.toFixed(2)} s`);
      fs.writeFileSync(path.join(outDir, 'frames.json'), JSON.stringify(r, null, 1));
      check(f.frames >= 3 && !r.stats.blowUp, '64^2 cloth on a sphere by VBD runs in the page', `${f.frames} frames`);
    }
  }
  // 9. Threads: served with the cross-origin isolation headers (as web/serve.py does), the page
  // runs the threaded module (OpenMP on Web Workers): the same hashes on 2 threads, and the time
  // per step on 1 and 2 threads (reported, not asserted).
  {
    const mt = await serve(undefined, { isolated: true });
    try {
      await openPage(page, mt.base, '?scene=flag_in_wind&paused');
      const info = await page.evaluate(() => ({ isolated: self.crossOriginIsolated, threaded: maille.threaded,
        threads: maille.threads(), cores: navigator.hardwareConcurrency }));
      check(info.isolated && info.threaded && info.threads >= Math.min(2, info.cores),
        'a cross-origin isolated page runs the threaded module', JSON.stringify(info));
      // Scene errors are C++ exceptions inside the reader: caught in the threaded module too.
      const bad = await page.evaluate(() => maille.load(maille.exampleText('flag_in_wind').replace(/^mass\s*=.*$/m, 'mass = -1.0')));
      check(!bad.ok && bad.error.line > 0, 'the threaded module reports a bad value at its line', bad.error?.text);
      const two = await page.evaluate(() => maille.setThreads(2));
      if (two < 2) {
        console.log(`skip threads: this machine offers ${info.cores} core(s)`);
      } else {
        const ref = refs.flag_in_wind_1s;
        const r = await page.evaluate(({ example, steps }) => {
          maille.pause();
          maille.load(maille.exampleText(example));
          const done = maille.step(steps);
          return { done, hash: maille.stateHash(), threads: maille.stats().threads };
        }, ref);
        check(r.threads === 2 && r.done === ref.steps && r.hash === ref.hash,
          'flag_in_wind, 1 s, on 2 threads: stateHash equals the native hash', `${r.hash} vs ${ref.hash}`);
        const golden2 = await goldenAll('2 threads: ');
        const same = Object.keys(golden2.hashes).filter((n) => golden2.hashes[n] === golden1.hashes[n]);
        console.log(`golden hashes on 2 threads: ${golden2.equal} of ${golden2.compared} equal to the native build's`);
        check(same.length === golden2.compared && golden2.compared === golden1.compared,
          'every example on 2 threads: the same hash as on 1 thread', `${same.length} of ${golden2.compared}`);
        check(golden2.equal === golden1.equal, 'as many golden hashes equal on 2 threads as on 1',
          `${golden2.equal} vs ${golden1.equal}`);
        // Time per step on 1 and 2 threads, the fastest of 3 runs each (reported only).
        const perf = await page.evaluate(() => {
          const cases = [
            { id: 'flag_64', example: 'flag_64', sets: [], steps: 200 },
            { id: '64^2 cloth on sphere, VBD, 1/60 s', example: 'cloth_on_sphere', steps: 10,
              sets: [['flag[0].resolution', '[64, 64]'], ['simulation.integrator', 'implicit_euler'],
                ['simulation.implicit.solver', 'vbd'], ['simulation.step', '0.016666666666666666']] },
          ];
          const rows = [];
          for (const c of cases) {
            const ms = {};
            for (const threads of [1, 2]) {
              maille.setThreads(threads);
              let best = Infinity;
              for (let rep = 0; rep < 3; ++rep) {
                maille.load(maille.exampleText(c.example));
                for (const [k, v] of c.sets) maille.set(k, v);
                maille.step(2);
                const t = performance.now();
                maille.step(c.steps);
                best = Math.min(best, (performance.now() - t) / c.steps);
              }
              ms[threads] = best;
            }
            rows.push({ id: c.id, one: ms[1], two: ms[2] });
          }
          return rows;
        });
        for (const p of perf)
          console.log(`perf: ${p.id}: ${p.one.toFixed(3)} ms/step on 1 thread, ${p.two.toFixed(3)} on 2 (${(p.one / p.two).toFixed(2)}x)`);
        fs.writeFileSync(path.join(outDir, 'threads.json'), JSON.stringify(perf, null, 1));
      }
    } finally {
      mt.server.close();
    }
  }
  check(consoleErrors.length === 0, 'no error in the page\'s console', consoleErrors.slice(0, 3).join(' | '));
} catch (e) {
  check(false, 'browser test', e.stack || String(e));
} finally {
  await close();
  server.close();
}
console.log(`${failures === 0 ? 'PASS' : 'FAIL'}: browser test (${((Date.now() - t0) / 1000).toFixed(0)} s)`);
process.exit(failures === 0 ? 0 : 1);
