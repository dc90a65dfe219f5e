#!/usr/bin/env node
// Renders a 3D Tiles tileset (1.0 .pnts or 1.1 .glb) in headless Chromium (software GL: SwiftShader through ANGLE)
// with three.js and 3d-tiles-renderer (viewer/viewer.js: glTF tiles through its GLTFExtensionsPlugin with three's
// MeshoptDecoder; a tileset placed on the globe framed in its local frame), saves a screenshot and checks that at
// least 1 % of its pixels differ from the clear colour. Everything is served from a local HTTP server on a free
// port: DIR under /tileset/, the page from viewer/, the modules from node_modules/ (no CDN). Prints one JSON
// line; exits 1 when the picture is empty or loading fails, 2 on bad arguments or when no Chromium is found (set
// CHROMIUM to its path).
//   node render_tileset.mjs DIR OUT.png
import { existsSync } from 'node:fs';
import { writeFile } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';
import { serveFolders } from './static_server.mjs';

const [dir, out] = process.argv.slice(2);
if (!dir || !out) {
  console.error('usage: node render_tileset.mjs DIR OUT.png');
  process.exit(2);
}
const here = path.dirname(fileURLToPath(import.meta.url));
const width = 640, height = 480, clear = [0x20, 0x30, 0x40];
const minFraction = 0.01;

function findChromium() {
  if (process.env.CHROMIUM) return process.env.CHROMIUM;
  for (const name of ['chromium', 'chromium-browser', 'google-chrome']) {
    for (const d of (process.env.PATH ?? '').split(':')) {
      if (d && existsSync(path.join(d, name))) return path.join(d, name);
    }
  }
  return null;
}

function fail(result, code = 1) {
  console.log(JSON.stringify({ ok: false, ...result }));
  process.exit(code);
}

const executablePath = findChromium();
if (!executablePath) fail({ error: 'no Chromium found (scripts/setup.sh --viewer installs it; or set CHROMIUM)' }, 2);

const server = await serveFolders([
  ['/tileset/', dir],
  ['/node_modules/', path.join(here, 'node_modules')],
  ['/', path.join(here, 'viewer')],
]);
const args = ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', `--window-size=${width},${height}`];
if (process.getuid?.() === 0) args.push('--no-sandbox');  // Chromium refuses to run its sandbox as root
let browser;
let outcome = { code: 1, result: { error: 'not run' } };
const timer = setTimeout(() => fail({ error: 'timed out after 120 s' }), 120_000);
try {
  browser = await puppeteer.launch({ executablePath, headless: true, args });
  const page = await browser.newPage();
  const logs = [];
  page.on('console', (m) => logs.push(m.text()));
  page.on('pageerror', (e) => logs.push(`page error: ${e.message}`));
  await page.setViewport({ width, height });
  const hex = '%23' + clear.map((c) => c.toString(16).padStart(2, '0')).join('');
  await page.goto(`${server.url}/index.html?width=${width}&height=${height}&clear=${hex}`);
  await page.waitForFunction('window.__render && window.__render.done', { timeout: 90_000 }).catch((e) => {
    throw new Error(`${e.message}; page said: ${logs.slice(-5).join(' | ')}`);
  });
  const render = await page.evaluate(() => window.__render);
  const png = await page.screenshot({ type: 'png' });
  await writeFile(out, png);
  // Count in the page, from the screenshot itself (no PNG decoder needed here).
  const { differing, total } = await page.evaluate(async (b64, c) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const canvas = Object.assign(document.createElement('canvas'), { width: img.width, height: img.height });
    const g = canvas.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, img.width, img.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4)
      if (Math.abs(d[i] - c[0]) > 2 || Math.abs(d[i + 1] - c[1]) > 2 || Math.abs(d[i + 2] - c[2]) > 2) n++;
    return { differing: n, total: img.width * img.height };
  }, Buffer.from(png).toString('base64'), clear);
  const fraction = differing / total;
  const result = { screenshot: out, width, height, differingPixels: differing, fraction: Number(fraction.toFixed(4)),
                   tilesLoaded: render.loaded, tilesFailed: render.failed, visiblePoints: render.visiblePoints,
                   browser: await browser.version() };
  if (render.failed > 0) outcome = { code: 1, result: { ...result, error: 'tiles failed to load', logs: logs.slice(-5) } };
  else if (fraction < minFraction)
    outcome = { code: 1, result: { ...result, error: `only ${(100 * fraction).toFixed(2)} % of the pixels are drawn` } };
  else outcome = { code: 0, result };
} catch (e) {
  outcome = { code: 1, result: { error: String(e?.message ?? e) } };
} finally {
  clearTimeout(timer);
  await browser?.close();
  await server.close();
}
console.log(JSON.stringify({ ok: outcome.code === 0, ...outcome.result }));
process.exit(outcome.code);
