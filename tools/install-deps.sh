#!/usr/bin/env bash
# Installs what mimetic needs to build and test on Debian 12, non-interactively and
# idempotently: packages already present are not touched, and apt-get runs only when
# something is missing. Run as root (CI and the README's commands do).
#   bash tools/install-deps.sh            # build + tests + benchmark + viewer (+ node tools)
#   bash tools/install-deps.sh --viewer   # the same packages, without the npm tools
#   bash tools/install-deps.sh --fuzz     # also clang and its libFuzzer runtime (fuzz/)
set -euo pipefail

# Why each is here (README "Dependencies"): the toolchain; nlohmann-json (the JSON reader),
# tinygltf (glTF), OpenMesh (OBJ reading, offline geometry), stb (images) for the offline io
# module; libspng (16-bit PNG height maps of `mimetic texture`: stb writes 8 bits only);
# Eigen (bounded least squares, offline fitting, fine-scale harmonic fields); GoogleTest and
# Google Benchmark for tests/ and bench/; python3-jsonschema checks the rig schema in a test;
# GLFW, Dear ImGui 1.86, OpenGL and GLM for the viewer (built by default when they are found,
# docs/viewer.md), Xvfb and xauth (xvfb-run) for its headless screenshots, and Mesa's software
# OpenGL under it, xdotool for the tests that drive its UI with synthetic input. The runtime libraries need none of them.
packages=(
  build-essential cmake pkg-config git
  nlohmann-json3-dev libtinygltf-dev libopenmesh-dev libstb-dev libspng-dev libeigen3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-jsonschema
  libglfw3-dev libimgui-dev libgl-dev libegl-dev libglm-dev xvfb xauth libgl1-mesa-dri libegl-mesa0
  xdotool
)
if [[ "${1:-}" == "--fuzz" ]]; then
  packages+=(clang libclang-rt-14-dev)  # Debian 12's clang 14; the runtime holds libFuzzer
fi

# The glTF bake's tests (tests/tools/node): the Khronos glTF validator and three.js (for its
# GLTFLoader), from npm into the repository's .node/ (ignored by git), only when absent.
# They need node and npm (Debian's nodejs, npm); without them the two tests skip.
install_node_packages() {
  local root
  root="$(cd "$(dirname "$0")/.." && pwd)/.node"
  if [[ -d "$root/node_modules/gltf-validator" && -d "$root/node_modules/three" ]]; then
    echo "install-deps: gltf-validator and three already in $root"
    return 0
  fi
  if ! command -v npm >/dev/null; then
    echo "install-deps: npm not found; the glTF validator tests will be skipped"
    return 0
  fi
  mkdir -p "$root"
  echo "install-deps: npm install gltf-validator three into $root"
  (cd "$root" && npm install --no-audit --no-fund --silent --no-save gltf-validator three)
}
if [[ -z "${1:-}" ]]; then
  # Debian's node and npm only where no node/npm is on PATH (one from elsewhere is kept).
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then packages+=(nodejs npm); fi
  trap install_node_packages EXIT
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if (( ${#missing[@]} == 0 )); then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
