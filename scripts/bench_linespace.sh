#!/usr/bin/env bash
# Line Space comparison tables (linespace/README.md, docs/benchmarks.md) as a report: `chcrt report --preset
# linespace` (docs/report.md) runs the benches (the same rays for every method of a bench; approximate methods'
# whole frames rendered with pure BVH and with the method for the image error) and writes tables, figures, page:
#   RC Table 1 shape  (rc, study ls-rc) pure BVH, bvh+ls-exact and bvh+ls per depth in CHCRT_LS_DEPTHS: primary,
#                     AO and diffuse rays, shadows exact (--ls-modes shadow=exact,bounce=exact,ao=off, named in
#                     full since bvh+ls's own defaults differ), Line Space build s and MB, speedup, image error;
#   SS Table 1 shape  (ss, study ls-ss) 25 shadow rays per pixel, bvh+ls with shadow termination for N in
#                     CHCRT_LS_SS_N at depth CHCRT_LS_SS_DEPTH; shadow samples differing, pixels > 2/255;
#   N-tree rows       (ntree, study ls-ntree) the same 25 shadow rays over ntree+ls for N:d in CHCRT_LS_NTREE
#                     (start node skipped as SS §4.1; --ls-ntree-near CHCRT_LS_NTREE_NEAR);
#   SS candidates     (opt-in sscand, study ls-sscand) shadow=candidate for the N:D pairs in CHCRT_LS_SS_CANDIDATE;
#   AO candidates     (opt-in ao, study ls-ao) ao=candidate with faces=both / front-start and candidate-exact-start.
# CHCRT_LS_TABLES selects the tables ("rc ss ntree", default).
# Usage: scripts/bench_linespace.sh [build dir (build)] [out dir (out/bench/linespace)] [scene ...]
#   scenes: city interior bunny dragon castle (default: all; the last three only when ../shared/scenes has them)
# Environment: CHCRT_BENCH_SIZE (256), CHCRT_BENCH_FRAMES (0,5), CHCRT_BENCH_RUNS (3), CHCRT_LS_DEPTHS ("6 9"),
#   CHCRT_LS_SPP (1: samples per pixel of the RC and AO tables; every pixel of a pass shares one Halton direction,
#   CHC+RT §5.3, so a 1-spp image error depends on that one direction: use 4 or more for error figures),
#   CHCRT_LS_N (6), CHCRT_LS_SS_N ("4 6"), CHCRT_LS_SS_DEPTH (9), CHCRT_LS_CACHE (out/cache/linespace),
#   CHCRT_LS_NTREE ("4:4 6:3 8:3"), CHCRT_LS_SS_CANDIDATE ("7:11 8:11"), CHCRT_LS_NTREE_NEAR (0).
# Output: <out>/index.html, report.md, tables/linespace.md|csv, figures/, data/*.json (bench rows); an interrupted
#   run resumes from the benches already measured.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/bench/linespace}
shift $(( $# > 2 ? 2 : $# )) || true
scenes=("$@")
((${#scenes[@]})) || scenes=(city interior bunny dragon castle)
shared=../shared/scenes
list=()
for scene in "${scenes[@]}"; do
  case $scene in
    bunny) file=$shared/stanford_bunny/bunny.glb; entry=$file ;;
    dragon) file=$shared/stanford_dragon/dragon.glb; entry=$file ;;
    castle) file=$shared/intel_castle/castle.gltf; entry="$file@scripts/report/castle_street.json" ;;
    *) file=""; entry=$scene ;;
  esac
  if [[ -n $file && ! -f $file ]]; then echo "bench_linespace: $file not found, skipping $scene"; continue; fi
  list+=("$entry")
done
studies=()
for t in ${CHCRT_LS_TABLES:-rc ss ntree}; do
  case $t in rc|ss|ntree|ao|sscand) studies+=("ls-$t") ;; *) studies+=("$t") ;; esac
done
join() { local IFS=,; echo "$*"; }
exec "$build/bin/chcrt" report --preset linespace --out "$out" --scenes "$(join "${list[@]}")" \
  --studies "$(join "${studies[@]}")" --size "${CHCRT_BENCH_SIZE:-256}" --frames "${CHCRT_BENCH_FRAMES:-0,5}" \
  --runs "${CHCRT_BENCH_RUNS:-3}" --single-view-runs "${CHCRT_BENCH_RUNS:-3}" --ls-spp "${CHCRT_LS_SPP:-1}" \
  --ls-depths "$(join ${CHCRT_LS_DEPTHS:-6 9})" --ls-n "${CHCRT_LS_N:-6}" --ls-ss-n "$(join ${CHCRT_LS_SS_N:-4 6})" \
  --ls-ss-depth "${CHCRT_LS_SS_DEPTH:-9}" --ls-cache "${CHCRT_LS_CACHE:-out/cache/linespace}" \
  --ls-ntree "$(join ${CHCRT_LS_NTREE:-4:4 6:3 8:3})" --ls-ss-candidate "$(join ${CHCRT_LS_SS_CANDIDATE:-7:11 8:11})" \
  --ls-ntree-near "${CHCRT_LS_NTREE_NEAR:-0}"
