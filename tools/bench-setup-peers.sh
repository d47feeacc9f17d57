#!/usr/bin/env bash
# The simplification benchmark's extra peers on a fresh Debian 12 machine, idempotent and quiet when nothing is
# missing (tools/setup.sh has the rest, native meshoptimizer 0.18 among it):
# - libcgal-dev (CGAL 5.5, header only; brings boost, gmp, mpfr) and libeigen3-dev (CGAL's Garland-Heckbert
#   policies include Eigen) for bench-simplify's cgal-lt and cgal-gh rows: reconfigure the build after installing
#   (meson finds them when it configures);
# - npm meshoptimizer 1.x into tools/node for its mopt-js and mopt-js-upd rows (tools/peer-meshopt.mjs), found at
#   run time.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(libcgal-dev libeigen3-dev)
. tools/packages.sh
install_missing bench-setup-peers "${packages[@]}"

version=$(node -p "try { require('./tools/node/node_modules/meshoptimizer/package.json').version } catch { '' }")
if [ "${version%%.*}" != 1 ]; then
  echo "bench-setup-peers: installing meshoptimizer 1.x (npm)" >&2
  npm install --prefix tools/node --no-audit --no-fund 'meshoptimizer@^1.3.0' >/dev/null
fi

if [ -f build/build.ninja ] && ! grep -q -- '-DHAVE_CGAL' build/build.ninja; then
  echo "bench-setup-peers: reconfiguring build/ to find CGAL" >&2
  meson setup --reconfigure build >/dev/null
fi
