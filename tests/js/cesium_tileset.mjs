#!/usr/bin/env node
// Loads a 3D Tiles tileset (1.1 glb or 1.0 .pnts) with CesiumJS (@cesium/engine) in headless Chromium, offline:
// cesium_page.js is bundled with esbuild (the engine's sources import CommonJS packages a browser cannot load
// unbundled) and served with the engine's Workers, ThirdParty and Assets from node_modules by a local server;
// any request elsewhere fails the check. Fails on a failed tile, a page or console error, a failed request,
// tiles not all loaded within 60 s, a leaf point count other than --points N, no `classification` drawn from the
// tiles' metadata where asset.extras lists it or --classes is given, one drawn outside --classes A,B,.., or a
// bounding sphere centre further than 0.1 degrees from --near LAT,LON. Prints one JSON line; exits 1 on failure, 2 on bad
// arguments or when no Chromium is found (set CHROMIUM to its path).
//   node cesium_tileset.mjs DIR [--points N] [--classes A,B,..] [--near LAT,LON]
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { build } from 'esbuild';
import puppeteer from 'puppeteer-core';
import { serveFolders } from './static_server.mjs';

const started = performance.now();
const argv = process.argv.slice(2);
const dir = argv.shift();
const opts = {};
while (argv.length >= 2 && ['--points', '--classes', '--near'].includes(argv[0])) opts[argv.shift().slice(2)] = argv.shift();
function fail(result, code = 1) {
  console.log(JSON.stringify({ ok: false, ...result }));
  process.exit(code);
}
if (!dir || argv.length || !existsSync(path.join(dir, 'tileset.json')))
  fail({ error: 'usage: node cesium_tileset.mjs DIR [--points N] [--classes A,B,..] [--near LAT,LON]' }, 2);
const here = path.dirname(fileURLToPath(import.meta.url));
const engine = path.join(here, 'node_modules/@cesium/engine');

function findChromium() {
  if (process.env.CHROMIUM) return process.env.CHROMIUM;
  for (const name of ['chromium', 'chromium-browser', 'google-chrome'])
    for (const d of (process.env.PATH ?? '').split(':')) if (d && existsSync(path.join(d, name))) return path.join(d, name);
  return null;
}
const executablePath = findChromium();
if (!executablePath) fail({ error: 'no Chromium found (scripts/setup.sh --viewer installs it; or set CHROMIUM)' }, 2);

const page_dir = mkdtempSync(path.join(os.tmpdir(), 'cesium-page-'));
const timer = setTimeout(() => {
  rmSync(page_dir, { recursive: true, force: true });
  fail({ error: 'timed out after 120 s' });
}, 120_000);
let server, browser, outcome;
try {
  await build({ entryPoints: [path.join(here, 'cesium_page.js')], bundle: true, format: 'esm', minify: false,
                outfile: path.join(page_dir, 'page.js'), logLevel: 'error' });
  // CESIUM_BASE_URL is where the engine fetches its workers and assets from; it must be set before it loads.
  writeFileSync(path.join(page_dir, 'index.html'), '<!doctype html><link rel="icon" href="data:,">' +
    '<style>body { margin: 0 } .cesium-widget, canvas { width: 100%; height: 100% }</style><body>' +
    '<script>window.CESIUM_BASE_URL = "/cesium/";</script><script type="module" src="page.js"></script>');
  server = await serveFolders([
    ['/tileset/', dir],
    ['/cesium/Workers/', path.join(engine, 'Build/Workers')],
    ['/cesium/ThirdParty/Workers/', path.join(engine, 'Build/ThirdParty/Workers')],
    ['/cesium/ThirdParty/', path.join(engine, 'Source/ThirdParty')],
    ['/cesium/Assets/', path.join(engine, 'Source/Assets')],
    ['/', page_dir],
  ]);
  const args = ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--window-size=640,480'];
  if (process.getuid?.() === 0) args.push('--no-sandbox');  // Chromium refuses to run its sandbox as root
  browser = await puppeteer.launch({ executablePath, headless: true, args });
  const page = await browser.newPage();
  const errors = [], warnings = [], external = [];
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(`console: ${m.text()}`);
    if (m.type() === 'warn') warnings.push(m.text());
  });
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()} ${r.failure()?.errorText}`));
  page.on('response', (r) => r.status() >= 400 && errors.push(`HTTP ${r.status()}: ${r.url()}`));
  page.on('request', (r) => !r.url().startsWith(server.url) && !/^(data|blob):/.test(r.url()) && external.push(r.url()));
  await page.setViewport({ width: 640, height: 480 });
  await page.goto(`${server.url}/index.html`);
  await page.waitForFunction('window.__cesium && window.__cesium.done', { timeout: 100_000, polling: 250 });
  const r = await page.evaluate(() => window.__cesium);
  delete r.done;
  const result = { ...r, errors: errors.slice(0, 5), warnings: warnings.slice(0, 5), externalRequests: external.slice(0, 5),
                   engine: JSON.parse(readFileSync(path.join(engine, 'package.json'))).version,
                   browser: await browser.version() };
  const problems = [];
  if (r.error) problems.push(r.error);
  if (errors.length || external.length) problems.push('page errors or requests outside the local server');
  if (r.tileFailures.length) problems.push(`${r.tileFailures.length} tiles failed`);
  if (!r.tilesLoaded || r.leavesLoaded !== r.leaves) problems.push(`${r.leavesLoaded} of ${r.leaves} leaves loaded`);
  if (opts.points !== undefined && r.points !== Number(opts.points)) problems.push(`${r.points} points, not ${opts.points}`);
  const listed = JSON.parse(readFileSync(path.join(dir, 'tileset.json'))).asset?.extras?.properties ?? [];
  const drawn = Object.keys(r.classesDrawn ?? {}).map(Number);
  const allowed = opts.classes?.split(',').map(Number);
  if ((allowed || listed.includes('classification')) && !drawn.length) problems.push('no classification drawn');
  if (allowed && drawn.some((c) => !allowed.includes(c))) problems.push(`classifications ${drawn} outside ${allowed}`);
  if (opts.near) {
    const [lat, lon] = opts.near.split(',').map(Number);
    if (!r.centre || Math.abs(r.centre.lat - lat) > 0.1 || Math.abs(r.centre.lon - lon) > 0.1)
      problems.push(`centre ${JSON.stringify(r.centre)} is not near ${opts.near}`);
  }
  outcome = problems.length ? { ok: false, ...result, problems } : { ok: true, ...result };
} catch (e) {
  outcome = { ok: false, error: String(e?.message ?? e) };
} finally {
  clearTimeout(timer);
  await browser?.close();
  await server?.close();
  rmSync(page_dir, { recursive: true, force: true });
}
outcome.seconds = Number(((performance.now() - started) / 1000).toFixed(1));
console.log(JSON.stringify(outcome));
process.exit(outcome.ok ? 0 : 1);
