// Time three.js takes to parse .glb files (GLTFLoader with its MeshoptDecoder, as the run
// report's viewer loads character.glb): median over RUNS (default 11) of reading the file and of
// GLTFLoader.parseAsync on its bytes, files interleaved run by run.
// Usage: RUNS=11 node tests/benchmarks/three_load.mjs THREE_DIR FILE...
//   THREE_DIR holds node_modules/three (scripts/vendor_three.sh THREE_DIR installs it).
import fs from 'fs';
import path from 'path';
import {performance} from 'perf_hooks';

const [threeDir, ...files] = process.argv.slice(2);
if (!threeDir || files.length === 0) {
  console.error('usage: node three_load.mjs THREE_DIR FILE...');
  process.exit(2);
}
const three = path.resolve(threeDir, 'node_modules', 'three');
const {GLTFLoader} = await import(path.join(three, 'examples/jsm/loaders/GLTFLoader.js'));
const {MeshoptDecoder} = await import(path.join(three, 'examples/jsm/libs/meshopt_decoder.module.js'));
await MeshoptDecoder.ready;
const loader = new GLTFLoader();
loader.setMeshoptDecoder(MeshoptDecoder);
const runs = Number(process.env.RUNS || 11);
const median = (a) => a.slice().sort((x, y) => x - y)[a.length >> 1];
const times = Object.fromEntries(files.map((f) => [f, {read: [], parse: [], targets: 0}]));
for (let r = 0; r < runs; ++r)
  for (const file of files) {
    const t0 = performance.now();
    const bytes = fs.readFileSync(file);
    const t1 = performance.now();
    const gltf = await loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength), '');
    const t2 = performance.now();
    gltf.scene.traverse((o) => { if (o.morphTargetInfluences) times[file].targets = o.morphTargetInfluences.length; });
    times[file].read.push(t1 - t0);
    times[file].parse.push(t2 - t1);
  }
for (const [file, t] of Object.entries(times))
  console.log(`${file}: ${fs.statSync(file).size} bytes, ${t.targets} morph targets, read ${median(t.read).toFixed(1)} ms, ` +
              `parse ${median(t.parse).toFixed(1)} ms (median of ${runs})`);
