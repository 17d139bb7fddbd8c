#!/usr/bin/env bash
# ctest "package.embed": installs this build into a temporary prefix, builds examples/embed
# against it (find_package(mimetic), the runtime library alone), compiles the sample head and the
# Surprise clip (`mimetic build`), runs the example's frame loop for 4 characters and compares
# character 0's positions at t = 1.2 s with `mimetic play RIG CLIP --time 1.2`'s OBJ: every
# coordinate within 1e-5 of the head's size (the OBJ's printed precision), and the pose moves.
#   embed_test.sh BUILD_DIR SOURCE_DIR MIMETIC
set -euo pipefail
build=$1 source=$2 tool=$3
tmp=$(mktemp -d /tmp/mimetic-embed-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$source/examples/embed" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/build" -j2 >/dev/null
rig="$source/assets/head/sample_head.rig.json"
clip="$source/assets/clips/surprise.clip.json"
lib="$source/assets/expressions/default.library.json"
"$tool" build "$rig" --out "$tmp/head.mrig" >/dev/null
"$tool" build "$clip" --rig "$tmp/head.mrig" --library "$lib" --out "$tmp/surprise.mclip" >/dev/null
"$tmp/build/embed" "$tmp/head.mrig" "$tmp/surprise.mclip" --instances 4 --frames 10 \
  --dump 1.2 "$tmp/embed.txt" | tee "$tmp/embed.log"
grep -q "4 character(s) of [0-9]* vertices on one rig, 10 frames" "$tmp/embed.log"
"$tool" play "$rig" "$clip" --library "$lib" --time 1.2 --out "$tmp/play.obj" --quiet
"$tool" eval "$rig" --out "$tmp/rest.obj" >/dev/null
# Columns: embed's x y z, play's x y z, the rest pose's x y z (same vertex order).
# The skin only: the OBJ's first object (the sample head's eyes follow as a second one).
skin_v() { awk '/^o /{o++} o < 2 && /^v /{print $2, $3, $4}' "$1"; }
skin_v "$tmp/play.obj" > "$tmp/play.txt"
skin_v "$tmp/rest.obj" > "$tmp/rest.txt"
paste -d' ' "$tmp/embed.txt" "$tmp/play.txt" "$tmp/rest.txt" | awk '
  function abs(x) { return x < 0 ? -x : x }
  NF != 9 { bad = 1 }
  { n++
    for (c = 1; c <= 3; ++c) {
      if (n == 1 || $(c+3) < lo[c]) lo[c] = $(c+3)
      if (n == 1 || $(c+3) > hi[c]) hi[c] = $(c+3)
      d = abs($c - $(c+3)); if (d > diff) diff = d
      m = abs($(c+3) - $(c+6)); if (m > move) move = m } }
  END {
    size = sqrt((hi[1]-lo[1])^2 + (hi[2]-lo[2])^2 + (hi[3]-lo[3])^2)
    printf "embed vs mimetic play at 1.2 s: %d vertices, max |difference| %g (head %g), max move %g\n", n, diff, size, move
    if (bad || n < 1000 || diff > 1e-5 * size || move < 1e-3 * size) exit 1 }'
echo "package.embed: the example built against the installed package matches mimetic play"
