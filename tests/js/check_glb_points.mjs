#!/usr/bin/env node
// An independent reader of megavox's glb point tiles (3D Tiles 1.1 content): loaders.gl's GLTFLoader (not
// megavox code) parses FILE.glb, decodes EXT_meshopt_compression buffer views with its own meshopt decoder
// (gltf.decompressMeshes), and postProcessGLTF turns every accessor into a typed array. Checks that each
// attribute holds count * components values, that POSITION's decoded values lie within its accessor min/max,
// that every property attribute of EXT_structural_metadata names an attribute of the primitive and a property
// of its class, and that EXT_mesh_features' feature IDs attribute holds featureCount distinct IDs.
// Prints one JSON line: points, attributes, extensions, classes {class: [properties]}, propertyAttributes,
// featureIds, and the first point's decoded values; exits 1 on any problem, 2 on bad arguments.
//   node check_glb_points.mjs FILE.glb
import { readFile } from 'node:fs/promises';
import { parse } from '@loaders.gl/core';
import { GLTFLoader, postProcessGLTF } from '@loaders.gl/gltf';

const [file] = process.argv.slice(2);
if (!file) {
  console.error('usage: node check_glb_points.mjs FILE.glb');
  process.exit(2);
}

const components = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 };
const problems = [];
const bytes = await readFile(file);
const gltf = await parse(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), GLTFLoader, {
  gltf: { loadBuffers: true, decompressMeshes: true, loadImages: false, normalize: true },
});
// What the file declared, before loaders.gl removes the extensions it has decoded (meshopt).
const declared = JSON.parse(
  new TextDecoder().decode(bytes.subarray(20, 20 + bytes.readUInt32LE(12))),
);
const post = postProcessGLTF(gltf);
const meshes = post.meshes ?? [];
if (meshes.length !== 1 || meshes[0].primitives.length !== 1) problems.push('not one mesh with one primitive');
const primitive = meshes[0]?.primitives?.[0] ?? { attributes: {} };
if ((primitive.mode ?? 4) !== 0) problems.push(`primitive mode ${primitive.mode}, not 0 (POINTS)`);

const attributes = {};
let points = -1;
for (const [name, accessor] of Object.entries(primitive.attributes)) {
  const n = components[accessor.type];
  const values = accessor.value;
  attributes[name] = { componentType: accessor.componentType, type: accessor.type, count: accessor.count };
  if (points < 0) points = accessor.count;
  if (accessor.count !== points) problems.push(`${name}: ${accessor.count} elements, POSITION has ${points}`);
  if (!values || values.length !== accessor.count * n)
    problems.push(`${name}: ${values?.length ?? 0} decoded values for ${accessor.count} x ${accessor.type}`);
}
const position = primitive.attributes.POSITION;
if (!position) problems.push('no POSITION');
else if (position.value) {
  for (let i = 0; i < position.value.length; ++i) {
    const v = position.value[i], a = i % 3;
    if (v < position.min[a] || v > position.max[a]) {
      problems.push(`POSITION value ${i} = ${v} outside accessor min/max`);
      break;
    }
  }
}

const metadata = declared.extensions?.EXT_structural_metadata;
const classes = {};
for (const [id, cls] of Object.entries(metadata?.schema?.classes ?? {})) classes[id] = Object.keys(cls.properties ?? {});
const propertyAttributes = (metadata?.propertyAttributes ?? []).map((pa) => ({
  class: pa.class,
  properties: Object.fromEntries(Object.entries(pa.properties).map(([p, v]) => [p, v.attribute])),
}));
for (const pa of propertyAttributes) {
  if (!classes[pa.class]) problems.push(`property attribute of unknown class ${pa.class}`);
  for (const [p, attribute] of Object.entries(pa.properties)) {
    if (!classes[pa.class]?.includes(p)) problems.push(`property ${p} is not in class ${pa.class}`);
    if (!primitive.attributes[attribute]) problems.push(`property ${p}: no attribute ${attribute} in the primitive`);
  }
}
// The feature IDs as the _FEATURE_ID_n attribute decodes them. loaders.gl's own EXT_mesh_features result
// (featureId.data) is reported beside them, unchecked: loaders.gl 4.5 decodes EXT_mesh_features before
// EXT_meshopt_compression, so for a compressed file it reads the still-empty fallback buffer (all zeros).
const featureIds = (primitive.extensions?.EXT_mesh_features?.featureIds ?? []).map((f) => {
  const ids = primitive.attributes[`_FEATURE_ID_${f.attribute}`]?.value;
  return {
    featureCount: f.featureCount,
    attribute: f.attribute,
    label: f.label,
    decoded: ids?.length ?? 0,
    distinct: ids ? new Set(ids).size : 0,
    loadersGlDataDistinct: f.data ? new Set(f.data).size : null,
  };
});
for (const f of featureIds) {
  if (f.decoded !== points) problems.push(`feature IDs ${f.label}: ${f.decoded} decoded for ${points} points`);
  if (f.distinct !== f.featureCount) problems.push(`feature IDs ${f.label}: ${f.distinct} distinct, featureCount ${f.featureCount}`);
}

const first = Object.fromEntries(
  Object.entries(primitive.attributes).map(([name, a]) => [name, Array.from(a.value?.subarray(0, components[a.type]) ?? [])]),
);
console.log(JSON.stringify({
  points,
  attributes,
  extensionsUsed: declared.extensionsUsed,
  extensionsRequired: declared.extensionsRequired,
  classes,
  propertyAttributes,
  featureIds,
  node: { translation: post.nodes?.[0]?.translation, rotation: post.nodes?.[0]?.rotation, scale: post.nodes?.[0]?.scale },
  first,
  problems,
}));
process.exit(problems.length ? 1 : 0);
