#!/usr/bin/env node
// An independent reader of megavox's 3D Tiles output, 1.0 (.pnts) and 1.1 (.glb): loaders.gl (not megavox
// code) loads DIR/tileset.json over HTTP from a local server (as a client would, relative URIs and all), every
// tile is walked and every content loaded and parsed by Tiles3DLoader. For a .glb that is loaders.gl's
// GLTFLoader, EXT_meshopt_compression decoded by loaders.gl's own meshopt decoder (gltf.decompressMeshes).
// Each content's point count must be what the file itself says (a .pnts's POINTS_LENGTH, a .glb's POSITION
// accessor count, read from the file by hand), with 3 positions and, where it has colours, 3 colours per point;
// every per-point property (a .pnts batch table's, read with loaders.gl's Tile3DBatchTable; a .glb's
// EXT_structural_metadata property attributes) must hold one value per point; a .glb's EXT_mesh_features
// feature IDs attribute too. The leaves must add up to EXPECTED_LEAF_POINTS (refine REPLACE: the leaves are the
// whole cloud). VERSION, when given, is the asset.version the tileset must have. Prints one JSON line; exits 1
// on any mismatch, 2 on bad arguments.
//   node check_tileset.mjs DIR EXPECTED_LEAF_POINTS [VERSION]
import { load } from '@loaders.gl/core';
import { Tiles3DLoader, Tile3DBatchTable } from '@loaders.gl/3d-tiles';
import { serveFolders } from './static_server.mjs';

const [dir, expectedText, version] = process.argv.slice(2);
if (!dir || !/^\d+$/.test(expectedText ?? '')) {
  console.error('usage: node check_tileset.mjs DIR EXPECTED_LEAF_POINTS [VERSION]');
  process.exit(2);
}
const expected = Number(expectedText);
const loadOptions = {
  '3d-tiles': { loadGLTF: true },
  gltf: { loadBuffers: true, decompressMeshes: true, loadImages: false, normalize: true },
};

// What the file says of itself, read by hand: a .pnts's feature and batch table JSON (header: 7 uint32), a
// .glb's JSON chunk.
async function header(url) {
  const bytes = Buffer.from(await (await fetch(url)).arrayBuffer());
  const magic = bytes.subarray(0, 4).toString('latin1');
  if (magic === 'glTF') return { magic, gltf: JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString('utf8')) };
  const ftJson = bytes.readUInt32LE(12), ftBin = bytes.readUInt32LE(16), btJson = bytes.readUInt32LE(20);
  const featureTable = JSON.parse(bytes.subarray(28, 28 + ftJson).toString('utf8'));
  const at = 28 + ftJson + ftBin;
  const batchTable = btJson ? JSON.parse(bytes.subarray(at, at + btJson).toString('utf8')) : null;
  return { magic, featureTable, batchTable };
}

const problems = [];
const counts = { tiles: 0, contentTiles: 0, leaves: 0, leafPoints: 0, points: 0, expectedLeafPoints: expected,
                 properties: [], featureIdTiles: 0 };
const propertyNames = new Set();

function checkPnts(name, content, h) {
  const n = h.featureTable.POINTS_LENGTH;
  const colors = content.attributes?.colors?.value ?? content.attributes?.colors;
  if (h.featureTable.RGB && (!colors || colors.length !== 3 * n))
    problems.push(`${name}: ${colors?.length ?? 0} colour values for ${n} points`);
  if (!Array.isArray(h.featureTable.RTC_CENTER) || h.featureTable.RTC_CENTER.length !== 3) problems.push(`${name}: no RTC_CENTER`);
  if (h.batchTable) {
    // No BATCH_ID: the batch table holds one value per point (its length is POINTS_LENGTH).
    const table = new Tile3DBatchTable(content.batchTableJson, content.batchTableBinary, n);
    for (const property of Object.keys(h.batchTable)) {
      propertyNames.add(property);
      for (const i of [0, n - 1]) {
        const v = table.getProperty(i, property);
        if (typeof v !== 'number' || !Number.isFinite(v)) problems.push(`${name}: ${property} of point ${i} is ${v}`);
      }
    }
  }
  return n;
}

