#!/bin/bash
# docs/reference.md shows every command's --help text as the built tool prints it (tools/reference.sh fills the
# blocks); a changed option without a refreshed reference fails here.
# usage: test_docs.sh RESURF_BINARY SOURCE_DIR
set -euo pipefail
cli=$1 src=$2
copy=$(mktemp)
trap 'rm -f "$copy"' EXIT
cp "$src/docs/reference.md" "$copy"
bash "$src/tools/reference.sh" "$cli" "$copy"
if ! diff -u "$src/docs/reference.md" "$copy"; then
    echo "docs/reference.md is out of date: run 'bash tools/reference.sh build/tools/resurf'" >&2
    exit 1
fi
for command in info convert restore smooth compare simplify lod preview; do
    grep -q "^<!-- help:$command -->\$" "$src/docs/reference.md" || { echo "no help block for '$command'" >&2; exit 1; }
done
