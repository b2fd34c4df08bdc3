#!/usr/bin/env bash
# The engine under AddressSanitizer + UndefinedBehaviorSanitizer + LeakSanitizer
# (docs/reliability.md): builds ./build-san with clang (engine library, the
# GoogleTest suite, the libFuzzer targets), runs the engine tests (all but one
# capture test and the whole diagnoses not listed below) and replays every fuzz
# corpus and regression input once. Any finding fails the script.
#
#   ./scripts/sanitize.sh            build + engine tests + fuzz replays
#   FUZZ_SECONDS=300 ./scripts/sanitize.sh fuzz   also fuzz each target that long
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
B="$ROOT/build-san"
SUPP="$ROOT/fuzz/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1:check_initialization_order=1:suppressions=$SUPP/asan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SUPP/ubsan.supp"
export LSAN_OPTIONS="suppressions=$SUPP/lsan.supp:print_suppressions=0"

t0=$(date +%s)
CC=clang CXX=clang++ cmake -S "$ROOT" -B "$B" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
  -DPTEROMYS_SANITIZE=ON -DPTEROMYS_FUZZ=ON -DPTEROMYS_BUILD_PYTHON=OFF -DPTEROMYS_BUILD_BENCH=OFF \
  -DPTEROMYS_BUILD_PYTESTS=OFF >/dev/null
cmake --build "$B" -j"$(nproc)"
t1=$(date +%s)
echo "sanitize: build $((t1 - t0)) s"
# One test is left out here, not for a sanitizer finding: its 6-pixel manual
# click lands at the edge of the tracker's gate, and the clang build (any
# ASAN_OPTIONS) splits the flight in two where the g++ build does not. It runs
# in the Release suite; docs/reliability.md says more.
EXCLUDE='^(CaptureTrack\.ManualCorrectionsReplaceAddAndRemovePoints|Diagnose\..*)$'
(cd "$B" && ctest --output-on-failure -j"$(nproc)" --timeout 1800 -E "$EXCLUDE")
# The whole diagnoses (Diagnose.*) run sanitized only as listed here. Under
# ASan at -O1 a diagnosis runs 30-100 times slower than in Release: a test of
# seconds in Release takes two to fifteen minutes, and the full list took the
# CI past its 90 minutes on 2026-12-02 (docs/reliability.md). Every test of
# DiagnosisFit.* and DiagnoseStatistics.* (the fits, steps and statistics the
# diagnoses are made of) runs above; of Diagnose.* these run: the decisions
# made from given results (about a second each), the whole pipeline with and
# without --profile on baseline flights, each flight's own launch rotation,
# the second round, and the theoretical-size starts with their ramp's early
# end (one to three minutes each under ASan). A Diagnose test not listed here
# runs in the Release suite only; add it here only if it takes under three
# minutes sanitized.
SANITIZED_DIAGNOSES=(
  RefusesTooFewGlidersAndBadOptions
  SecondRoundDecisionFollowsItsRule
  IdentifiablePreferenceNamesTheEffectCoefficientsCannotImitate
  SecondRoundDoesNotHandTheVerdictBackToThePassedOverEffect
  DominantGliderSentenceNamesOnlyAGliderNoCandidateHelps
  LeaveOneGliderOutShrinkFindsAGainThatRestsOnOneGlider
  HeldOutLedStepsTakeOnlyCandidatesTheHeldOutGlidersConfirm
  FlightsOfTheBaselineModelLeaveNoGap
  EachFlightsOwnLaunchRotationIsFound
  SecondRoundFindsTheSecondEffectAndOnlyIt
  ATheoreticalSizeStartFarFromTheFlightsEndsItsRampEarly
)
INCLUDE="^Diagnose\.($(IFS='|'; echo "${SANITIZED_DIAGNOSES[*]}"))\$"
found=$(cd "$B" && ctest -N -R "$INCLUDE" | sed -n 's/^Total Tests: //p')
if [ "$found" != "${#SANITIZED_DIAGNOSES[@]}" ]; then
  echo "sanitize: $found of the ${#SANITIZED_DIAGNOSES[@]} listed Diagnose tests exist; a listed test was renamed or removed (scripts/sanitize.sh)" >&2
  exit 1
fi
(cd "$B" && ctest --output-on-failure -j"$(nproc)" --timeout 1800 -R "$INCLUDE")
t2=$(date +%s)
echo "sanitize: engine tests and fuzz replays under ASan+UBSan+LSan $((t2 - t1)) s"

if [ "${1:-}" = "fuzz" ]; then
  secs=${FUZZ_SECONDS:-300}
  for t in "$B"/fuzz/fuzz_*; do
    name=$(basename "$t"); name=${name#fuzz_}
    mkdir -p "$B/corpus/$name" "$ROOT/fuzz/regressions/$name"
    case "$name" in  # the same seeds as fuzz/CMakeLists.txt
      glider) seeds="$ROOT/examples/gliders $ROOT/examples/training $ROOT/tests/data/broken" ;;
      model) seeds="$ROOT/engine/models" ;;
      *) seeds="$ROOT/fuzz/corpus/$name" ;;
    esac
    echo "sanitize: fuzzing $name for $secs s"
    (cd "$ROOT/fuzz/regressions/$name" && "$t" -max_total_time="$secs" -timeout=30 -rss_limit_mb=2048 \
       -max_len=8192 -print_final_stats=1 "$B/corpus/$name" $seeds 2>&1 | tail -25) || true
  done
fi
