#!/usr/bin/env bash
# What build/tools/bench-assets and bench-draco need besides the build (kept out of tools/setup.sh so that the test
# suite's set-up stays fast), idempotent and quiet when nothing is missing: Debian's assimp-testmodels (the glTF2
# assets, in /usr/share/assimp/models/glTF2) and npm @gltf-transform/cli 4.5 (bench-draco's `gltf-transform draco`)
# in tools/node/; gltfpack 1.3, the other peer, comes with tools/setup.sh. Run as root on Debian 12, after
# tools/setup.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

. tools/packages.sh
install_missing bench-setup-assets assimp-testmodels

# bench-draco's level-by-level peer (issue 20 item 10 compares against glTF-Transform 4.5).
version=4.5
installed=$(node -p "try { require('./tools/node/node_modules/@gltf-transform/cli/package.json').version } catch { '' }")
if [ "${installed%.*}" != "$version" ]; then
  echo "bench-setup-assets: installing @gltf-transform/cli@$version (npm)" >&2
  npm install --prefix tools/node --no-audit --no-fund "@gltf-transform/cli@$version" >/dev/null
fi
