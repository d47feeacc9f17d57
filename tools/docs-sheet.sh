#!/usr/bin/env bash
# Refreshes docs/dragon-lod.png, the README's picture of the main job: the same levels as tools/main-job.sh (the
# dragon scan at 0.5, 0.25, 0.1), drawn by `resurf lod --preview` at a size for a web page. Needs build/.
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
build/tools/resurf lod data/scans/dragon-48k.ply -o "$tmp/dragon-lod.glb" --levels 0.5,0.25,0.1 --draco \
  --preview docs/dragon-lod.png --preview-size 1200x480 >/dev/null
echo "wrote docs/dragon-lod.png"
