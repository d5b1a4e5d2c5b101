// What the browser test and the benchmark share: build/web served by a static server in this
// process, and Debian's Chromium launched headless (WebGL2 on SwiftShader) through
// playwright-core, with a fresh profile that is removed at close.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');

const types = { '.html': 'text/html', '.js': 'text/javascript', '.wasm': 'application/wasm',
  '.css': 'text/css', '.png': 'image/png', '.toml': 'text/plain' };

// `isolated`: send the cross-origin isolation headers (as web/serve.py does), so that the page
// runs the threaded module; without them it runs on one thread.
export async function serve(site = process.env.MAILLE_WEB_SITE || path.join(root, 'build/web'),
  { isolated = false } = {}) {
  if (!fs.existsSync(path.join(site, 'maille.wasm'))) {
    console.error(`${site}/maille.wasm is missing: run scripts/web.sh first`);
    process.exit(2);
  }
  const server = http.createServer((req, res) => {
    let file = path.join(site, decodeURIComponent(new URL(req.url, 'http://x').pathname));
    if (file.startsWith(site) && fs.existsSync(file) && fs.statSync(file).isDirectory())
      file = path.join(file, 'index.html');
    if (!file.startsWith(site) || !fs.existsSync(file)) { res.writeHead(404); return res.end('not found'); }
    const headers = { 'content-type': types[path.extname(file)] || 'application/octet-stream' };
    if (isolated) {
      headers['cross-origin-opener-policy'] = 'same-origin';
      headers['cross-origin-embedder-policy'] = 'require-corp';
    }
    res.writeHead(200, headers);
    fs.createReadStream(file).pipe(res);
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  return { server, base: `http://127.0.0.1:${server.address().port}` };
}

export async function launch() {
  const userDir = fs.mkdtempSync('/tmp/maille-chromium-');
  const context = await chromium.launchPersistentContext(userDir, {
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    viewport: { width: 1400, height: 900 },
    args: ['--no-sandbox', '--headless=new', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      '--no-first-run', '--disable-renderer-backgrounding', '--disable-background-timer-throttling'],
  });
  const page = context.pages()[0] || await context.newPage();
  const close = async () => { await context.close(); fs.rmSync(userDir, { recursive: true, force: true }); };
  return { context, page, close };
}

export async function openPage(page, base, query = '') {
  await page.goto(`${base}/index.html${query}`);
  await page.waitForFunction(() => window.maille && window.maille.ready === true, null, { timeout: 60000 });
}
