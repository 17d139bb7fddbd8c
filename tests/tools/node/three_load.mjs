// tests/tools/node/three_load.mjs FILE.glb NODE_MODULES FRAMES DURATION K FRAME_K.obj: loads
// FILE with three.js's GLTFLoader.parse in node and checks the morph-target count (FRAMES), one
// animation lasting DURATION s, and frame K (base + morph target K, morphTargetsRelative) against
// the `v` lines of FRAME_K.obj (`mimetic play --time`): max |difference| < 1e-4 of the head size.
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

// The only polyfill node needs here: three's texture path names `self` (no textures are loaded).
globalThis.self ??= globalThis;

const [file, modules, framesArg, durationArg, kArg, objFile] = process.argv.slice(2);
const { GLTFLoader } = await import(
    pathToFileURL(path.join(path.resolve(modules), 'three/examples/jsm/loaders/GLTFLoader.js')).href);
const bytes = fs.readFileSync(file);
const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const gltf = await new Promise((resolve, reject) =>
    new GLTFLoader().parse(buffer, '', resolve, reject));

let failed = false;
const check = (ok, what) => { console.log(`${ok ? 'ok' : 'FAIL'}: ${what}`); if (!ok) failed = true; };
const meshes = [];
gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
check(meshes.length === 1, `one mesh (got ${meshes.length})`);
const mesh = meshes[0];
const geometry = mesh.geometry;
const targets = geometry.morphAttributes.position ?? [];
const frames = Number(framesArg), duration = Number(durationArg), k = Number(kArg);
check(targets.length === frames, `${frames} morph targets (got ${targets.length})`);
check(mesh.morphTargetInfluences?.length === frames, `${frames} morph target influences`);
check(gltf.animations.length === 1, `one animation (got ${gltf.animations.length})`);
const clip = gltf.animations[0];
check(Math.abs(clip.duration - duration) < 1e-6, `animation lasts ${duration} s (got ${clip.duration})`);
check(geometry.morphTargetsRelative === true, 'morph targets are relative (deltas)');

// Frame k: base + target k against the OBJ.
const obj = fs.readFileSync(objFile, 'utf8').split('\n').filter((l) => l.startsWith('v '))
    .map((l) => l.split(/\s+/).slice(1, 4).map(Number));
const base = geometry.attributes.position, delta = targets[k];
check(base.count === obj.length, `${obj.length} vertices (got ${base.count})`);
let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity], maxDiff = 0, maxMove = 0;
for (let v = 0; v < Math.min(base.count, obj.length); ++v) {
  for (let c = 0; c < 3; ++c) {
    const b = base.getComponent(v, c), p = b + delta.getComponent(v, c);
    lo[c] = Math.min(lo[c], obj[v][c]); hi[c] = Math.max(hi[c], obj[v][c]);
    maxDiff = Math.max(maxDiff, Math.abs(p - obj[v][c]));
    maxMove = Math.max(maxMove, Math.abs(obj[v][c] - b));
  }
}
const size = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
check(maxDiff < 1e-4 * size, `frame ${k}: max |three - mimetic play --time| = ${maxDiff} < 1e-4 * ${size}`);
check(maxMove > 1e-3 * size, `frame ${k} moves (max ${maxMove}) so the comparison means something`);
process.exit(failed ? 1 : 0);
