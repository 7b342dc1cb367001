#!/usr/bin/env bash
# CHC+RT comparison tables (culling/README.md, docs/benchmarks.md) as a report: `chcrt report --preset paper`
# (docs/report.md) runs the benches and writes the tables, figures and page:
#   Table 2  ms/frame and speedup vs pure BVH, near/far walkthrough x ray type (primary 1 spp, shadow 16 spp, AO 20
#            spp, diffuse 20 spp), methods bvh, chcrt, chcrt-noadapt, with culled share, mean height, steps ratio
#            and culling efficiency (study compare, bench --steps); Figure 8 (time per phase) from the same runs;
#   Table 4  aggressive thresholds 0/20/100/200 rays, near path, primary and AO (study aggressive);
#   Table 5  per-pixel sample rotation 0/18/36/360 degrees, near path, AO and diffuse (study rotation);
#   work     (opt-in, CHCRT_BENCH_TABLES="work") BVH traversal steps per forced termination height
#            (CHCRT_BENCH_HEIGHTS, default "24 18 14 10 8 6").
# Usage: scripts/bench_chcrt.sh [build dir (build)] [out dir (out/bench/chcrt)] [scene ...]
#   scenes: city interior plant castle (default: all; castle only when ../shared/scenes/intel_castle exists, as
#   its street view scripts/report/castle_street.json)
# Environment: CHCRT_BENCH_SIZE (256), CHCRT_BENCH_FRAMES (0-15), CHCRT_BENCH_RUNS (1 timed run after 1 warm-up),
#   CHCRT_BENCH_CASTLE_RUNS (8: the castle is one view, so its runs are what temporal coherence sees),
#   CHCRT_BENCH_TABLES ("2 4 5"; add "images" for the debug and difference images).
# Output: <out>/index.html, report.md, tables/*.md|csv, figures/*.png|svg|csv, data/*.json (bench rows); an
#   interrupted run resumes from the benches already measured.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/bench/chcrt}
shift $(( $# > 2 ? 2 : $# )) || true
scenes=("$@")
((${#scenes[@]})) || scenes=(city interior plant castle)
castle=../shared/scenes/intel_castle/castle.gltf
list=()
for scene in "${scenes[@]}"; do
  if [[ $scene == castle ]]; then
    if [[ ! -f $castle ]]; then echo "bench_chcrt: $castle not found, skipping the castle"; continue; fi
    list+=("$castle@scripts/report/castle_street.json")
  else
    list+=("$scene")
  fi
done
studies=()
for t in ${CHCRT_BENCH_TABLES:-2 4 5}; do
  case $t in 2) studies+=(compare) ;; 4) studies+=(aggressive) ;; 5) studies+=(rotation) ;; *) studies+=("$t") ;; esac
done
heights=${CHCRT_BENCH_HEIGHTS:-24 18 14 10 8 6}
join() { local IFS=,; echo "$*"; }
exec "$build/bin/chcrt" report --preset paper --out "$out" --scenes "$(join "${list[@]}")" \
  --studies "$(join "${studies[@]}")" --size "${CHCRT_BENCH_SIZE:-256}" --frames "${CHCRT_BENCH_FRAMES:-0-15}" \
  --runs "${CHCRT_BENCH_RUNS:-1}" --single-view-runs "${CHCRT_BENCH_CASTLE_RUNS:-8}" --heights "$(join $heights)"
