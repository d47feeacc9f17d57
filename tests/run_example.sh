#!/usr/bin/env bash
# Runs one example program of tools/examples/ (tests/meson.build, suite 'examples'): it must exit 0 and print a
# line containing the expected text. Its whole output is shown, so the test log holds the example's figures.
# Usage: run_example.sh PROGRAM EXPECTED-TEXT
set -uo pipefail
program=$1 expected=$2
out=$("$program" 2>&1)
status=$?
printf '%s\n' "$out"
if [ $status -ne 0 ]; then
    echo "run_example: FAIL: $(basename "$program") exited with $status" >&2
    exit 1
fi
if ! grep -qF -- "$expected" <<<"$out"; then
    echo "run_example: FAIL: $(basename "$program") did not print '$expected'" >&2
    exit 1
fi
