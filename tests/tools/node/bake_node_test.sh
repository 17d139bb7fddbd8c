#!/usr/bin/env bash
# tests/tools/node/bake_node_test.sh MIMETIC SOURCE_DIR validate|three: bakes a short clip on
# the sample head with `mimetic play --fps 10 --out x.glb`, then either runs the Khronos glTF
# validator on it (0 errors, 0 warnings; this bake also has --tension, so the _TENSION
# attribute and its per-target deltas are validated) or loads it with three.js's GLTFLoader and compares
# one frame with `mimetic play --time`. node and the npm packages come from
# tools/install-deps.sh (SOURCE_DIR/.node/node_modules); without them the test is skipped
# (exit 77), except under CI=true, where their absence is a failure.
set -euo pipefail
tool=$1 src=$2 what=$3
source "$src/tests/tools/node/node_env.sh"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
rig="$src/assets/head/sample_head.rig.json"
cat > "$tmp/c.clip.json" <<'JSON'
{"format": "mimetic-clip", "version": 1, "name": "bake_test", "duration": 0.5,
 "channels": [{"expression": "Surprise", "keys": [{"t": 0, "v": 0, "interp": "cubic"},
                                                  {"t": 0.5, "v": 1}]},
              {"muscle": "zygomaticus_major", "keys": [{"t": 0, "v": 0}, {"t": 0.5, "v": 0.6}]}]}
JSON
lib="$src/assets/expressions/default.library.json"
"$tool" play "$rig" "$tmp/c.clip.json" --library "$lib" --fps 10 --out "$tmp/c.glb"
if [[ $what == validate ]]; then
  "$tool" play "$rig" "$tmp/c.clip.json" --library "$lib" --fps 10 --out "$tmp/c.glb" --tension \
    --quiet
  node "$src/tests/tools/node/validate.mjs" "$tmp/c.glb" "$modules"
else
  # 0.5 s at 10 fps: frames 0..5, frame 0 the neutral (no target): 5 targets; frame 3 at 0.3 s.
  "$tool" play "$rig" "$tmp/c.clip.json" --library "$lib" --time 0.3 --out "$tmp/f3.obj" --quiet
  node "$src/tests/tools/node/three_load.mjs" "$tmp/c.glb" "$modules" 5 0.5 0.3 "$tmp/f3.obj"
fi
