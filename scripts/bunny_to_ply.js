#!/usr/bin/env node
// Converts the npm package `bunny` (exports {positions: [[x,y,z],...], cells: [[a,b,c],...]}) to a binary
// little-endian PLY: float x,y,z; list uchar int vertex_indices; a comment naming the source.
//   node scripts/bunny_to_ply.js <path to node_modules/bunny> <out.ply>
// Writes a temporary file beside <out.ply> and renames it on success, so a failed run leaves no partial file.
'use strict';

const fs = require('fs');
const path = require('path');

function fail(message) {
  process.stderr.write(`bunny_to_ply: ${message}\n`);
  process.exit(1);
}

function loadPackage(dir) {
  const root = path.resolve(dir);
  let mesh;
  try {
    mesh = require(root);
  } catch (e) {
    fail(`cannot load the bunny package from '${root}': ${e.message.split('\n')[0]}`);
  }
  let pkg = {};
  try {
    pkg = JSON.parse(fs.readFileSync(path.join(root, 'package.json'), 'utf8'));
  } catch (e) {
    // The version only goes into the comment; the mesh itself is what matters.
  }
  return { mesh, pkg };
}

// Throws with the first fault found: the PLY must be valid for any reader.
function checkMesh(mesh) {
  const { positions, cells } = mesh || {};
  if (!Array.isArray(positions) || !Array.isArray(cells)) throw new Error('the package exports no positions/cells arrays');
  if (positions.length === 0) throw new Error('the mesh has no vertices');
  if (positions.length > 0x7fffffff) throw new Error(`${positions.length} vertices do not fit PLY int indices`);
  positions.forEach((p, i) => {
    if (!Array.isArray(p) || p.length !== 3 || !p.every((x) => Number.isFinite(x) && Math.abs(x) <= 3.4028234663852886e38))
      throw new Error(`vertex ${i} is not 3 finite float coordinates: ${JSON.stringify(p)}`);
  });
  cells.forEach((c, i) => {
    if (!Array.isArray(c) || c.length < 3 || c.length > 255) throw new Error(`face ${i} does not have 3 to 255 indices`);
    for (const v of c)
      if (!Number.isInteger(v) || v < 0 || v >= positions.length)
        throw new Error(`face ${i} refers to vertex ${v} (only ${positions.length} vertices)`);
  });
}

function toPly(mesh, source) {
  const { positions, cells } = mesh;
  const header =
    'ply\nformat binary_little_endian 1.0\n' +
    `comment source: ${source}\n` +
    `element vertex ${positions.length}\nproperty float x\nproperty float y\nproperty float z\n` +
    `element face ${cells.length}\nproperty list uchar int vertex_indices\nend_header\n`;
  const faceBytes = cells.reduce((sum, c) => sum + 1 + 4 * c.length, 0);
  const body = Buffer.alloc(12 * positions.length + faceBytes);
  let at = 0;
  for (const p of positions) for (const x of p) at = body.writeFloatLE(x, at);
  for (const c of cells) {
    at = body.writeUInt8(c.length, at);
    for (const v of c) at = body.writeInt32LE(v, at);
  }
  return Buffer.concat([Buffer.from(header, 'ascii'), body]);
}

function main(argv) {
  if (argv.length !== 2) {
    process.stderr.write('usage: node scripts/bunny_to_ply.js <path to node_modules/bunny> <out.ply>\n');
    process.exit(2);
  }
  const [dir, out] = argv;
  const { mesh, pkg } = loadPackage(dir);
  try {
    checkMesh(mesh);
  } catch (e) {
    fail(`${path.resolve(dir)}: ${e.message}`);
  }
  const repo = pkg.repository && (pkg.repository.url || pkg.repository);
  const source = `npm package ${pkg.name || 'bunny'} ${pkg.version || '(unknown version)'}` +
    (typeof repo === 'string' ? ` (${repo})` : '') + ', converted by scripts/bunny_to_ply.js';
  const tmp = `${out}.tmp-${process.pid}`;
  try {
    fs.writeFileSync(tmp, toPly(mesh, source));
    fs.renameSync(tmp, out);
  } catch (e) {
    fs.rmSync(tmp, { force: true });
    fail(`cannot write '${out}': ${e.message}`);
  }
  process.stdout.write(`${out}: ${mesh.positions.length} vertices, ${mesh.cells.length} faces\n`);
}

main(process.argv.slice(2));
