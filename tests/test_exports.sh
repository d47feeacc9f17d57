#!/usr/bin/env bash
# Symbol visibility test: the shared library exports the public API and nothing else. The library is compiled
# with -fvisibility=hidden and only RESURF_API declarations are made visible, so every dynamic symbol must be a
# resurf_ function declared RESURF_API in the public headers (include/resurf/*.h); internal resurfi_ functions, static helpers
# and anything linked in (a C++ glTF shim, tinygltf, Draco) must stay hidden.
# Called by tests/meson.build: test_exports.sh LIBRESURF.SO LIBRESURF.A HEADER...
set -euo pipefail
so=$1 archive=$2
shift 2
headers=("$@")
fail() { echo "test_exports: FAIL: $*" >&2; exit 1; }

exported=$(nm -D --defined-only "$so" | awk 'NF >= 3 {print $3}' | sort -u)
[ -n "$exported" ] || fail "$so exports nothing"
# The declared API: every name that follows RESURF_API ... up to its '(' (declarations may span lines).
declared=$(cat "${headers[@]}" | tr '\n' ' ' | grep -o 'RESURF_API[^;(]*(' | grep -o 'resurf_[A-Za-z0-9_]*[[:space:]]*($' |
    tr -d '( ' | sort -u)
[ -n "$declared" ] || fail "no RESURF_API declarations found in ${headers[*]}"

bad=$(comm -23 <(echo "$exported") <(echo "$declared"))
[ -z "$bad" ] || fail "exported but not declared RESURF_API in the headers:"$'\n'"$bad"
for name in resurf_version resurf_status_string resurf_mesh_create resurf_mesh_free resurf_mesh_validate; do
    grep -qx "$name" <<<"$exported" || fail "$name is not exported"
done
# The check above means something only if there are internal functions to hide: the archive has them.
# (Captured, not piped into grep -q: an early exit of grep would kill nm with SIGPIPE under pipefail.)
internal=$(nm --defined-only "$archive" | awk '$2 == "T" && $3 ~ /^resurfi_/ {print $3}')
[ -n "$internal" ] || fail "no resurfi_ functions in $archive (test is void)"

echo "$(wc -l <<<"$exported") exported symbols, all declared RESURF_API in the public headers"
