// The page cesium_tileset.mjs bundles (esbuild) and opens: CesiumJS loads /tileset/tileset.json with nothing from
// the network (no globe, imagery, terrain, sky or Ion token), refines to every leaf, then draws each point's
// `classification` with a custom shader, so the values Cesium read from the tiles' metadata come back as pixel
// colours. Results land in window.__cesium.
import {
  Cartographic, CesiumWidget, Cesium3DTileset, CustomShader, HeadingPitchRange, LightingModel, Math as M,
} from '@cesium/engine';

const out = { done: false, cesium: globalThis.CESIUM_VERSION, tileFailures: [] };
window.__cesium = out;
const frames = (n) => new Promise((resolve) => {
  const step = () => (n-- > 0 ? requestAnimationFrame(step) : resolve());
  step();
});
const tiles = (tile, list = []) => (list.push(tile), tile.children.forEach((c) => tiles(c, list)), list);
// Model and its scene graph are not public API, but they are where Cesium keeps what it parsed from a tile.
const primitives = (t) => t.content._model.sceneGraph.components.nodes.flatMap((n) => n.primitives);

// Classification c comes back as red = (c % 16) * 16 + 8, green = floor(c / 16) * 16 + 8 and blue 255: steps of 16
// survive rounding. A custom shader is the one way Cesium exposes per-point property attributes of glb tiles (its
// styles read them only from .pnts); the UNLIT path converts linear to sRGB on output, so the shader undoes that.
const classShader = new CustomShader({
  lightingModel: LightingModel.UNLIT,
  fragmentShaderText: `
    void fragmentMain(FragmentInput fsInput, inout czm_modelMaterial material) {
      float c = float(fsInput.metadata.classification);
      material.diffuse = czm_srgbToLinear(vec3(mod(c, 16.0) * 16.0 + 8.0, floor(c / 16.0) * 16.0 + 8.0, 255.0) / 255.0);
    }`,
});

// CesiumJS 1.139 and later (CustomShaderPipelineStage's getAllPropertyIds) look up the property table of every
// feature ID set and throw on a set without one, which EXT_mesh_features allows and megavox's glb tiles have
// (classification as feature IDs, the properties as property attributes). An empty table under the key
// `undefined` lets the shader build and adds no property. Returns whether the tile needed it.
function allowFeatureIdsWithoutTable(tile) {
  if (!primitives(tile).some((p) => p.featureIds.some((f) => f.propertyTableId === undefined))) return false;
  tile.content._model.structuralMetadata.propertyTables.undefined = { class: { properties: {} } };
  return true;
}

function classesDrawn(canvas) {
  const copy = Object.assign(document.createElement('canvas'), { width: canvas.width, height: canvas.height });
  const g = copy.getContext('2d');
  g.drawImage(canvas, 0, 0);
  const d = g.getImageData(0, 0, copy.width, copy.height).data;
  const pixels = {};
  for (let i = 0; i < d.length; i += 4) {
    if (d[i + 2] < 250) continue;  // the background is black; every point the shader drew has blue 255
    const c = (d[i] >> 4) + 16 * (d[i + 1] >> 4);
    pixels[c] = (pixels[c] ?? 0) + 1;
  }
  return pixels;
}

async function run() {
  const container = Object.assign(document.createElement('div'), { style: 'width:640px;height:480px' });
  document.body.appendChild(container);
  const widget = new CesiumWidget(container, {
    baseLayer: false, globe: false, skyBox: false, skyAtmosphere: false, requestRenderMode: false,
    msaaSamples: 1, contextOptions: { webgl: { preserveDrawingBuffer: true } },
  });
  widget.scene.fog.enabled = false;  // it would shade the colours the custom shader encodes values in
  // Refine everything in view to the leaves, at once: no deferral of peripheral or distant tiles.
  const tileset = await Cesium3DTileset.fromUrl('/tileset/tileset.json', {
    maximumScreenSpaceError: 0, dynamicScreenSpaceError: false, foveatedScreenSpaceError: false,
    cullRequestsWhileMoving: false,
  });
  tileset.tileFailed.addEventListener((e) => out.tileFailures.push(`${e.url}: ${e.message}`));
  widget.scene.primitives.add(tileset);
  const sphere = tileset.boundingSphere;
  widget.camera.viewBoundingSphere(sphere, new HeadingPitchRange(0, -M.PI_OVER_FOUR, sphere.radius * 2.5));
  // tilesLoaded speaks of the tiles the last frame selected; every leaf must have arrived too.
  const all = tiles(tileset.root);
  const leaves = all.filter((t) => t.children.length === 0);
  const deadline = performance.now() + 60_000;
  do await frames(1);
  while (!(tileset.tilesLoaded && leaves.every((t) => t.contentReady)) && !out.tileFailures.length &&
         performance.now() < deadline);
  out.tilesLoaded = tileset.tilesLoaded;

  const loaded = all.filter((t) => t.contentReady);
  out.tiles = all.length;
  out.tilesWithContent = loaded.length;
  out.leaves = leaves.length;
  out.leavesLoaded = leaves.filter((t) => t.contentReady).length;
  out.points = leaves.reduce((n, t) => n + (t.contentReady ? t.content.pointsLength : 0), 0);
  const g = Cartographic.fromCartesian(sphere.center);
  out.centre = g ? { lat: M.toDegrees(g.latitude), lon: M.toDegrees(g.longitude), height: g.height } : null;

  // What Cesium parsed: EXT_mesh_features feature ID sets (by label) and EXT_structural_metadata property
  // attributes in glb; for .pnts, the batch table turned into property attributes.
  out.featureIdLabels = [...new Set(loaded.flatMap((t) => primitives(t).flatMap((p) => p.featureIds.map((f) => f.label))))];
  const attrs = loaded.flatMap((t) => t.content._model.structuralMetadata?.propertyAttributes ?? []);
  out.metadataProperties = [...new Set(attrs.flatMap((a) => Object.keys(a.properties)))].sort();
  const withClass = attrs.find((a) => a.getProperty('classification'));
  out.classification = withClass ? { attribute: withClass.getProperty('classification').attribute,
                                     componentType: withClass.class.properties.classification.componentType } : null;
  if (withClass) {
    out.tilesPatchedForShader = loaded.filter(allowFeatureIdsWithoutTable).length;
    tileset.customShader = classShader;
    await frames(5);
    out.classesDrawn = classesDrawn(widget.canvas);
  }
  out.done = true;
}

run().catch((e) => {
  out.error = String(e?.stack ?? e);
  out.done = true;
});
