// tests/tools/node/three_blendshapes.mjs FILE.glb NODE_MODULES SHAPE FRAME.obj: loads FILE (from
// `mimetic export-blendshapes`) with three.js's GLTFLoader in node and checks that
// morphTargetDictionary holds exactly Apple's 52 ARKit names (the list below, from Apple's
// ARFaceAnchor.BlendShapeLocation documentation) with 52 targets, then that the base plus target
// SHAPE at influence 1 matches the `v` lines of FRAME.obj (`mimetic eval` at that shape's
// activations): max |difference| < 1e-4 of the head size.
import { check, exitStatus, loadGlb, objVertices } from './gltf_node.mjs';

const ARKIT = [
  'eyeBlinkLeft', 'eyeLookDownLeft', 'eyeLookInLeft', 'eyeLookOutLeft', 'eyeLookUpLeft',
  'eyeSquintLeft', 'eyeWideLeft', 'eyeBlinkRight', 'eyeLookDownRight', 'eyeLookInRight',
  'eyeLookOutRight', 'eyeLookUpRight', 'eyeSquintRight', 'eyeWideRight', 'jawForward', 'jawLeft',
  'jawRight', 'jawOpen', 'mouthClose', 'mouthFunnel', 'mouthPucker', 'mouthLeft', 'mouthRight',
  'mouthSmileLeft', 'mouthSmileRight', 'mouthFrownLeft', 'mouthFrownRight', 'mouthDimpleLeft',
  'mouthDimpleRight', 'mouthStretchLeft', 'mouthStretchRight', 'mouthRollLower', 'mouthRollUpper',
  'mouthShrugLower', 'mouthShrugUpper', 'mouthPressLeft', 'mouthPressRight', 'mouthLowerDownLeft',
  'mouthLowerDownRight', 'mouthUpperUpLeft', 'mouthUpperUpRight', 'browDownLeft', 'browDownRight',
  'browInnerUp', 'browOuterUpLeft', 'browOuterUpRight', 'cheekPuff', 'cheekSquintLeft',
  'cheekSquintRight', 'noseSneerLeft', 'noseSneerRight', 'tongueOut',
];

const [file, modules, shape, objFile] = process.argv.slice(2);
const { mesh } = await loadGlb(file, modules);
const dict = mesh.morphTargetDictionary ?? {};
const targets = mesh.geometry.morphAttributes.position ?? [];
check(ARKIT.length === 52, 'the reference list has 52 names');
check(targets.length === 52, `52 morph targets (got ${targets.length})`);
check(Object.keys(dict).length === 52, `52 names in morphTargetDictionary (got ${Object.keys(dict).length})`);
ARKIT.forEach((name, i) => {
  if (dict[name] !== i) check(false, `morphTargetDictionary["${name}"] is ${dict[name]}, expected ${i}`);
});
check(ARKIT.every((name, i) => dict[name] === i), 'every ARKit name at its index, in Apple\'s order');

const t = dict[shape];
const obj = objVertices(objFile);
const base = mesh.geometry.attributes.position;
check(base.count === obj.length, `${obj.length} vertices (got ${base.count})`);
const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
let maxDiff = 0, maxMove = 0;
for (let v = 0; v < Math.min(base.count, obj.length); ++v)
  for (let c = 0; c < 3; ++c) {
    const b = base.getComponent(v, c), p = b + targets[t].getComponent(v, c);
    lo[c] = Math.min(lo[c], obj[v][c]); hi[c] = Math.max(hi[c], obj[v][c]);
    maxDiff = Math.max(maxDiff, Math.abs(p - obj[v][c]));
    maxMove = Math.max(maxMove, Math.abs(obj[v][c] - b));
  }
const size = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
check(maxDiff < 1e-4 * size, `${shape} at 1: max |three - mimetic eval| = ${maxDiff} < 1e-4 * ${size}`);
check(maxMove > 1e-3 * size, `${shape} moves (max ${maxMove}) so the comparison means something`);
process.exit(exitStatus());
