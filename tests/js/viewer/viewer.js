// Loads /tileset/tileset.json with 3d-tiles-renderer, frames its bounding sphere, renders until every tile it
// wants is loaded, then sets window.__render = { done: true, ... } for render_tileset.mjs to screenshot.
import * as THREE from 'three';
import { TilesRenderer } from '3d-tiles-renderer';

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

let framed = false, settled = 0, frames = 0, rootFailed = false;
function frame() {
  const sphere = new THREE.Sphere();
  if (!tiles.getBoundingSphere(sphere)) return false;
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
