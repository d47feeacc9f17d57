#!/usr/bin/env bash
# Everything a fresh Debian 12 machine needs, idempotent and quiet when nothing is missing:
# Debian packages, the scanned meshes (npm), then configure and build with meson into build/.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(gcc g++ meson ninja-build pkg-config check libtinygltf-dev nlohmann-json3-dev libdraco-dev draco
          libmeshoptimizer-dev valgrind clang libclang-rt-14-dev xz-utils libpng-dev libjpeg-dev zlib1g-dev
          assimp-testmodels)
. tools/packages.sh
install_missing setup "${packages[@]}"

# The Khronos glTF validator for the tests (tools/validate-gltf.js runs it).
if [ ! -f tools/node/node_modules/gltf-validator/package.json ]; then
  echo "setup: installing gltf-validator (npm)" >&2
  npm install --prefix tools/node --no-audit --no-fund gltf-validator >/dev/null
fi

# gltfpack 1.3 (meshoptimizer's glTF tool, wasm under node): the corpus test feeds its compressed, quantized and
# instanced outputs to resurf (tests/test_corpus_gltf.sh), and bench-assets measures against it.
version=1.3
installed=$(node -p "try { require('./tools/node/node_modules/gltfpack/package.json').version } catch { '' }")
if [ "${installed%.*}" != "$version" ]; then
  echo "setup: installing gltfpack@$version (npm)" >&2
  npm install --prefix tools/node --no-audit --no-fund "gltfpack@$version" >/dev/null
fi

bash tools/fetch-data.sh

# Quiet when all is well; the log's tail when something fails.
quietly() {
  local log
  log=$(mktemp)
  if ! "$@" >"$log" 2>&1; then
    tail -n 40 "$log" >&2
    rm -f "$log"
    echo "setup: failed: $*" >&2
    return 1
  fi
  rm -f "$log"
}
if [ ! -f build/build.ninja ]; then
  quietly meson setup build --buildtype=release -Dwerror=true
fi
quietly ninja -C build
