#!/usr/bin/env bash
# tools/make-library.sh: regenerates the expression library, the ARKit map and the library's
# pictures (docs/facs.md, docs/arkit.md). Run from the repository root after building
# `mimetic`, with ICT-FaceKit in ../shared/data (DATA=DIR to point elsewhere):
#
#   bash tools/make-library.sh            # solve, write both files, render every expression
#   bash tools/make-library.sh --renders  # only the pictures, from the committed library
#
# 1. `mimetic make-library` fits the default template to ICT's neutral, solves the entries
#    that have an ICT shape and writes assets/expressions/default.library.json and
#    assets/arkit/default.arkit.json (deterministic: a rerun writes the same files).
# 2. Each library expression is posed on the sample head rig (`mimetic eval`, every skin
#    layer), rendered (`mimetic render`, the face close up) to docs/images/expressions/NAME.png
#    and made grayscale (tools/png_gray.py: about 40 KB a picture).
set -euo pipefail
mimetic=${MIMETIC:-./build/mimetic}
data=${DATA:-../shared/data}
library=assets/expressions/default.library.json
rig=assets/head/sample_head.rig.json
out=docs/images/expressions
if [[ "${1:-}" != "--renders" ]]; then
  "$mimetic" make-library --data "$data" --library "$library" --arkit assets/arkit/default.arkit.json
  python3 tools/arkit_table.py  # docs/arkit.md's per-shape table from the new map
fi
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# One line per expression: NAME then its --set arguments.
python3 - "$library" > "$tmp/list" <<'PY'
import json, sys
for e in json.load(open(sys.argv[1]))["expressions"]:
    sets = " ".join(f"--set {m}={v}" for m, v in e["activations"].items())
    print(e["name"], sets)
PY
while read -r name sets; do
  # shellcheck disable=SC2086  # $sets is a list of arguments
  "$mimetic" eval "$rig" $sets --out "$tmp/$name.glb" > /dev/null
  "$mimetic" render "$tmp/$name.glb" --out "$out/$name.png" --size 400 --zoom 2.3 --focus 0.5,0.55 > /dev/null
  python3 tools/png_gray.py "$out/$name.png"  # a quarter of the bytes
  rm -f "$tmp/$name.glb"
  echo "rendered $out/$name.png"
done < "$tmp/list"
