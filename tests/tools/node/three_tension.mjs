// tests/tools/node/three_tension.mjs FILE.glb NODE_MODULES T TENSION.bin: loads a
// `mimetic play --fps F --out FILE.glb --tension` bake with three.js's GLTFLoader and checks
// the _TENSION attribute (docs/tension.md "Baking"): the base attribute is loaded (as
// `_tension`, VEC2, one pair per vertex, the neutral's (r - 1, eps) = (0, 0) up to 1e-5), three
// decodes every morph target's _TENSION accessor (one VEC2 per vertex), and the morphed pair at
// time T (three's AnimationMixer influences, base + sum of influence x target delta) equals
// TENSION.bin within 1e-5 + 1e-6: (r - 1, eps) per vertex as little-endian f32, written by an
// independent EvaluateJob at time T (tests/tools/bake_test.cpp's WriteTensionAt, ctest
// tools.bake_tension_reference). three morphs only positions, normals and colours, so the
// morph is computed here from the accessors, as docs/tension.md tells a three.js user to.
import fs from 'node:fs';
import { check, exitStatus, loadGlb, threeModule } from './gltf_node.mjs';

const [file, modules, timeArg, referenceFile] = process.argv.slice(2);
const { AnimationMixer } = await threeModule(modules, 'three/build/three.module.js');
const { gltf, mesh } = await loadGlb(file, modules);
const geometry = mesh.geometry;
const base = geometry.attributes._tension;
const count = geometry.attributes.position.count;
check(base !== undefined, 'the base _TENSION attribute is loaded (as geometry.attributes._tension)');
if (!base) process.exit(exitStatus());
check(base.itemSize === 2 && base.count === count, `_tension: ${count} VEC2 (got ${base.count} x ${base.itemSize})`);
let neutral = 0;
for (let i = 0; i < base.count; ++i)
  neutral = Math.max(neutral, Math.abs(base.getX(i)), Math.abs(base.getY(i)));
check(neutral <= 1e-5, `the neutral's (r - 1, eps) is (0, 0) up to 1e-5 (max |.| ${neutral})`);

// The targets' _TENSION deltas, through three's own accessor decoding.
const prim = gltf.parser.json.meshes[0].primitives[0];
const targets = prim.targets ?? [];
check(targets.length === (geometry.morphAttributes.position ?? []).length,
      `${targets.length} targets, as many as three's position morphs`);
const deltas = [];
for (const [i, t] of targets.entries()) {
  if (t._TENSION === undefined) { check(false, `target ${i} has _TENSION`); continue; }
  const a = await gltf.parser.getDependency('accessor', t._TENSION);
  if (a.itemSize !== 2 || a.count !== count) check(false, `target ${i}: ${count} VEC2 (got ${a.count} x ${a.itemSize})`);
  deltas.push(a);
}
check(deltas.length === targets.length, `every target's _TENSION decoded by three (${deltas.length})`);

// The morphed pair at `time` against the independent EvaluateJob's.
const mixer = new AnimationMixer(gltf.scene);
mixer.clipAction(gltf.animations[0]).play();
mixer.setTime(Number(timeArg));
const w = mesh.morphTargetInfluences;
const ref = fs.readFileSync(referenceFile);
check(ref.length === 8 * count, `the reference holds ${count} pairs (${ref.length} bytes)`);
let worst = 0, most = 0;
for (let v = 0; v < Math.min(count, ref.length / 8); ++v) {
  for (let c = 0; c < 2; ++c) {
    let x = c === 0 ? base.getX(v) : base.getY(v);
    for (let i = 0; i < deltas.length; ++i)
      if (w[i] !== 0) x += w[i] * (c === 0 ? deltas[i].getX(v) : deltas[i].getY(v));
    const want = ref.readFloatLE(8 * v + 4 * c);
    worst = Math.max(worst, Math.abs(x - want));
    most = Math.max(most, Math.abs(want));
  }
}
check(worst < 1e-5 + 1e-6, `t = ${timeArg}: max |three's morphed _TENSION - EvaluateJob's (r - 1, eps)| = ${worst}`);
check(most > 1e-3, `t = ${timeArg} strains the skin (max |r - 1|, eps = ${most}) so the comparison means something`);
process.exit(exitStatus());
