// tests/tools/node/three_load.mjs FILE.glb NODE_MODULES TARGETS DURATION T FRAME.obj: loads
// FILE with three.js's GLTFLoader.parse in node and checks the morph-target count (TARGETS), one
// animation lasting DURATION s, and the pose at time T (three's AnimationMixer sets the
// morph-target influences; base + sum of influence x target, morphTargetsRelative) against the
// `v` lines of FRAME.obj (`mimetic play --time T`): max |difference| < 1e-4 of the head size.
import { check, exitStatus, loadGlb, objVertices, threeModule } from './gltf_node.mjs';

const [file, modules, targetsArg, durationArg, timeArg, objFile] = process.argv.slice(2);
const { AnimationMixer } = await threeModule(modules, 'three/build/three.module.js');
const { gltf, mesh } = await loadGlb(file, modules);
const geometry = mesh.geometry;
const targets = geometry.morphAttributes.position ?? [];
const count = Number(targetsArg), duration = Number(durationArg), time = Number(timeArg);
check(targets.length === count, `${count} morph targets (got ${targets.length})`);
check(mesh.morphTargetInfluences?.length === count, `${count} morph target influences`);
check(gltf.animations.length === 1, `one animation (got ${gltf.animations.length})`);
const clip = gltf.animations[0];
check(Math.abs(clip.duration - duration) < 1e-6, `animation lasts ${duration} s (got ${clip.duration})`);
check(geometry.morphTargetsRelative === true, 'morph targets are relative (deltas)');

// The pose at `time`: the mixer's influences times the targets, plus the base, against the OBJ.
const mixer = new AnimationMixer(gltf.scene);
mixer.clipAction(clip).play();
mixer.setTime(time);
const w = mesh.morphTargetInfluences;
const obj = objVertices(objFile);
const base = geometry.attributes.position;
check(base.count === obj.length, `${obj.length} vertices (got ${base.count})`);
let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity], maxDiff = 0, maxMove = 0;
for (let v = 0; v < Math.min(base.count, obj.length); ++v) {
  for (let c = 0; c < 3; ++c) {
    const b = base.getComponent(v, c);
    let p = b;
    for (let i = 0; i < targets.length; ++i) if (w[i] !== 0) p += w[i] * targets[i].getComponent(v, c);
    lo[c] = Math.min(lo[c], obj[v][c]); hi[c] = Math.max(hi[c], obj[v][c]);
    maxDiff = Math.max(maxDiff, Math.abs(p - obj[v][c]));
    maxMove = Math.max(maxMove, Math.abs(obj[v][c] - b));
  }
}
const size = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
check(maxDiff < 1e-4 * size, `t = ${time}: max |three - mimetic play --time| = ${maxDiff} < 1e-4 * ${size}`);
check(maxMove > 1e-3 * size, `t = ${time} moves (max ${maxMove}) so the comparison means something`);
process.exit(exitStatus());
