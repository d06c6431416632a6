#!/usr/bin/env bash
# Installs the dependencies (apt), builds everything and runs every test (unit tests and CLI tests) with CTest,
# then builds the parser and geometry stages with AddressSanitizer + UndefinedBehaviorSanitizer and runs their
# tests again (set EWIS_SANITIZE_TESTS=0 to skip that second part). The sanitized pass leaves out the statistical
# tests of many draws (they ran in the first pass; under the sanitizers they took 0.5-3 minutes each, over half of
# the pass, and the other tests of the same functions run their code paths: FilletRefine's MixedPixelsUnderACable-
# OnAPlateAreLeftOut and AWindowReachingIntoTheNextBendIsCutBack, the FilletFit, SmoothTubeFit and Pipeline tests),
# the whole inspections of several scans (the touching cables' tests run the same pipeline under them), and the
# touching cables' control without the second trace (EachIsTracedOnItsOwnSurface runs the first trace and the second),
# and the run joins' controls without the join or the mixed pixels' removal (ABendUnderACrossingCable... runs both).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
ctest --test-dir build --output-on-failure -j "$jobs" --timeout 900
if [ "${EWIS_SANITIZE_TESTS:-1}" != "0" ]; then
  sanitized="core io search filter scene sample raycast plan tubes inspect"
  targets=""
  for s in $sanitized; do targets="$targets ewis_test_$s"; done
  cmake --preset asan >/dev/null
  cmake --build build-asan -j "$jobs" --target $targets
  label_regex="^($(echo $sanitized | tr ' ' '|'))\$"
  many_draws="(FilletRefine\.(AVaryingCurvatureIsMeasuredAtItsPeakInNoise|AnArcsEndIsNoTighterBend|AShortTightArcBeatsALongLooserOne|ANarrowerWindowReadsASplinesPeak|ShortTightBendAmongLongArcs|ASmoothBendIsMeasuredAtItsPeak|AHelicalBendIsNotReadTighterAtItsEnds|AShortKinkIsReportedAtAnUpperBound|AFilletBendKeepsTheFilletsReading|ACircleFigureOnAFilletsArcIsNoBendOfItsOwn)|ScannedBend\..*|TouchingCables\.(TracedAloneTheyTakeInTheNeighbour|WithoutTheRetraceTheMovedCableTakesItsNeighbour)|RunJoins\.WithoutTheJoinOrWithTheOccludersMixedPixelsTheBendReadsWrong)\$"
  LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure -j "$jobs" --timeout 900 -L "$label_regex" -E "$many_draws"
fi
