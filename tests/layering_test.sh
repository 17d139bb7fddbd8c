#!/usr/bin/env bash
# ctest "layering": the dependency direction in #include lines (README "Layout").
#   - runtime modules (core, muscles/runtime, wrinkles/runtime, expressions/runtime,
#     rig/runtime, capi) include only the C++ standard library (and, for the C ABI's header,
#     <stddef.h> and <stdint.h>), SIMD intrinsics, a few POSIX headers of core's file writer,
#     and runtime modules;
#   - no module below io includes a third-party parser (nlohmann, tinygltf, stb, libspng) or io/ (io,
#     tools, bench, tests, viewer and fuzz sit above it);
#   - only io includes OpenMesh's file reader; only tools include tools/.
# Prints every offending line as FILE:LINE: TEXT and exits 1 when there is any.
set -uo pipefail
cd "$1"
fail=0
report() { echo "$1: $2"; fail=1; }
std='^(algorithm|array|atomic|bit|cassert|cerrno|cfloat|charconv|climits|cmath|cstddef|cstdint|cstdio|cstdlib|cstring|filesystem|fstream|functional|initializer_list|iterator|limits|memory|mutex|new|numbers|numeric|optional|sstream|span|string|string_view|system_error|thread|tuple|type_traits|unordered_map|utility|vector|immintrin\.h|emmintrin\.h|xmmintrin\.h|unistd\.h|fcntl\.h|signal\.h|sys/stat\.h|stddef\.h|stdint\.h)$'
runtime='^(core|muscles/runtime|wrinkles/runtime|expressions/runtime|rig/runtime|capi)/'
while IFS= read -r f; do
  n=0
  while IFS= read -r line; do
    n=$((n + 1))
    [[ $line =~ ^[[:space:]]*#[[:space:]]*include[[:space:]]*[\<\"]([^\>\"]+)[\>\"] ]] || continue
    inc=${BASH_REMATCH[1]}
    if [[ $f =~ $runtime ]]; then
      if [[ $line == *'<'* ]]; then
        [[ $inc =~ $std ]] || report "$f:$n" "runtime code includes <$inc> (C++ standard library only)"
      else
        [[ $inc =~ $runtime ]] || report "$f:$n" "runtime code includes \"$inc\" (runtime modules only)"
      fi
      continue
    fi
    case $f in
      io/*|tools/*|bench/*|tests/*|viewer/*|fuzz/*) ;;
      *)
        case $inc in
          nlohmann/*|tiny_gltf.h|stb/*|spng.h) report "$f:$n" "includes <$inc>: third-party parsers belong to io/" ;;
          OpenMesh/Core/IO/*) report "$f:$n" "includes <$inc>: file reading belongs to io/" ;;
          io/*) report "$f:$n" "includes \"$inc\": modules below io do not include it" ;;
        esac ;;
    esac
    case $f in
      tools/*|tests/*|bench/*|fuzz/*) ;;
      *) [[ $inc == tools/* ]] && report "$f:$n" "includes \"$inc\": only the tools include tools/" ;;
    esac
  done < "$f"
done < <(git ls-files '*.h' '*.cpp' 2>/dev/null || find . -name '*.h' -o -name '*.cpp')
if (( fail )); then exit 1; fi
echo "layering: every #include follows the dependency direction"
