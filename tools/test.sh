#!/usr/bin/env bash
# Runs the whole test suite of build/ and ends with one plain line "tests: N passed, N failed".
set -uo pipefail
cd "$(dirname "$0")/.."
meson test -C build --print-errorlogs "$@"
rc=$?
python3 - <<'PY' || true
import json
passed = failed = 0
for line in open("build/meson-logs/testlog.json"):
    r = json.loads(line)["result"]
    if r in ("OK", "EXPECTEDFAIL", "SKIP"): passed += r != "SKIP"
    else: failed += 1
print(f"tests: {passed} passed, {failed} failed")
PY
exit $rc
