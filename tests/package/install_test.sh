#!/usr/bin/env bash
# ctest "package.install": installs this build into a temporary prefix and builds the consumer
# in tests/package/consumer against it with find_package(mimetic), then runs it.
#   install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
tmp=$(mktemp -d /tmp/mimetic-package-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
test -f "$tmp/prefix/lib/cmake/mimetic/mimetic-config.cmake"
test -f "$tmp/prefix/lib/cmake/mimetic/mimetic-config-version.cmake"
test -f "$tmp/prefix/include/mimetic/rig/runtime/evaluate_job.h"
test -f "$tmp/prefix/include/mimetic/capi/mimetic_c.h"
cmake -S "$source/tests/package/consumer" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/build" -j2 >/dev/null
"$tmp/build/consumer"
"$tmp/build/consumer_c"
# A newer version than the package offers is refused (mimetic-config-version.cmake).
if cmake -S "$source/tests/package/consumer" -B "$tmp/build2" -DCMAKE_PREFIX_PATH="$tmp/prefix" \
     -DMIMETIC_WANT=9.0 >"$tmp/refused.log" 2>&1; then
  echo "package: find_package(mimetic 9.0) was accepted by a 0.x package" >&2
  exit 1
fi
grep -q "mimetic" "$tmp/refused.log"
echo "package: installed, found and linked"
