#!/usr/bin/env bash
# docs/images/fidelity/jaw_open.png: ICT-FaceKit's real jawOpen next to the default template's
# jaw at 1 on the ICT head (docs/jaw.md). Needs ../shared and ImageMagick's montage.
#   bash tools/make-jaw-render.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
mimetic=${1:-build}/mimetic
data=../shared/data/ict-facekit
[[ -f $data/arkit/jawOpen.obj ]] || { echo "make-jaw-render: $data/arkit/jawOpen.obj not found" >&2; exit 1; }
command -v montage >/dev/null || { echo "make-jaw-render: needs montage (apt-get install imagemagick)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$mimetic" fit assets/head/default.template.json --mesh "$data/ict_skin_neutral.obj" \
  --landmarks tests/data/landmarks/ict_facekit.landmarks.json --out "$tmp/ict.rig.json" > /dev/null
"$mimetic" eval "$tmp/ict.rig.json" --set jaw=1 --out "$tmp/jaw1.obj" > /dev/null
view=(--size 500 --zoom 2.0 --focus 0.5,0.6)
"$mimetic" render "$data/arkit/jawOpen.obj" --out "$tmp/real.png" "${view[@]}" > /dev/null
"$mimetic" render "$tmp/jaw1.obj" --out "$tmp/rig.png" "${view[@]}" > /dev/null
mkdir -p docs/images/fidelity
montage -label '%t' "$tmp/real.png" "$tmp/rig.png" -tile 2x1 -geometry +2+2 \
  "$tmp/jaw_open.png"
mv "$tmp/jaw_open.png" docs/images/fidelity/jaw_open.png
echo "wrote docs/images/fidelity/jaw_open.png"
