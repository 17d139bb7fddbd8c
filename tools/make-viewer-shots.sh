#!/usr/bin/env bash
# The viewer's screenshots in docs/viewer.md and the README, each from a script of
# tools/viewer-shots/ (the same commands the panels issue, docs/viewer.md "Scripts") replayed by
# mimetic-viewer under xvfb-run, then cropped to the panel it shows. Needs xvfb-run and
# ImageMagick's convert (bash tools/install-deps.sh; apt-get install imagemagick).
#   bash tools/make-viewer-shots.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
viewer=${1:-build}/viewer/mimetic-viewer
[[ -x $viewer ]] || { echo "make-viewer-shots: $viewer not found (build the viewer first)" >&2; exit 1; }
for tool in xvfb-run convert; do
  command -v $tool >/dev/null || { echo "make-viewer-shots: needs $tool" >&2; exit 1; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The timeline: the smile clip with muscle and jaw channels keyed over it, two keys selected,
# the playhead at 1 s. The clip is edited in memory only (the script saves nothing).
xvfb-run -a "$viewer" assets/head/sample_head.rig.json --clip assets/clips/smile.clip.json \
  --script tools/viewer-shots/timeline.txt --ui --size 1600x950 --screenshot "$tmp/timeline.png" >/dev/null
convert "$tmp/timeline.png" -crop 905x250+350+700 +repage "$tmp/viewer_timeline.png"
mv "$tmp/viewer_timeline.png" docs/images/viewer_timeline.png
echo "wrote docs/images/viewer_timeline.png"

# The three rig editors (docs/viewer.md "Editing the rig"), each opened by --panel, at 1280x720;
# the UV view has thousands of faint triangle edges, so it is reduced to 64 colours.
xvfb-run -a "$viewer" assets/head/sample_head.rig.json --ui --size 1280x720 --panel muscle-editor \
  --select zygomaticus_major_L --screenshot docs/images/viewer_muscle_editor.png >/dev/null
xvfb-run -a "$viewer" assets/head/sample_head.rig.json --ui --size 1280x720 --panel uv-curves \
  --screenshot "$tmp/uv.png" >/dev/null
convert "$tmp/uv.png" -colors 64 docs/images/viewer_uv_curves.png
xvfb-run -a "$viewer" assets/head/sample_head.rig.json --ui --size 1280x720 --panel directions \
  --screenshot docs/images/viewer_directions.png >/dev/null
echo "wrote docs/images/viewer_muscle_editor.png, viewer_uv_curves.png, viewer_directions.png"

# Fine scale: the rig's maps (mimetic texture, 1024^2) bump-mapped in the viewer's shader, the
# brows raised (the frontalis compresses the forehead across field 1: its furrows deepen).
"${1:-build}/mimetic" texture assets/head/sample_head.rig.json --size 1024 --out "$tmp/maps" --seed 1 --quiet
raise=()
for m in frontalis_inner frontalis_major frontalis_outer; do raise+=(--set $m=1); done
for fine in "" "--fine $tmp/maps --fine-depth 0.4"; do
  # shellcheck disable=SC2086
  xvfb-run -a "$viewer" assets/head/sample_head.rig.json "${raise[@]}" $fine --size 2400x1800 \
    --screenshot "$tmp/fine${fine:+_on}.png" >/dev/null
done
convert "$tmp/fine.png" -crop 760x460+820+330 +repage "$tmp/a.png"
convert "$tmp/fine_on.png" -crop 760x460+820+330 +repage "$tmp/b.png"
montage -label 'without maps' "$tmp/a.png" -label '--fine maps --fine-depth 0.4' "$tmp/b.png" \
  -tile 2x1 -geometry +2+2 "$tmp/viewer_fine.png"
mv "$tmp/viewer_fine.png" docs/images/viewer_fine.png
echo "wrote docs/images/viewer_fine.png"
