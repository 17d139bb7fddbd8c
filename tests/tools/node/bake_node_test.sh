#!/usr/bin/env bash
# tests/tools/node/bake_node_test.sh MIMETIC SOURCE_DIR validate|three|three_tension [REFERENCE]:
# bakes a short clip on the sample head with `mimetic play --fps 10 --out x.glb`, then runs the
# Khronos glTF validator on it (validate: 0 errors, 0 warnings; this bake also has --tension, so
# the _TENSION attribute and its per-target deltas are validated), or loads it with three.js's
# GLTFLoader and compares one frame with `mimetic play --time` (three), or does that on a
# --tension bake and checks its _TENSION at that frame against an independent EvaluateJob
# (three_tension; REFERENCE is tests/tools/node/tension_reference). node and the npm packages
# come from tools/install-deps.sh (SOURCE_DIR/.node/node_modules); without them the test is
# skipped (exit 77), except under CI=true, where their absence is a failure.
set -euo pipefail
tool=$1 src=$2 what=$3 reference=${4:-}
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
elif [[ $what == three_tension ]]; then
  # A --tension bake in three.js: its _TENSION at 0.3 s (frame 3) against tension_reference's
  # independent EvaluateJob there (REFERENCE, the 4th argument); positions as for `three`.
  "$tool" play "$rig" "$tmp/c.clip.json" --library "$lib" --fps 10 --out "$tmp/c.glb" --tension \
    --quiet
  "$reference" "$rig" "$tmp/c.clip.json" "$lib" 0.3 "$tmp/t3.bin"
  "$tool" play "$rig" "$tmp/c.clip.json" --library "$lib" --time 0.3 --out "$tmp/f3.obj" --quiet
  node "$src/tests/tools/node/three_load.mjs" "$tmp/c.glb" "$modules" 5 0.5 0.3 "$tmp/f3.obj"
  node "$src/tests/tools/node/three_tension.mjs" "$tmp/c.glb" "$modules" 0.3 "$tmp/t3.bin"
else
  # 0.5 s at 10 fps: frames 0..5, frame 0 the neutral (no target): 5 targets; frame 3 at 0.3 s.
  "$tool" play "$rig" "$tmp/c.clip.json" --library "$lib" --time 0.3 --out "$tmp/f3.obj" --quiet
  node "$src/tests/tools/node/three_load.mjs" "$tmp/c.glb" "$modules" 5 0.5 0.3 "$tmp/f3.obj"
fi
