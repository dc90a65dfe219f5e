// Loads /tileset/tileset.json with 3d-tiles-renderer, frames its bounding sphere, renders until every tile it
// wants is loaded, then sets window.__render = { done: true, ... } for render_tileset.mjs to screenshot.
// glTF tiles (3D Tiles 1.1) load through GLTFExtensionsPlugin with three's MeshoptDecoder registered
// (EXT_meshopt_compression); a tileset placed on the globe is viewed in its local frame.
import * as THREE from 'three';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { TilesRenderer } from '3d-tiles-renderer';
import { GLTFExtensionsPlugin } from '/node_modules/3d-tiles-renderer/build/index.plugins.js';

const params = new URLSearchParams(location.search);
const width = Number(params.get('width') ?? 640), height = Number(params.get('height') ?? 480);
const clear = new THREE.Color(params.get('clear') ?? '#203040');

const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(width, height);
renderer.setClearColor(clear, 1);
document.body.appendChild(renderer.domElement);

const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(45, width / height, 1, 1e7);
const tiles = new TilesRenderer('/tileset/tileset.json');
tiles.registerPlugin(new GLTFExtensionsPlugin({ meshoptDecoder: MeshoptDecoder }));
tiles.errorTarget = 2;  // refine down to the leaves at this size
tiles.setCamera(camera);
tiles.setResolutionFromRenderer(camera, renderer);
scene.add(tiles.group);
// Points of 3 pixels whatever the distance: the tileset's units are the input's (metres, say).
tiles.addEventListener('load-model', ({ scene: model }) => {
  model.traverse((o) => {
    if (o.isPoints) {
      o.material.size = 3;
      o.material.sizeAttenuation = false;
    }
  });
});

// A tileset placed on the globe (a root transform to EPSG:4978): the group undoes that transform, so the scene
// is the tileset's local frame again (z up) and the camera presets below apply.
function unplace() {
  const t = tiles.root?.transform;
  if (!t || tiles.rootTileset?.asset?.extras?.placement !== 'EPSG:4978') return;
  new THREE.Matrix4().fromArray(t).invert().decompose(tiles.group.position, tiles.group.quaternion, tiles.group.scale);
  tiles.group.updateMatrixWorld(true);
}

let framed = false, settled = 0, frames = 0, rootFailed = false;
function frame() {
  const sphere = new THREE.Sphere();
  if (!tiles.getBoundingSphere(sphere)) return false;
  unplace();
  sphere.applyMatrix4(tiles.group.matrixWorld);
  const zUp = tiles.rootTileset?.asset?.extras?.upAxis !== 'Y';
  camera.up.set(0, zUp ? 0 : 1, zUp ? 1 : 0);
  const view = zUp ? new THREE.Vector3(0.8, -1.2, 0.9) : new THREE.Vector3(0.8, 0.9, 1.2);
  const distance = sphere.radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  camera.position.copy(sphere.center).addScaledVector(view.normalize(), distance);
  camera.near = distance / 100;
  camera.far = distance * 3;
  camera.updateProjectionMatrix();
  camera.lookAt(sphere.center);
  return true;
}

function visiblePoints() {
  let n = 0;
  tiles.group.traverseVisible((o) => { if (o.isPoints) n += o.geometry.getAttribute('position').count; });
  return n;
}

function tick() {
  frames++;
  if (!framed) framed = frame();
  camera.updateMatrixWorld();
  tiles.update();
  renderer.render(scene, camera);
  const loading = tiles.stats.queued + tiles.stats.downloading + tiles.stats.parsing;
  settled = framed && loading === 0 && tiles.stats.loaded > 0 ? settled + 1 : 0;
  if (settled >= 10 || tiles.stats.failed > 0 || rootFailed) {
    window.__render = { done: true, frames, loaded: tiles.stats.loaded, failed: tiles.stats.failed + rootFailed,
                        visiblePoints: visiblePoints() };
    return;
  }
  requestAnimationFrame(tick);
}
tiles.addEventListener('load-error', ({ tile, error, url }) => {
  console.error(`load error ${url}: ${error}`);
  if (!tile) rootFailed = true;  // the tileset itself: nothing will come
});
requestAnimationFrame(tick);
