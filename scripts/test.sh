#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (the README's test command; .ci/run runs exactly this):
#   1. scripts/setup.sh (packages when missing, configure, build into build/) and ctest over all tests;
#   2. unless --no-sanitize: a second build (build-asan/) with AddressSanitizer + UndefinedBehaviorSanitizer,
#      running the unit-labelled tests (the GL tests run inside Mesa's llvmpipe, whose own allocations are not
#      ours to sanitize);
#   3. unless --no-fuzz: scripts/fuzz.sh builds the libFuzzer harnesses with clang (build-fuzz/) and runs each for
#      20 s, two at a time, on its seeds, replaying every seed and regression input under tests/data/fuzz/ first
#      (tests/fuzz/README.md; what this stage adds to the run: docs/benchmarks.md, "Tests and CI").
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
  # Warnings are checked by the regular build: GCC 12's -Wmaybe-uninitialized reports false positives inside
  # libstdc++ (<regex>, <functional>) once sanitizer instrumentation is on, so -Werror stays off here.
  CHCRT_BUILD_DIR=build-asan CHCRT_SANITIZE=ON CHCRT_WERROR=OFF CHCRT_BUILD_TYPE=RelWithDebInfo \
    CHCRT_BUILD_TARGET=unit_tests CHCRT_CMAKE_ARGS="-DCHCRT_BUILD_VIEWER=OFF" scripts/setup.sh
  ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build-asan --output-on-failure -j2 -L unit --timeout 600
fi

if ((fuzz)); then
  scripts/fuzz.sh 20
fi
