#!/usr/bin/env bash
# The main job on the bundled default input (the Stanford dragon scan, 47,794 triangles): describe it, then write a
# Draco-compressed glTF LOD chain (MSFT_lod), every level restored onto the original's smooth surface, into out/,
# with a picture of the levels and their errors (out/dragon-lod.png).
set -euo pipefail
cd "$(dirname "$0")/.."
input=data/scans/dragon-48k.ply
mkdir -p out
build/tools/resurf info "$input"
build/tools/resurf lod "$input" -o out/dragon-lod.glb --levels 0.5,0.25,0.1 --draco --preview out/dragon-lod.png
