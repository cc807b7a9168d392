// The 3D viewer of the run report (pipelines/report.py inlines it, three.js and the .glb files):
// plays every animation of character.glb and of previews/animation.glb with three.js. What it
// loaded and how far it played is written to #viewer-status as JSON, for people and for the
// headless-browser test (tests/e2e/client_chromium.sh).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

const status = { loaded: [], errors: [], webgl: false, framesRendered: 0, playing: null, morphTargetsChanged: false };
const statusElement = document.getElementById('viewer-status');
const showStatus = () => { statusElement.textContent = JSON.stringify(status, null, 1); };

function bytesOf(id) {
  const text = document.getElementById(id).textContent.trim();
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

const container = document.getElementById('viewer');
const select = document.getElementById('viewer-clip');
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xf2f2f2);
scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 2.0));
const sun = new THREE.DirectionalLight(0xffffff, 2.0);
sun.position.set(3, 6, 4);
scene.add(sun);
scene.add(new THREE.GridHelper(20, 20, 0x999999, 0xcccccc));
const camera = new THREE.PerspectiveCamera(40, container.clientWidth / container.clientHeight, 0.05, 200);
camera.position.set(3.5, 2.0, 4.5);
let renderer = null;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setSize(container.clientWidth, container.clientHeight);
  container.appendChild(renderer.domElement);
  status.webgl = true;
} catch (error) {
  status.errors.push('WebGL: ' + error.message);
}
const controls = renderer ? new OrbitControls(camera, renderer.domElement) : null;
if (controls) controls.target.set(0, 0.9, 0);

const clips = [];  // {label, root, mixer, clip, mesh}
const loader = new GLTFLoader();
loader.setMeshoptDecoder(MeshoptDecoder);
let current = null;
let firstWeights = null;

function play(index) {
  for (const entry of clips) entry.root.visible = false;
  current = clips[index];
  if (!current) return;
  current.root.visible = true;
  current.mixer.stopAllAction();
  const action = current.mixer.clipAction(current.clip);
  action.setLoop(THREE.LoopRepeat, Infinity);
  action.play();
  status.playing = current.label;
  firstWeights = null;
}

async function load(id, label) {
  const bytes = bytesOf(id);
  const start = performance.now();
  await MeshoptDecoder.ready;
  const gltf = await loader.parseAsync(bytes, '');
  const parseMs = performance.now() - start;
  let mesh = null;
  gltf.scene.traverse((object) => { if (object.isMesh && !mesh) mesh = object; });
  const morphTargets = mesh && mesh.morphTargetInfluences ? mesh.morphTargetInfluences.length : 0;
  const normals = mesh ? Boolean(mesh.geometry.attributes.normal) : false;
  status.loaded.push({ file: label, morphTargets, animations: gltf.animations.length,
                       normals, flatShading: mesh ? Boolean(mesh.material.flatShading) : null,
                       vertexColors: mesh ? Boolean(mesh.material.vertexColors) : null,
                       fps: (gltf.scene.userData || {}).fps ?? null, bytes: bytes.byteLength,
                       parseMs: Math.round(parseMs) });
  scene.add(gltf.scene);
  gltf.scene.visible = false;
  const mixer = new THREE.AnimationMixer(gltf.scene);
  for (const clip of gltf.animations) {
    clips.push({ label: label + ': ' + clip.name, root: gltf.scene, mixer, clip, mesh });
    const option = document.createElement('option');
    option.value = String(clips.length - 1);
    option.textContent = label + ': ' + clip.name + ' (' + clip.duration.toFixed(2) + ' s)';
    select.appendChild(option);
  }
}

const timer = new THREE.Timer();
function frame(time) {
  timer.update(time);
  if (current) {
    current.mixer.update(Math.min(timer.getDelta(), 0.1));
    const weights = current.mesh && current.mesh.morphTargetInfluences;
    if (weights) {
      if (firstWeights === null) firstWeights = Array.from(weights);
      else if (weights.some((w, i) => Math.abs(w - firstWeights[i]) > 1e-6)) status.morphTargetsChanged = true;
    }
  }
  if (controls) controls.update();
  if (renderer) renderer.render(scene, camera);
  status.framesRendered += 1;
  showStatus();
  requestAnimationFrame(frame);
}

async function main() {
  for (const [id, label] of [['glb-character', 'character.glb'], ['glb-animation', 'animation.glb']]) {
    if (!document.getElementById(id)) continue;
    try {
      await load(id, label);
    } catch (error) {
      status.errors.push(label + ': ' + error.message);
    }
  }
  select.addEventListener('change', () => play(Number(select.value)));
  play(0);
  showStatus();
  requestAnimationFrame(frame);
}
main();
