#!/usr/bin/env bash
# Textured props, vehicles and characters for build/tools/bench-assets: models of Debian's sweethome3d-furniture
# (Sweet Home 3D's furniture catalogs, OBJ with MTL and textures, CC0 and CC-BY), exported to GLB by Debian's assimp
# (`assimp export IN OUT.glb -fglb2`), each in a folder of its own with the images its GLB refers to, kept when it
# validates with 0 errors. The selection is fixed by the package's files: of the OBJ files over 200 kB sorted by
# path, every tenth from the third, and the vehicles (car, bus, truck, bike). Real exporters' habits the other sets
# lack: faces written double-sided, panels attached to single-sided bodies, foliage cards, many small parts.
# Writes data/furniture/ (idempotent); then: build/tools/bench-assets --models data/furniture --scans ''
# Run as root on Debian 12, after tools/setup.sh and tools/bench-setup-assets.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

. tools/packages.sh
install_missing bench-setup-furniture sweethome3d-furniture assimp-utils unzip

src=/usr/share/sweethome3d/furniture
out=data/furniture
[ -f "$out/.done" ] && exit 0
mkdir -p "$out"
out_abs=$(pwd)/$out
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for catalog in "$src"/*.sh3f; do
  unzip -q -o "$catalog" -d "$tmp/$(basename "$catalog" .sh3f)"
done
(cd "$tmp" && find . -name '*.obj' -size +200k | sort) > "$tmp/list"
{ awk 'NR % 10 == 3' "$tmp/list"; grep -E '/[^/]*(car|bus|truck|bike)[^/]*\.obj$' "$tmp/list" || true; } |
  sort -u > "$tmp/picked"
kept=0
while IFS= read -r rel; do
  name=$(basename "$rel" .obj)
  folder="$tmp/${rel%/*}"
  mkdir -p "$out/$name"
  find "$folder" -maxdepth 1 -type f \( -iname '*.jpg' -o -iname '*.jpeg' -o -iname '*.png' \) \
       -exec cp {} "$out/$name/" \;
  if (cd "$folder" && timeout 60 assimp export "$name.obj" "$out_abs/$name/$name.glb" -fglb2) \
       >/dev/null 2>&1 &&
     node tools/validate-gltf.js "$out/$name/$name.glb" 2>/dev/null | grep -q 'numErrors 0 '; then
    kept=$((kept + 1))
  else
    rm -rf "${out:?}/$name"
  fi
done < "$tmp/picked"
touch "$out/.done"
echo "bench-setup-furniture: $kept models in $out" >&2
