// Checks a run's animation.glb the way browser viewers read it: the Khronos glTF validator, then
// three.js's GLTFLoader (the loader of most web viewers) playing the animation with an
// AnimationMixer, the morphed particles compared with positions.npy (docs/exports.md).
//
//   clothsim run paper-fig5 --duration 0.5 --export gltf-animation --render none --out out/fig5
//   npm install --prefix ~/glb-check three gltf-validator      # once; not a build dependency
//   (cd ~/glb-check && node /path/to/clothsim/scripts/check-animation-in-threejs.mjs /path/to/out/fig5)
//
// The packages are found from the working directory (where npm installed them), not from this
// file's folder, so the repository needs no node_modules. Runs in Node without a GPU: it checks
// the file and the animation's weights, not WebGL's limits (docs/exports.md, "Viewers").
// Exits 1 on a validator error or a difference above float32 rounding of the coordinates.
import fs from 'fs';
import path from 'path';
import { createRequire } from 'module';
import { pathToFileURL } from 'url';

const require = createRequire(path.join(process.cwd(), '/'));
const threeFolder = path.dirname(require.resolve('three'));
// The loader imports 'three' as the ES module build: import the same file, so both share it.
const THREE = await import(pathToFileURL(path.join(threeFolder, 'three.module.js')).href);
const { GLTFLoader } = await import(pathToFileURL(require.resolve('three/examples/jsm/loaders/GLTFLoader.js')).href);
const validator = (await import(pathToFileURL(require.resolve('gltf-validator')).href)).default;

const folder = process.argv[2];
const glb = fs.readFileSync(path.join(folder, 'animation.glb'));
const report = await validator.validateBytes(new Uint8Array(glb), { maxIssues: 20 });
console.log(`glTF validator ${report.validatorVersion}: ${report.issues.numErrors} errors, ` +
            `${report.issues.numWarnings} warnings, ${report.issues.numInfos} infos`);
for (const message of report.issues.messages) console.log(`  ${message.code} ${message.pointer}: ${message.message}`);

// positions.npy: float64 [frames, particles, 3], a version 1.0 header.
const npy = fs.readFileSync(path.join(folder, 'positions.npy'));
const headerLength = npy.readUInt16LE(8);
const [frames, particles] = npy.toString('latin1', 10, 10 + headerLength).match(/\((\d+), (\d+), 3\)/).slice(1).map(Number);
const positions = new Float64Array(npy.buffer.slice(npy.byteOffset + 10 + headerLength, npy.byteOffset + npy.length));
const fps = JSON.parse(fs.readFileSync(path.join(folder, 'summary.json')))['files']['animation.glb']['fps'];

const gltf = await new GLTFLoader().parseAsync(glb.buffer.slice(glb.byteOffset, glb.byteOffset + glb.length), '');
let mesh = null;
gltf.scene.traverse((object) => { if (object.isMesh) mesh = object; });
const clip = gltf.animations[0];
const mixer = new THREE.AnimationMixer(gltf.scene);
const action = mixer.clipAction(clip);
action.setLoop(THREE.LoopOnce, 1);
action.clampWhenFinished = true;  // else, at its end, the clip wraps to its first frame
action.play();
const base = mesh.geometry.attributes.position.array;
const targets = mesh.geometry.morphAttributes.position;
let worst = 0;
let scale = 0;
// The particles (the mesh's first vertices) at `time`, s, as three.js morphs them, against `expected`.
const compare = (time, expected) => {
  mixer.setTime(time);
  const weights = mesh.morphTargetInfluences;
  for (let i = 0; i < 3 * particles; ++i) {
    let x = base[i];
    for (let t = 0; t < weights.length; ++t) if (weights[t] !== 0) x += weights[t] * targets[t].array[i];
    worst = Math.max(worst, Math.abs(x - expected(i)));
    scale = Math.max(scale, Math.abs(expected(i)));
  }
};
const frame = (k) => (i) => positions[k * 3 * particles + i];
const middle = Math.floor(frames / 2);
// In time order: a LoopOnce action stops at its end.
for (const k of [0, 1, middle]) compare(k / fps, frame(k));
compare((middle + 0.5) / fps, (i) => 0.5 * (frame(middle)(i) + frame(middle + 1)(i)));
compare((frames - 1) / fps, frame(frames - 1));
console.log(`three.js r${THREE.REVISION} GLTFLoader: ${mesh.geometry.attributes.position.count} vertices, ` +
            `${targets.length} morph targets, clip '${clip.name}' of ${clip.duration.toFixed(4)} s ` +
            `(${frames} frames at ${fps} fps); at frames 0, 1, ${middle}, ${middle + 0.5}, ${frames - 1}: ` +
            `largest difference ${worst.toExponential(3)} m (coordinates up to ${scale.toPrecision(3)} m)`);
const tolerance = 1e-6 * Math.max(1, scale);
process.exit(report.issues.numErrors === 0 && targets.length === frames && worst <= tolerance ? 0 : 1);
