#!/usr/bin/env bash
# The main job on the bundled default input (the Stanford dragon, 48k triangles): describe it and convert it.
set -euo pipefail
cd "$(dirname "$0")/.."
input=data/scans/dragon-48k.ply
mkdir -p out
build/tools/resurf info "$input"
build/tools/resurf convert "$input" out/dragon.obj
build/tools/resurf info out/dragon.obj --json
