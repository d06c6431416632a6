#!/bin/bash
# Builds the libFuzzer targets (clang, ASan+UBSan), makes the seed corpora, replays the regression inputs and
# fuzzes every parser for SECONDS each (one process at a time). Findings land in BUILD/artifacts/<target>/.
#
#   tests/fuzz/run.sh SECONDS [TARGET...]      targets: ply pcd xyz plan pose mesh_obj mesh_stl mesh_ply
#
# Environment: EWIS_FUZZ_BUILD (default <repo>/build-fuzz), EWIS_REALDATA (default <repo>/../shared/realdata),
# EWIS_FUZZ_JOBS (ninja -j, default 2). The corpus in BUILD/corpus/<target> grows across runs (the long runs
# continue where the short ones stopped). Exit code 1 when any target crashed, leaked, timed out or ran out of
# memory (including on a regression input).
# EWIS_FUZZ_SKIP_KNOWN=1 tolerates the findings already reported and not yet fixed (known.supp and the targets'
# own checks), so a run can look for new ones; without it every finding counts (and a corpus that holds an input
# of an unfixed finding stops its target at once).
set -u
SECONDS_PER_TARGET=${1:?usage: run.sh SECONDS [TARGET...]}
shift
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
BUILD=${EWIS_FUZZ_BUILD:-$ROOT/build-fuzz}
REALDATA=${EWIS_REALDATA:-$ROOT/../shared/realdata}
JOBS=${EWIS_FUZZ_JOBS:-2}
ALL_TARGETS="ply pcd xyz plan pose mesh_obj mesh_stl mesh_ply"
TARGETS=${*:-$ALL_TARGETS}

command -v clang++ >/dev/null || { echo "run.sh: clang++ missing (apt-get install clang libclang-rt-14-dev)" >&2; exit 2; }

# --- build
if [ ! -f "$BUILD/build.ninja" ]; then
  mkdir -p "$BUILD"
  CC=clang CXX=clang++ cmake -G Ninja -S "$HERE" -B "$BUILD" >"$BUILD/configure.log" 2>&1 ||
    { cat "$BUILD/configure.log" >&2; exit 2; }
fi
build_targets=""
for t in $TARGETS; do build_targets="$build_targets fuzz_$t"; done
ninja -C "$BUILD" -j "$JOBS" $build_targets || { echo "run.sh: build failed" >&2; exit 2; }

# --- seeds (regression inputs included)
rm -rf "$BUILD/seeds"
/usr/bin/python3 "$HERE/make_seeds.py" "$BUILD/seeds" "$REALDATA" >/dev/null || exit 2

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$HERE/lsan.supp:print_suppressions=0}
UBSAN_DEFAULT=print_stacktrace=1:halt_on_error=1
[ -n "${EWIS_FUZZ_SKIP_KNOWN:-}" ] && UBSAN_DEFAULT=$UBSAN_DEFAULT:suppressions=$HERE/known.supp
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-$UBSAN_DEFAULT}
export EWIS_FUZZ_TMP=${EWIS_FUZZ_TMP:-/dev/shm}
COMMON_FLAGS=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1)

summary="$BUILD/fuzz-summary.md"
{
  echo "| target | seconds | runs | executions | exec/s | coverage (edges) | features | corpus | findings |"
  echo "|---|---|---|---|---|---|---|---|---|"
} >"$summary"
status=0
for t in $TARGETS; do
  bin="$BUILD/bin/fuzz_$t"
  corpus="$BUILD/corpus/$t"
  art="$BUILD/artifacts/$t"
  logs="$BUILD/logs/$t"
  mkdir -p "$corpus" "$art" "$logs"
  dict=()
  [ -f "$HERE/dict/$t.dict" ] && dict=(-dict="$HERE/dict/$t.dict")

  # 1. the regression inputs: each must now run clean; then they seed the run too
  reg="$HERE/regressions/$t"
  extra=()
  if [ -d "$reg" ] && [ -n "$(ls -A "$reg")" ]; then
    if "$bin" "${COMMON_FLAGS[@]}" "$reg"/* >"$logs/regressions.log" 2>&1; then
      extra=("$reg")
    else
      echo "REGRESSION $t: an input in $reg still fails (see $logs/regressions.log)" >&2
      status=1
    fi
  fi

  # 2. fuzz for SECONDS; libFuzzer stops at the first finding, so restart (at most 20 times) until time is up
  before=$(ls "$art" | wc -l)
  start=$(date +%s)
  execs=0 cov=0 ft=0 runs=0
  while :; do
    left=$((SECONDS_PER_TARGET - ($(date +%s) - start)))
    [ "$left" -gt 0 ] && [ "$runs" -lt 20 ] || break
    runs=$((runs + 1))
    log="$logs/run$runs.log"
    "$bin" "${COMMON_FLAGS[@]}" "${dict[@]}" -max_total_time="$left" -artifact_prefix="$art/" \
      "$corpus" "$BUILD/seeds/$t" "${extra[@]}" >"$log" 2>&1
    rc=$?
    e=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    execs=$((execs + ${e:-0}))
    c=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
    f=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
    [ "${c:-0}" -gt "$cov" ] && cov=$c
    [ "${f:-0}" -gt "$ft" ] && ft=$f
    if [ $rc -ne 0 ]; then
      echo "FINDING $t (run $runs, exit $rc): $(grep -m1 -E 'ERROR: |runtime error|fuzz invariant|terminate called|out-of-memory|timeout' "$log")" >&2
      # a finding on the very first input of a run would loop: give up on this target then
      grep -q 'INITED' "$log" || break
    fi
  done
  found=$(( $(ls "$art" | wc -l) - before ))
  [ "$found" -gt 0 ] && status=1
  elapsed=$(( $(date +%s) - start ))
  rate=$(( execs / (elapsed > 0 ? elapsed : 1) ))
  echo "| $t | $elapsed | $runs | $execs | $rate | $cov | $ft | $(ls "$corpus" | wc -l) | $found |" >>"$summary"
  echo "fuzz_$t: ${elapsed}s, $execs executions, cov $cov, ft $ft, $found new findings" >&2
done
echo >&2
cat "$summary" >&2
ls "$BUILD"/artifacts/*/ 2>/dev/null | grep -E 'crash|leak|timeout|oom|slow' >&2 && echo "findings in $BUILD/artifacts" >&2
exit $status
