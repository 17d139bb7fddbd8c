#!/usr/bin/env bash
# docs/images/fine_*.png: the bundled rig's fine-scale maps (docs/model.md §20-23) and the
# forehead rendered with them at rest, with the brows raised (the frontalis compresses the
# forehead across field 1: its furrows deepen) and lowered (corrugators and procerus stretch it:
# they fade). Needs ImageMagick (convert, montage) for the previews; the maps themselves are
# 2048 x 2048 16-bit (shown downscaled to 8 bits).
#   bash tools/make-fine-renders.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
mimetic=${1:-build}/mimetic
command -v montage >/dev/null || { echo "make-fine-renders: needs montage (apt-get install imagemagick)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
rig=assets/head/sample_head.rig.json
"$mimetic" texture "$rig" --size 2048 --out "$tmp/maps" --seed 1 --quiet
# Previews: the merged height map (contrast stretched) and a crop of the normal map.
convert "$tmp/maps/fine_height.png" -resize 768x768 -level 55%,100% -depth 8 "$tmp/height.png"
convert "$tmp/maps/fine_height.png" -crop 512x512+768+240 -level 40%,100% -depth 8 "$tmp/height_crop.png"
convert "$tmp/maps/fine_normal.png" -crop 512x512+768+240 "$tmp/normal_crop.png"
view=(--fine "$tmp/maps" --fine-depth 0.4 --size 480 --zoom 4 --focus 0.5,0.36)
up=() down=()
for m in frontalis_inner frontalis_major frontalis_outer; do up+=(--activate ${m}_L=1 --activate ${m}_R=1); done
for m in corrugator_supercilii procerus; do down+=(--activate ${m}_L=1 --activate ${m}_R=1); done
"$mimetic" render "$rig" "${view[@]}" --out "$tmp/rest.png" > /dev/null
"$mimetic" render "$rig" "${view[@]}" "${up[@]}" --out "$tmp/raised.png" > /dev/null
"$mimetic" render "$rig" "${view[@]}" "${down[@]}" --out "$tmp/lowered.png" > /dev/null
montage -label 'rest' "$tmp/rest.png" -label 'brows raised (compressed)' "$tmp/raised.png" \
  -label 'brows lowered (stretched)' "$tmp/lowered.png" -tile 3x1 -geometry +2+2 "$tmp/forehead.png"
cp "$tmp/height.png" docs/images/fine_height.png
montage "$tmp/height_crop.png" "$tmp/normal_crop.png" -tile 2x1 -geometry +2+2 docs/images/fine_maps_forehead.png
cp "$tmp/forehead.png" docs/images/fine_forehead.png
echo "wrote docs/images/fine_height.png, fine_maps_forehead.png, fine_forehead.png"
