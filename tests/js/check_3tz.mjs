// An independent reader of megavox serve's 3D Tiles archives (.3tz): loaders.gl (not megavox code) opens the
// archive through its @3dtilesIndex1@ index, reads tileset.json, walks every tile and parses every content it
// names (.pnts, or .glb through loaders.gl's GLTFLoader with its meshopt decoder); the leaves' points must add
// up to EXPECTED_LEAF_POINTS (refine REPLACE: the leaves are the whole cloud). Prints one JSON line; exits 1 on
// any problem, 2 on bad arguments.
//   node check_3tz.mjs FILE EXPECTED_LEAF_POINTS
import { readFile } from 'node:fs/promises';
import { parse } from '@loaders.gl/core';
import { Tiles3DArchiveFileLoader, Tiles3DLoader } from '@loaders.gl/3d-tiles';

const [file, expectedText] = process.argv.slice(2);
if (!file || !/^\d+$/.test(expectedText ?? '')) {
  console.error('usage: node check_3tz.mjs FILE EXPECTED_LEAF_POINTS');
  process.exit(2);
}
const bytes = await readFile(file);
const archive = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
// each file found by its path's MD5 in the archive's index, as a 3tz reader does
const entry = (path) => parse(archive.slice(0), Tiles3DArchiveFileLoader, { '3d-tiles-archive': { path } });

const counts = { tiles: 0, contents: 0, leafPoints: 0, expectedLeafPoints: Number(expectedText) };
const loadOptions = {
  '3d-tiles': { loadGLTF: true },
  gltf: { loadBuffers: true, decompressMeshes: true, loadImages: false, normalize: true },
};
// A .pnts's point count, or a .glb's POSITION count as loaders.gl decoded it.
const pointCount = (content) => content.pointCount ?? content.gltf?.meshes?.[0]?.primitives?.[0]?.attributes?.POSITION?.value?.length / 3;
async function walk(tile) {
  counts.tiles++;
  const uri = tile.content?.uri ?? tile.content?.url;
  if (uri) {
    counts.contents++;
    const content = await parse(await entry(uri), Tiles3DLoader, loadOptions);
    const n = pointCount(content);
    if (!(n > 0)) throw new Error(`${uri}: no points`);
    if (!tile.children?.length) counts.leafPoints += n;
  }
  for (const child of tile.children ?? []) await walk(child);
}
try {
  const tileset = JSON.parse(new TextDecoder().decode(await entry('tileset.json')));
  await walk(tileset.root);
  console.log(JSON.stringify(counts));
  if (counts.leafPoints !== counts.expectedLeafPoints) process.exit(1);
} catch (e) {
  console.error(`${file}: ${e.message}`);
  process.exit(1);
}
