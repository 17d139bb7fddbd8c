# tests/tools/node/node_env.sh: sourced by the node tests with `src` and `what` set. Sets
# `modules` (SOURCE_DIR/.node/node_modules, where tools/install-deps.sh puts the npm packages)
# and exits 77 (skipped) when node or the package the test needs (gltf-validator for
# `validate`, three for `three`) is missing, except under CI=true, where that is a failure.
modules="$src/.node/node_modules"
need=gltf-validator; [[ $what == three* ]] && need=three
if ! command -v node >/dev/null || [[ ! -d "$modules/$need" ]]; then
  msg="skipped: node or $modules/$need is missing (bash tools/install-deps.sh installs them)"
  if [[ "${CI:-}" == true ]]; then echo "FAIL (CI): $msg"; exit 1; fi
  echo "$msg"; exit 77
fi
