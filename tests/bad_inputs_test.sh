#!/usr/bin/env bash
# ctest "bad_inputs": every case of tests/data/bad/cases.txt through the built CLI. Each must
# end with its stated exit status (1 bad input, 2 bad command line; never a signal, never
# 0), print its message, and name its file. Also checks the inputs that cannot be checked in:
# a FIFO, a directory and /dev/zero as the mesh (each refused at once, never a hang).
#   bash tests/bad_inputs_test.sh MIMETIC SOURCE_DIR
set -uo pipefail
tool=$(realpath "$1")
src=$2
cd "$src/tests/data/bad" || exit 1
fail=0 n=0
check() {  # FILE EXIT MESSAGE ARGS...
  local file=$1 want=$2 msg=$3
  shift 3
  n=$((n + 1))
  local out rc
  out=$(timeout 60 "$tool" "$@" 2>&1)
  rc=$?
  if (( rc >= 124 )); then
    echo "FAIL $file: exit $rc (a signal or the 60 s timeout) for: mimetic $*"; echo "$out" | head -5; fail=1; return
  fi
  if [[ $rc != "$want" ]]; then
    echo "FAIL $file: exit $rc, expected $want for: mimetic $*"; echo "$out" | head -5; fail=1; return
  fi
  if [[ $out != *"$msg"* ]]; then
    echo "FAIL $file: message '$msg' not in the output of: mimetic $*"; echo "$out" | head -5; fail=1; return
  fi
  if [[ $out != *"$(basename "$file")"* ]]; then
    echo "FAIL $file: the output does not name the file"; echo "$out" | head -5; fail=1; return
  fi
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
assets=$src/assets/head
while IFS=$'\t' read -r file want msg cmd; do
  [[ -z $file || $file == \#* ]] && continue
  cmd=${cmd//@F/$file}
  cmd=${cmd//@A/$assets}
  cmd=${cmd//@T/$tmp}
  msg=${msg//@T/$tmp}
  read -r -a args <<< "$cmd"
  check "$file" "$want" "$msg" "${args[@]}"
done < cases.txt
# Inputs that are not regular files.
mkfifo "$tmp/fifo.glb"
mkdir "$tmp/dir.obj"
check "$tmp/fifo.glb" 1 "is not a regular file (it is a FIFO (named pipe); expected a glb mesh file)" \
  render "$tmp/fifo.glb" --out "$tmp/x.png"
check "$tmp/dir.obj" 1 "is not a regular file (it is a directory; expected an obj mesh file)" \
  render "$tmp/dir.obj" --out "$tmp/x.png"
ln -s /dev/zero "$tmp/zero.gltf"
check "$tmp/zero.gltf" 1 "is not a regular file (it is a character device; expected a gltf mesh file)" \
  render "$tmp/zero.gltf" --out "$tmp/x.png"
if (( fail )); then echo "bad_inputs: failures above ($n cases)"; exit 1; fi
echo "bad_inputs: all $n cases refused with their exit status and message"
