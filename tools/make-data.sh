#!/usr/bin/env bash
# Regenerates the small analytic meshes in data/ (every vertex exactly on its surface). Needs a build in build/.
set -euo pipefail
cd "$(dirname "$0")/.."
${BUILD:-build}/tools/resurf-gen-analytic --data data
