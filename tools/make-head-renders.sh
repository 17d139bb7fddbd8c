#!/usr/bin/env bash
# tools/make-head-renders.sh: the README's and docs/wrinkles.md's four pictures of the default
# rig (neutral, surprise, frown, smile), every skin layer on, and docs/fidelity.md's two of its
# jaw (the mouth open at jaw 0.6; surprise with the jaw: the library's Surprise, AU1, AU2 and
# AU26 together, each muscle at the largest of their values). Run from the repository root
# after building `mimetic` (MIMETIC=path to use another build):
#
#   bash tools/make-head-renders.sh
#
# Writes docs/images/head_{neutral,surprise,frown,smile,jaw_open,surprise_jaw}.png (the face,
# cropped from a 2.2 times larger render of the whole head; `mimetic render --help`).
set -euo pipefail
mimetic=${MIMETIC:-./build/mimetic}
rig=assets/head/sample_head.rig.json
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$mimetic" eval "$rig" --out "$tmp/neutral.glb"
"$mimetic" eval "$rig" --set frontalis_inner=0.9 --set frontalis_major=0.9 \
  --set frontalis_outer=0.9 --out "$tmp/surprise.glb"
"$mimetic" eval "$rig" --set corrugator_supercilii=1 --set procerus=0.6 --out "$tmp/frown.glb"
"$mimetic" eval "$rig" --set zygomaticus_major=1 --set zygomaticus_minor=0.5 \
  --out "$tmp/smile.glb"
"$mimetic" eval "$rig" --set jaw=0.6 --out "$tmp/jaw_open.glb"
# shellcheck disable=SC2046  # one --set argument per word
"$mimetic" eval "$rig" $(python3 - assets/expressions/default.library.json <<'PY'
import json, sys
lib = {e["name"]: e["activations"] for e in json.load(open(sys.argv[1]))["expressions"]}
a = {}
for name in ("Surprise", "AU1", "AU2", "AU26"):
    for m, v in lib[name].items():
        a[m] = max(a.get(m, 0.0), v)
print(" ".join(f"--set {m}={v}" for m, v in sorted(a.items())))
PY
) --out "$tmp/surprise_jaw.glb"
for e in neutral surprise frown smile jaw_open surprise_jaw; do
  focus=0.5,0.5
  [[ $e == *jaw* ]] && focus=0.5,0.56  # the dropped chin stays in the picture
  "$mimetic" render "$tmp/$e.glb" --zoom 2.2 --focus "$focus" --out "docs/images/head_$e.png"
done
echo "wrote docs/images/head_{neutral,surprise,frown,smile,jaw_open,surprise_jaw}.png"
