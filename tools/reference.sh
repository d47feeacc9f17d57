#!/bin/bash
# Puts the current `resurf COMMAND --help` texts into docs/reference.md between its markers
#   <!-- help:COMMAND --> ... <!-- end help -->
# (COMMAND "resurf" = the tool's own --help). tests/test_docs.sh runs this on a copy and fails when the file
# differs, so the reference lists every option of every command exactly as the tool knows it.
# usage: tools/reference.sh RESURF_BINARY [FILE]   (FILE defaults to docs/reference.md, rewritten in place)
set -euo pipefail
cli=${1:?usage: tools/reference.sh RESURF_BINARY [FILE]}
file=${2:-"$(dirname "$0")/../docs/reference.md"}
tmp=$(mktemp "$file.XXXXXX")
trap 'rm -f "$tmp"' EXIT
skip=0
while IFS= read -r line || [[ -n $line ]]; do
    if [[ $line =~ ^\<!--\ help:([a-z]+)\ --\>$ ]]; then
        command=${BASH_REMATCH[1]}
        printf '%s\n```\n' "$line"
        if [[ $command == resurf ]]; then "$cli" --help; else "$cli" "$command" --help; fi
        printf '```\n'
        skip=1
        continue
    fi
    if [[ $line == '<!-- end help -->' ]]; then
        skip=0
    fi
    (( skip )) || printf '%s\n' "$line"
done < "$file" > "$tmp"
mv "$tmp" "$file"
trap - EXIT
