#!/usr/bin/env bash
# Runs every fuzz target of BUILD_DIR for a fixed number of inputs from its seed corpus (the
# repository's examples, tests/data/bad and fuzz/seeds), as CI's fuzz stage does:
#   bash fuzz/run.sh BUILD_DIR [RUNS]      (RUNS per target, default 2000)
# A crash, a sanitizer report, a leak or an input slower than 10 s fails the run; libFuzzer
# writes the input to BUILD_DIR/fuzz-artifacts/ (reproduce: BUILD_DIR/fuzz/fuzz_NAME FILE).
set -euo pipefail
build=$(realpath "$1")
runs=${2:-2000}
src=$(cd "$(dirname "$0")/.." && pwd)
bad=$src/tests/data/bad
seeds() {  # the seed files of one target
  case $1 in
    rig) echo "$src/assets/head/sample_head.rig.json $src/assets/surface/surface.rig.json $bad/rig_*.json" ;;
    template) echo "$src/assets/head/default.template.json $bad/template_*.json" ;;
    landmarks) echo "$src/assets/head/sample_head.landmarks.json $src/tests/data/landmarks/*.json $bad/landmarks_*.json" ;;
    expression) echo "$src/tests/data/expressions/*.json" ;;
    clip) echo "$src/tests/data/clips/*.json $bad/clip_*.json" ;;
    expression_library) echo "$src/assets/expressions/*.json" ;;
    arkit_map) echo "$src/assets/arkit/*.json" ;;
    arkit_take) echo "$src/tests/data/arkit/*.csv $src/tests/data/arkit/take.json" ;;
    golden) echo "$src/tests/golden/*.golden" ;;
    mesh_glb) echo "$src/fuzz/seeds/*.glb $bad/*.glb" ;;
    mesh_gltf) echo "$src/fuzz/seeds/*.gltf $bad/*.gltf" ;;
    mesh_obj) echo "$src/fuzz/seeds/*.obj $bad/*.obj" ;;
    image) echo "$src/fuzz/seeds/*.png $bad/*.png" ;;
    mrig) echo "$work/mrig-seed/*.mrig" ;;  # written below by fuzz_mrig_seed
    mclip) echo "$work/mclip-seed/*.mclip" ;;  # written below by fuzz_mclip_seed
  esac
}
artifacts=$build/fuzz-artifacts
mkdir -p "$artifacts"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/mrig-seed"
"$build/fuzz/fuzz_mrig_seed" "$work/mrig-seed/surface.mrig" >/dev/null
mkdir -p "$work/mclip-seed"
"$build/fuzz/fuzz_mclip_seed" "$work/mclip-seed/seed.mclip" >/dev/null
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for name in rig template landmarks expression clip expression_library arkit_map arkit_take golden mesh_glb mesh_gltf mesh_obj image mrig mclip; do
  mkdir -p "$work/$name/corpus" "$work/$name/seeds"
  # shellcheck disable=SC2046
  cp $(seeds "$name") "$work/$name/seeds/"
  start=$(date +%s)
  if ! "$build/fuzz/fuzz_$name" -runs="$runs" -seed=1 -max_len=65536 -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=0 -artifact_prefix="$artifacts/$name-" \
      "$work/$name/corpus" "$work/$name/seeds" >"$work/$name.log" 2>&1; then
    tail -40 "$work/$name.log"
    echo "fuzz: fuzz_$name failed (artifacts in $artifacts)" >&2
    exit 1
  fi
  echo "fuzz: fuzz_$name: $runs runs from $(ls "$work/$name/seeds" | wc -l) seeds, $(( $(date +%s) - start ))s, ok"
done
