// tests/tools/node/gltf_node.mjs: what the three.js node tests share. loadGlb(file, modules)
// parses FILE with three.js's GLTFLoader (from NODE_MODULES) and returns the glTF and its one
// mesh; check(ok, what) prints ok/FAIL and remembers a failure; exitStatus() is 1 after any.
import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

// The only polyfill node needs here: three's texture path names `self` (no textures are loaded).
globalThis.self ??= globalThis;

let failed = false;
export const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAIL'}: ${what}`);
  if (!ok) failed = true;
};
export const exitStatus = () => (failed ? 1 : 0);

export const threeModule = (modules, rel) =>
  import(pathToFileURL(path.join(path.resolve(modules), rel)).href);

export async function loadGlb(file, modules) {
  const { GLTFLoader } = await threeModule(modules, 'three/examples/jsm/loaders/GLTFLoader.js');
  const bytes = fs.readFileSync(file);
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const gltf = await new Promise((resolve, reject) =>
    new GLTFLoader().parse(buffer, '', resolve, reject));
  const meshes = [];
  gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
  check(meshes.length === 1, `one mesh (got ${meshes.length})`);
  return { gltf, mesh: meshes[0] };
}

// The `v` lines of an OBJ file as [x, y, z] arrays.
// The `v` lines of the OBJ's first object (mimetic writes the posed skin first; the sample
// head's eyeballs follow as a second `o` object, which no bake carries).
export const objVertices = (file) => {
  const lines = fs.readFileSync(file, 'utf8').split('\n');
  const out = [];
  let objects = 0;
  for (const l of lines) {
    if (l.startsWith('o ') && ++objects > 1) break;
    if (l.startsWith('v ')) out.push(l.split(/\s+/).slice(1, 4).map(Number));
  }
  return out;
};
