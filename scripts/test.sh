#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (the README's test command; .ci/run runs exactly this):
#   1. scripts/setup.sh (packages when missing, configure, build into build/) and ctest over all tests;
#   2. unless --no-sanitize: a second build (build-asan/) with clang, AddressSanitizer + UndefinedBehaviorSanitizer
#      and libFuzzer's coverage instrumentation (CHCRT_FUZZ; Debug at -O1, so asserts are on), running the
#      unit-labelled tests (the GL tests run inside Mesa's llvmpipe, whose own allocations are not ours to
#      sanitize), the fuzz harnesses' seed and regression replays among them;
#   3. unless --no-fuzz (or --no-sanitize): scripts/fuzz.sh fuzzes each harness for 10 s in that same build, two at
#      a time, replaying every seed and regression input under tests/data/fuzz/ first (tests/fuzz/README.md).
# One build serves stages 2 and 3; what they add to the run is in docs/benchmarks.md, "Tests and CI".
# Viewer tests (label viewer) start their own Xvfb.
set -euo pipefail
cd "$(dirname "$0")/.."
sanitize=1
fuzz=1
for arg in "$@"; do
  [[ $arg == --no-sanitize ]] && sanitize=0
  [[ $arg == --no-fuzz ]] && fuzz=0
done
if [[ ${CI:-} == true ]]; then export CHCRT_WERROR=ON; fi

scripts/setup.sh
ctest --test-dir build --output-on-failure -j2 --timeout 600

if ((sanitize)); then
  export CHCRT_FUZZ_BUILD_DIR=build-asan
  scripts/fuzz.sh --build-only unit_tests fuzz_targets
  # LeakSanitizer on: every test must free what it allocated (tests/lsan.supp: a library's own leak).
  ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j2 -L unit --timeout 600
  if ((fuzz)); then
    # 10 s each, not 20: the whole run took 1784 s of CI's 30 minutes with 20; longer runs by hand.
    scripts/fuzz.sh 10
  fi
fi
