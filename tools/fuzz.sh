#!/usr/bin/env bash
# Runs every libFuzzer harness for SECONDS each (default 60) on its committed seed corpus (tests/fuzz/corpus/NAME)
# plus a scratch corpus under build-fuzz/. Crashes are written to build-fuzz/crashes/; the script fails on any.
#   bash tools/fuzz.sh [SECONDS] [NAME ...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ meson setup build-fuzz -Dbuildtype=debugoptimized -Dfuzz=true -Dtests=false \
    -Dbenchmarks=false -Db_sanitize=address,undefined -Db_lundef=false >/dev/null
fi
if ! ninja -C build-fuzz >build-fuzz/build.log 2>&1; then
  tail -n 40 build-fuzz/build.log >&2
  echo "fuzz: building build-fuzz failed" >&2
  exit 1
fi
names=("$@")
# Every harness executable (not the fuzz_NAME.p object folders beside them).
[ ${#names[@]} -gt 0 ] ||
  names=($(find build-fuzz/tests/fuzz -maxdepth 1 -type f -perm -u+x -name 'fuzz_*' | sed 's|.*/fuzz_||' | sort))
mkdir -p build-fuzz/crashes
status=0
printf '%-8s %12s %8s %s\n' harness executions crashes corpus
for name in "${names[@]}"; do
  scratch=build-fuzz/corpus/$name
  mkdir -p "$scratch"
  log=build-fuzz/fuzz_$name.log
  # A dictionary where one helps: glTF JSON (also the JSON chunk of a .glb).
  dict=()
  case $name in
    gltf | glb) dict=(-dict=tests/fuzz/gltf.dict) ;;
  esac
  # Limits: any single allocation over 2 GiB is a finding everywhere. Draco inputs (drc, glb) get more time and
  # resident memory per input: Debian's libdraco 1.5.5 trusts a texture-coordinate count of the payload, so a
  # corrupt 300-byte payload can cost it 3.5 s and 165 MB (over 10 s under ASan) before it fails cleanly — a
  # known limit of that Draco release (later releases check the count), not a resurf fault to report.
  limits=(-malloc_limit_mb=2048 -rss_limit_mb=2048 -timeout=10)
  case $name in
    drc | glb) limits=(-malloc_limit_mb=2048 -rss_limit_mb=6144 -timeout=120) ;;
  esac
  if UBSAN_OPTIONS=halt_on_error=1 build-fuzz/tests/fuzz/fuzz_$name "$scratch" "tests/fuzz/corpus/$name" \
      "${dict[@]}" "${limits[@]}" -max_total_time="$seconds" -max_len=65536 \
      -print_final_stats=1 -artifact_prefix=build-fuzz/crashes/"$name"- >"$log" 2>&1; then
    crashes=0
  else
    crashes=1
    status=1
  fi
  # Executions: the stat::number_of_executed_units line of -print_final_stats=1 (printed after crashes too).
  # Failing that (a run killed from outside), the last status line's "#N", at the start of its line only: "#N"
  # elsewhere in the log is text of a dictionary word (a recommended-dictionary entry or a mutation's "DE:"), which
  # is how the STL harness's row once said 0.
  execs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9][0-9]*\)$/\1/p' "$log" | tail -n 1)
  [ -n "$execs" ] || execs=$(sed -n 's/^#\([0-9][0-9]*\)[[:space:]].*/\1/p' "$log" | tail -n 1)
  printf '%-8s %12s %8s %s\n' "$name" "${execs:-?}" "$crashes" "$(ls "$scratch" | wc -l) files"
  [ $crashes -eq 0 ] || tail -30 "$log"
done
exit $status
