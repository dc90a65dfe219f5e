#!/usr/bin/env node
// An independent reader of megavox's 3D Tiles output: loaders.gl (not megavox code) loads DIR/tileset.json
// over HTTP from a local server (as a client would, relative URIs and all), every tile is walked and every
// .pnts content is loaded and parsed. Each content's point count must be what
// its own feature table says (POINTS_LENGTH, read from the file by hand), with 3 positions and, where it has
// RGB, 3 colours per point; the leaves must add up to EXPECTED_LEAF_POINTS (refine REPLACE: the leaves are
// the whole cloud). Prints one JSON line; exits 1 on any mismatch, 2 on bad arguments.
//   node check_tileset.mjs DIR EXPECTED_LEAF_POINTS
import { load } from '@loaders.gl/core';
import { Tiles3DLoader } from '@loaders.gl/3d-tiles';
import { serveFolders } from './static_server.mjs';

const [dir, expectedText] = process.argv.slice(2);
if (!dir || !/^\d+$/.test(expectedText ?? '')) {
  console.error('usage: node check_tileset.mjs DIR EXPECTED_LEAF_POINTS');
  process.exit(2);
}
const expected = Number(expectedText);

// POINTS_LENGTH and the property names, from the tile's feature table JSON (header: 7 little-endian uint32).
async function featureTable(url) {
  const bytes = Buffer.from(await (await fetch(url)).arrayBuffer());
  const jsonLength = bytes.readUInt32LE(12);
  return JSON.parse(bytes.subarray(28, 28 + jsonLength).toString('utf8'));
}

const problems = [];
const counts = { tiles: 0, contentTiles: 0, leaves: 0, leafPoints: 0, points: 0, expectedLeafPoints: expected };

async function walk(tile, depth) {
  counts.tiles++;
  const children = tile.children ?? [];
  if (tile.contentUrl) {
    counts.contentTiles++;
    const name = new URL(tile.contentUrl).pathname;
    const content = await load(tile.contentUrl, Tiles3DLoader);
    const table = await featureTable(tile.contentUrl);
    const n = content.pointCount;
    const positions = content.attributes?.positions?.value ?? content.attributes?.positions;
    const colors = content.attributes?.colors?.value ?? content.attributes?.colors;
    if (n !== table.POINTS_LENGTH) problems.push(`${name}: loaders.gl read ${n} points, the file says ${table.POINTS_LENGTH}`);
    if (!positions || positions.length !== 3 * table.POINTS_LENGTH)
      problems.push(`${name}: ${positions?.length ?? 0} position values for ${table.POINTS_LENGTH} points`);
    if (table.RGB && (!colors || colors.length !== 3 * table.POINTS_LENGTH))
      problems.push(`${name}: ${colors?.length ?? 0} colour values for ${table.POINTS_LENGTH} points`);
    if (!Array.isArray(table.RTC_CENTER) || table.RTC_CENTER.length !== 3) problems.push(`${name}: no RTC_CENTER`);
    counts.points += n;
    if (!children.length) counts.leafPoints += n;
  }
  if (!children.length) counts.leaves++;
  for (const child of children) await walk(child, depth + 1);
}

const server = await serveFolders([['/', dir]]);
try {
  const tileset = await load(`${server.url}/tileset.json`, Tiles3DLoader);
  if (tileset.asset?.version !== '1.0') problems.push(`asset.version is ${tileset.asset?.version}, not 1.0`);
  // loaders.gl turns refine into its own enum: the file's own word is checked.
  const raw = await (await fetch(`${server.url}/tileset.json`)).json();
  if (raw.root?.refine !== 'REPLACE') problems.push(`the root refines by ${raw.root?.refine}, not REPLACE`);
  counts.crs = tileset.asset?.extras?.crs ?? null;
  await walk(tileset.root, 0);
} catch (e) {
  problems.push(`loading failed: ${e?.message ?? e}`);
} finally {
  await server.close();
}
if (counts.leafPoints !== expected) problems.push(`the leaves hold ${counts.leafPoints} points, expected ${expected}`);
const ok = problems.length === 0;
console.log(JSON.stringify({ ok, ...counts, problems: problems.slice(0, 10) }));
process.exit(ok ? 0 : 1);
