#!/usr/bin/env bash
# Converted assets for build/tools/bench-assets: every model of Debian's assimp-testmodels in a format other than
# glTF, exported to GLB by Debian's assimp (`assimp export IN OUT.glb -fglb2`, the exporter issue 19 names), kept
# when its GLB validates with 0 errors and has at least 500 triangles. These are the hard-surface props, vehicles,
# buildings and characters of real exporters that the glTF2 folder lacks. Writes data/converted/ (idempotent);
# then: build/tools/bench-assets --models data/converted --scans data/converted/none
# Run as root on Debian 12, after tools/setup.sh and tools/bench-setup-assets.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

. tools/packages.sh
install_missing bench-setup-converted assimp-testmodels assimp-utils

src=/usr/share/assimp/models
out=data/converted
mkdir -p "$out/none"
[ -f "$out/.done" ] && exit 0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
kept=0
while IFS= read -r -d '' f; do
  rel=${f#"$src"/}
  name=$(printf '%s' "${rel%.*}" | tr '/ ' '__')
  glb="$tmp/$name.glb"
  (timeout 60 assimp export "$f" "$glb" -fglb2) >/dev/null 2>&1 || continue # assimp crashes on some
  node tools/validate-gltf.js "$glb" 2>/dev/null | grep -q 'numErrors 0 ' || continue
  tris=$(build/tools/resurf info "$glb" 2>/dev/null | sed -n 's/.*primitives\[[0-9]*\]: triangles \([0-9]*\).*/\1/p' |
         awk '{s += $1} END {print s + 0}')
  [ "$tris" -ge 500 ] || continue
  mv "$glb" "$out/$name.glb"
  kept=$((kept + 1))
done < <(find "$src" -type f ! -path "$src/glTF*" ! -path "$src/invalid/*" ! -path "$src/ReferenceImages/*" \
         ! -path "$src/SourceFiles/*" ! -path "$src/ParsingFiles/*" ! -name '*.png' ! -name '*.jpg' ! -name '*.bmp' \
         ! -name '*.tga' ! -name '*.dds' ! -name '*.txt' ! -name '*.mtl' ! -name '*.md' -print0 | sort -z)
touch "$out/.done"
echo "bench-setup-converted: $kept converted assets in $out" >&2
