#!/usr/bin/env bash
# tests/tools/node/blendshapes_node_test.sh MIMETIC SOURCE_DIR validate|three: exports the sample
# head's 52 ARKit blendshapes with `mimetic export-blendshapes`, then either runs the Khronos
# glTF validator on the file (0 errors, 0 warnings) or loads it with three.js's GLTFLoader,
# checks the 52 names in morphTargetDictionary and compares mouthSmileLeft at 1 with
# `mimetic eval` at the map's activations for it. Skipped (77) without node or the npm packages
# (tools/install-deps.sh), except under CI=true.
set -euo pipefail
tool=$1 src=$2 what=$3
source "$src/tests/tools/node/node_env.sh"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
rig="$src/assets/head/sample_head.rig.json"
map="$src/assets/arkit/default.arkit.json"
"$tool" export-blendshapes "$rig" --map "$map" --out "$tmp/arkit52.glb"
if [[ $what == validate ]]; then
  node "$src/tests/tools/node/validate.mjs" "$tmp/arkit52.glb" "$modules"
else
  shape=mouthSmileLeft
  mapfile -t sets < <(node -e '
    const m = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
    for (const [k, v] of Object.entries(m.shapes[process.argv[2]].activations))
      console.log(`--set=${k}=${v}`);' "$map" "$shape")
  args=()
  for s in "${sets[@]}"; do args+=(--set "${s#--set=}"); done
  "$tool" eval "$rig" "${args[@]}" --out "$tmp/shape.obj"
  node "$src/tests/tools/node/three_blendshapes.mjs" "$tmp/arkit52.glb" "$modules" "$shape" "$tmp/shape.obj"
fi
