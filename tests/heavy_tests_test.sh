#!/usr/bin/env bash
# Every name in tests/heavy_tests.txt is a test of this build (a renamed or deleted test would
# otherwise slip back into the sanitizer stage unnoticed, or the list would rot).
#   heavy_tests_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
missing=0 count=0
while IFS= read -r name; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  count=$((count + 1))
  found=$(ctest --test-dir "$build" -N -R "^${name//./\\.}\$" | sed -n 's/^Total Tests: //p')
  if [[ "$found" != 1 ]]; then
    echo "tests/heavy_tests.txt: \"$name\" is not a test of $build (found $found)" >&2
    missing=$((missing + 1))
  fi
done < "$source/tests/heavy_tests.txt"
if (( missing > 0 )); then exit 1; fi
echo "heavy_tests: all $count names are tests"
