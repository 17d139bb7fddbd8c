#!/usr/bin/env bash
# tools/make-head-renders.sh: the README's and docs/wrinkles.md's four pictures of the default
# rig (neutral, surprise, frown, smile), every skin layer on. Run from the repository root
# after building `mimetic` (MIMETIC=path to use another build):
#
#   bash tools/make-head-renders.sh
#
# Writes docs/images/head_{neutral,surprise,frown,smile}.png (the face, cropped from a 2.2
# times larger render of the whole head; `mimetic render --help`).
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
for e in neutral surprise frown smile; do
  "$mimetic" render "$tmp/$e.glb" --zoom 2.2 --focus 0.5,0.5 --out "docs/images/head_$e.png"
done
echo "wrote docs/images/head_{neutral,surprise,frown,smile}.png"
