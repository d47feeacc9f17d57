#!/usr/bin/env bash
# The whole test suite in four parts, run in order; ends with one plain line "tests: N passed, N failed" that
# counts every test of every part (a meson test per run, a fuzz harness per run, a failed build as one failure).
#   1. release: every suite of build/ (configured and built by tools/setup.sh);
#   2. asan:    every suite again under ASan+UBSan (clang, debug build in build-asan/; leaks count as errors);
#   3. valgrind: the core suites under memcheck on the release build (any error or leak fails the suite);
#   4. fuzz:    every libFuzzer harness for FUZZ_SECONDS seconds each (default 30), via tools/fuzz.sh.
# Parts run even after a failure (so the count is complete); the exit status is non-zero if anything failed.
#   bash tools/test.sh [SUITE ...]       SUITEs limit parts 1 and 2 to those meson tests
#   TEST_PARTS=release,asan bash tools/test.sh    runs only the named parts
set -uo pipefail
cd "$(dirname "$0")/.."

parts=${TEST_PARTS:-release,asan,valgrind,fuzz}
export FUZZ_SECONDS=${FUZZ_SECONDS:-30}
passed=0
failed=0

has_part() { [[ ",$parts," == *",$1,"* ]]; }

# Adds a meson test log's results to the totals (OK and expected failures pass; skips are not counted).
count_log() {
  local counts
  counts=$(python3 - "$1" <<'PY'
import json, sys
passed = failed = 0
for line in open(sys.argv[1]):
    r = json.loads(line)["result"]
    if r in ("OK", "EXPECTEDFAIL"): passed += 1
    elif r != "SKIP": failed += 1
print(passed, failed)
PY
) || counts="0 1"
  passed=$((passed + ${counts% *}))
  failed=$((failed + ${counts#* }))
}

# Runs `meson test` in a build folder (already built) and counts its log. Extra arguments go to meson test.
run_meson_tests() {
  local build=$1 log=$2
  shift 2
  rm -f "$build/meson-logs/$log"
  meson test -C "$build" --no-rebuild --print-errorlogs "$@"
  if [ -f "$build/meson-logs/$log" ]; then
    count_log "$build/meson-logs/$log"
  else
    echo "test: no test log in $build" >&2
    failed=$((failed + 1))
  fi
}

# Builds a folder; on failure counts one failed test and returns 1.
build() {
  if ! ninja -C "$1" >"$1/build.log" 2>&1; then
    tail -n 40 "$1/build.log" >&2
    echo "test: building $1 failed" >&2
    failed=$((failed + 1))
    return 1
  fi
}

part() { printf '\n==== %s ====\n' "$*"; }

start=$SECONDS

if has_part release; then
  part "1/4 release suite (build/)"
  if [ ! -f build/build.ninja ]; then
    meson setup build --buildtype=release -Dwerror=true >/dev/null
  fi
  build build && release_built=1 && run_meson_tests build testlog.json "$@"
fi

if has_part asan; then
  part "2/4 ASan+UBSan suite (build-asan/, clang debug)"
  # clang: gcc's ASan takes minutes over the tinygltf translation unit. -Db_lundef=false: clang's sanitizer
  # runtime is linked into executables only. No vptr/function checks in C++: their handlers live in the C++ UBSan
  # runtime, which a C program linking libresurf (the packaging test's consumers) does not get.
  if [ ! -f build-asan/build.ninja ]; then
    CC=clang CXX=clang++ meson setup build-asan -Dbuildtype=debug -Db_sanitize=address,undefined \
      -Db_lundef=false -Dbenchmarks=false -Dcpp_args=-fno-sanitize=vptr,function >/dev/null
  fi
  if build build-asan; then
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      run_meson_tests build-asan testlog.json "$@"
  fi
fi

if has_part valgrind; then
  part "3/4 core suites under valgrind (build/, memcheck)"
  # Every suite but the simplifier's simplify_* (minutes under memcheck; ASan+UBSan runs them in part 2; its
  # queue's suite runs here) and those that only drive the CLI (whose processes memcheck does not follow). The
  # valgrind setup sets RESURF_TEST_LIGHT, as the sanitizer build does (tests/meson.build).
  core=(mesh mesh_arrays alloc weld adjacency validate repair io io_obj io_ply io_off io_stl io_corpus bvh normals
        curvature optdir glide restore smooth metrics quadric simplify_queue attributes gltf_read gltf_write
        gltf_self_contained gltf_schema scene_lods scene_world morph meshopt_decode)
  # Only the suites that exist (tests/meson.build builds a suite once its file is there).
  existing=$(meson test -C build --list 2>/dev/null | sed -n 's/^resurf \/ //p')
  suites=()
  for s in "${core[@]}"; do
    grep -qx "$s" <<<"$existing" && suites+=("$s")
  done
  # The release build, built by part 1 (a failed build there is counted once, there).
  if [ -n "${release_built:-}" ]; then
    run_meson_tests build testlog-valgrind.json --setup valgrind "${suites[@]}"
  elif has_part release; then
    echo "test: no valgrind run: the release build failed" >&2
  elif [ ! -f build/build.ninja ]; then
    echo "test: build/ is not configured (run tools/setup.sh)" >&2
    failed=$((failed + 1))
  elif build build; then
    run_meson_tests build testlog-valgrind.json --setup valgrind "${suites[@]}"
  fi
fi

if has_part fuzz; then
  part "4/4 fuzz harnesses, ${FUZZ_SECONDS} s each (build-fuzz/)"
  fuzz_out=$(mktemp)
  fuzz_status=0
  bash tools/fuzz.sh "$FUZZ_SECONDS" | tee "$fuzz_out" || fuzz_status=$?
  # tools/fuzz.sh prints "harness executions crashes corpus" rows; a missing table is a failure (the build), and
  # so is a failing exit status that no row explains.
  rows=$(awk '/^[a-z0-9_]+ +[0-9?]+ +[0-9]+ +[0-9]+ files$/ {print $3}' "$fuzz_out")
  if [ -z "$rows" ] || { [ "$fuzz_status" -ne 0 ] && ! grep -qw '[1-9]' <<<"$rows"; }; then
    failed=$((failed + 1))
  else
    for crashes in $rows; do
      if [ "$crashes" -eq 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
    done
  fi
  rm -f "$fuzz_out"
fi

printf '\n(%d s)\n' $((SECONDS - start))
echo "tests: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
