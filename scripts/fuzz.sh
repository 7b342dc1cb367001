#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/README.md) into build-fuzz/ with clang and runs each for SECONDS on
# its corpus; fails when any harness finds a crash, a hang (more than 1 s of CPU time on one input, which the
# harnesses measure themselves), more than 2 GB of memory or a sanitizer report.
# Usage: scripts/fuzz.sh [SECONDS (default 20)] [HARNESS...] (default: all of them)
#        scripts/fuzz.sh --build-only [TARGET...]: configure and build (the harnesses, or the targets named), run nothing
#   Seeds and regression inputs: tests/data/fuzz/<harness>/ (read, never written).
#   Inputs found while fuzzing: build-fuzz/corpus/<harness>/; crashes: build-fuzz/artifacts/<harness>/;
#   each run's log: build-fuzz/logs/<harness>.log.
# Environment: CHCRT_FUZZ_BUILD_DIR (default build-fuzz; scripts/test.sh uses build-asan, where the same build
#   also holds the sanitizer stage's unit tests), CHCRT_FUZZ_CXX (default clang++-14, else clang++),
#   CHCRT_FUZZ_JOBS (build jobs, default nproc),
#   CHCRT_FUZZ_PARALLEL (harnesses run at once, default nproc: SECONDS is each one's time),
#   CHCRT_FUZZ_MAX_RUNS (stop a harness after this many executions, whichever of the two limits comes first),
#   CHCRT_FUZZ_TIMEOUT (libFuzzer's -timeout: seconds of wall-clock time one input may take, default 60, a backstop
#   for an input that waits without using CPU; on a machine shared with other work a process can take far longer
#   than its CPU time, so the 1 s limit is the harnesses' CPU-time limit, tests/fuzz/fuzz_input.h).
set -euo pipefail
cd "$(dirname "$0")/.."
build_only=0
if [[ ${1:-} == --build-only ]]; then
  build_only=1
  shift
fi
seconds=20
if ((!build_only)) && [[ $# -gt 0 ]]; then
  seconds=$1
  shift
fi
all=(ply obj gltf camera_path frames scene_spec chs linespace_cache ntree_cache)
harnesses=()
((build_only)) || harnesses=("$@")
((${#harnesses[@]})) || harnesses=("${all[@]}")

cxx=${CHCRT_FUZZ_CXX:-$(command -v clang++-14 || command -v clang++ || true)}
[[ -n $cxx ]] || { echo "fuzz.sh: clang++ not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }
cc=${cxx/clang++/clang}
build=${CHCRT_FUZZ_BUILD_DIR:-build-fuzz}
if ! grep -qs '^CHCRT_FUZZ:BOOL=ON' "$build/CMakeCache.txt"; then
  # A build directory made otherwise (a GCC sanitizer build from before) is configured afresh: the compiler is set
  # only when a cache is made.
  rm -rf "$build/CMakeCache.txt" "$build/CMakeFiles"
  # Debug keeps assertions on (bugs assert, error.h); -O1 keeps executions fast and the build short; -g1 (line
  # tables) is enough for the sanitizers' stack traces and links faster than full debug information. app/ at -O0:
  # clang with ASan, UBSan and coverage took 51-57 s for app/parameters.cpp at -O1 and 23 s at -O0, and app/ was
  # 60 % of this build.
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_C_COMPILER="$cc" \
    -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DCMAKE_C_FLAGS_DEBUG="-O1 -g1" -DCHCRT_GLUE_OPTIMIZATION=-O0 \
    -DCHCRT_FUZZ=ON -DCHCRT_BUILD_VIEWER=OFF -DCHCRT_WERROR=OFF >/dev/null
fi
targets=()
if ((build_only)) && (($#)); then
  targets=("$@")
else
  for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
fi
cmake --build "$build" -j"${CHCRT_FUZZ_JOBS:-$(nproc)}" --target "${targets[@]}"
((build_only)) && exit 0

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
mkdir -p "$build/logs"

# Runs one harness; its summary line goes to build-fuzz/logs/<harness>.result.
run_one() {
  local h=$1 data=tests/data/fuzz/$1 corpus=$build/corpus/$1 artifacts=$build/artifacts/$1/ log=$build/logs/$1.log
  local status=0 runs cov took
  mkdir -p "$corpus" "$artifacts"
  # -close_fd_mask=1 silences the readers' stdout; the corpus directory named first receives new inputs.
  "$build/bin/fuzz_$h" "$corpus" "$data" -max_total_time="$seconds" ${CHCRT_FUZZ_MAX_RUNS:+-runs=$CHCRT_FUZZ_MAX_RUNS} \
    -timeout="${CHCRT_FUZZ_TIMEOUT:-60}" -rss_limit_mb=2048 -artifact_prefix="$artifacts" \
    -print_final_stats=1 -close_fd_mask=1 >"$log" 2>&1 ||
    status=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -E '^#[0-9]+' "$log" | tail -1 | grep -oE 'cov: [0-9]+ ft: [0-9]+' || echo 'cov: ? ft: ?')
  took=$(grep -oE '^Done [0-9]+ runs in [0-9]+ second' "$log" | grep -oE '[0-9]+ second' | grep -oE '[0-9]+' || echo "$seconds")
  if ((status != 0)); then
    { echo "FAIL $h (exit $status): $runs runs, $cov; log $log, inputs in $artifacts"
      grep -E 'ERROR|SUMMARY|runtime error|Test unit written|uncaught|CPU time' "$log" | head -6 || true; } >"$build/logs/$h.result"
  else
    printf 'ok   %-16s %5ss %10s runs  %s\n' "$h" "$took" "$runs" "$cov" >"$build/logs/$h.result"
  fi
}

# One harness per core at a time (CHCRT_FUZZ_PARALLEL overrides).
parallel=${CHCRT_FUZZ_PARALLEL:-$(nproc)}
for h in "${harnesses[@]}"; do
  [[ -d tests/data/fuzz/$h ]] || { echo "fuzz.sh: no corpus tests/data/fuzz/$h" >&2; exit 2; }
  rm -f "$build/logs/$h.result"
  while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
  run_one "$h" &
done
wait
failed=()
for h in "${harnesses[@]}"; do
  cat "$build/logs/$h.result"
  grep -q '^ok ' "$build/logs/$h.result" || failed+=("$h")
done
if ((${#failed[@]})); then
  echo "fuzz.sh: ${#failed[@]} harness(es) failed: ${failed[*]}" >&2
  exit 1
fi