function checkGlb(name, content, h) {
  const primitive = h.gltf.meshes?.[0]?.primitives?.[0];
  const n = h.gltf.accessors?.[primitive?.attributes?.POSITION]?.count;
  const loaded = content.gltf?.meshes?.[0]?.primitives?.[0];
  if (!loaded) {
    problems.push(`${name}: loaders.gl found no primitive`);
    return 0;
  }
  const attributes = loaded.attributes ?? {};
  const components = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
  for (const [attribute, accessor] of Object.entries(attributes)) {
    const values = accessor.value;
    if (!values || values.length !== n * components[accessor.type])
      problems.push(`${name}: ${attribute} decodes to ${values?.length ?? 0} values for ${n} points`);
  }
  if (!attributes.POSITION) problems.push(`${name}: no POSITION`);
  if (primitive.attributes.COLOR_0 !== undefined && !attributes.COLOR_0) problems.push(`${name}: COLOR_0 not loaded`);
  const metadata = h.gltf.extensions?.EXT_structural_metadata;
  for (const pa of metadata?.propertyAttributes ?? []) {
    for (const [property, { attribute }] of Object.entries(pa.properties)) {
      propertyNames.add(property);
      if (!attributes[attribute]) problems.push(`${name}: property ${property}'s attribute ${attribute} not loaded`);
    }
  }
  const featureIds = primitive.extensions?.EXT_mesh_features?.featureIds ?? [];
  for (const f of featureIds) {
    // The _FEATURE_ID_n attribute as loaders.gl decodes it (its own EXT_mesh_features result reads the meshopt
    // fallback buffer before decompression, see check_glb_points.mjs).
    const ids = attributes[`_FEATURE_ID_${f.attribute}`]?.value;
    if (!ids || ids.length !== n) problems.push(`${name}: feature IDs ${f.label}: ${ids?.length ?? 0} for ${n} points`);
    else if (new Set(ids).size !== f.featureCount) problems.push(`${name}: feature IDs ${f.label}: featureCount ${f.featureCount}, ${new Set(ids).size} distinct`);
  }
  if (featureIds.length) counts.featureIdTiles++;
  return n;
}

async function walk(tile, depth) {
  counts.tiles++;
  const children = tile.children ?? [];
  if (tile.contentUrl) {
    counts.contentTiles++;
    const name = new URL(tile.contentUrl).pathname;
    const content = await load(tile.contentUrl, Tiles3DLoader, loadOptions);
    const h = await header(tile.contentUrl);
    const n = h.magic === 'glTF' ? checkGlb(name, content, h) : checkPnts(name, content, h);
    const got = h.magic === 'glTF'
      ? content.gltf?.meshes?.[0]?.primitives?.[0]?.attributes?.POSITION?.count
      : content.pointCount;
    const positions = h.magic === 'glTF'
      ? content.gltf?.meshes?.[0]?.primitives?.[0]?.attributes?.POSITION?.value
      : content.attributes?.positions?.value ?? content.attributes?.positions;
    if (got !== n) problems.push(`${name}: loaders.gl read ${got} points, the file says ${n}`);
    if (!positions || positions.length !== 3 * n) problems.push(`${name}: ${positions?.length ?? 0} position values for ${n} points`);
    counts.points += got ?? 0;
    if (!children.length) counts.leafPoints += got ?? 0;
  }
  if (!children.length) counts.leaves++;
  for (const child of children) await walk(child, depth + 1);
}

const server = await serveFolders([['/', dir]]);
try {
  const tileset = await load(`${server.url}/tileset.json`, Tiles3DLoader, loadOptions);
  counts.version = tileset.asset?.version;
  if (version && counts.version !== version) problems.push(`asset.version is ${counts.version}, not ${version}`);
  // loaders.gl turns refine into its own enum: the file's own words are checked.
  const raw = await (await fetch(`${server.url}/tileset.json`)).json();
  if (raw.root?.refine !== 'REPLACE') problems.push(`the root refines by ${raw.root?.refine}, not REPLACE`);
  if (raw.root?.transform && raw.root.transform.length !== 16) problems.push('the root transform is not 16 numbers');
  counts.crs = (tileset.asset?.extras?.crs ?? null) === null ? null : 'set';
  counts.placement = tileset.asset?.extras?.placement ?? null;
  await walk(tileset.root, 0);
} catch (e) {
  problems.push(`loading failed: ${e?.message ?? e}`);
} finally {
  await server.close();
}
if (counts.leafPoints !== expected) problems.push(`the leaves hold ${counts.leafPoints} points, expected ${expected}`);
counts.properties = [...propertyNames];
const ok = problems.length === 0;
console.log(JSON.stringify({ ok, ...counts, problems: problems.slice(0, 10) }));
process.exit(ok ? 0 : 1);
