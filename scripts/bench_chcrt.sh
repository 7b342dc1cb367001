#!/usr/bin/env bash
# CHC+RT comparison tables (culling/README.md, docs/benchmarks.md), all through `chcrt bench`, which
# traces the same rays with every method in one process (ratios within a run):
#   Table 2  ms/frame and speedup vs pure BVH GLSL, near/far walkthrough x ray type (primary 1 spp, shadow 16 spp,
#            AO 20 spp short rays, diffuse 20 spp), methods bvh, chcrt (adaptive), chcrt-noadapt (always culls);
#            with the share of chcrt's traces that culled, their mean height, the steps ratio and the culling
#            efficiency (noadapt speedup / steps ratio);
#   Figure 8 time per phase (Phase 1/2/3, reductions, pair decisions, cell lists) of chcrt-noadapt, same runs;
#   Table 4  aggressive thresholds 0/20/100/200 rays (chcrt-aggressive --chcrt-threshold T), near path, primary and
#            AO, with the differing hit pixels (the image error of culled hits);
#   Table 5  per-pixel sample rotation 0/18/36/360 degrees (--rotation), near path, AO and diffuse.
#   work     (opt-in, CHCRT_BENCH_TABLES="work") how much traversal culling can save: BVH traversal steps per
#            active ray (`bench --steps`) of pure BVH and always-culling CHC+RT per termination height
#            (CHCRT_BENCH_HEIGHTS, default "24 18 14 10 8 6"), near path, 1 spp per ray type, next to the times.
# Usage: scripts/bench_chcrt.sh [build dir (build)] [out dir (out/bench/chcrt)] [scene ...]
#   scenes: city interior plant castle (default: all; castle only when ../shared/scenes/intel_castle exists)
# Environment: CHCRT_BENCH_SIZE (256: width = height), CHCRT_BENCH_FRAMES (0-15: consecutive frames, so that
#   temporal coherence works), CHCRT_BENCH_RUNS (1 timed run after 1 warm-up), CHCRT_BENCH_CASTLE_RUNS (8: the
#   castle is one view, so its runs are what temporal coherence and the adaptive rule see), CHCRT_BENCH_TABLES
#   ("2 4 5").
# Output: <out>/<scene>_<table>_*.json (bench rows), and <out>/<scene>_table2.md|csv, _figure8.md|csv,
#   _table4.md|csv, _table5.md|csv, _work.md|csv.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/bench/chcrt}
shift $(( $# > 2 ? 2 : $# )) || true
scenes=("$@")
((${#scenes[@]})) || scenes=(city interior plant castle)
chcrt="$build/bin/chcrt"
size=${CHCRT_BENCH_SIZE:-256}
frames=${CHCRT_BENCH_FRAMES:-0-15}
runs=${CHCRT_BENCH_RUNS:-1}
tables=${CHCRT_BENCH_TABLES:-"2 4 5"}
mkdir -p "$out"
castle=../shared/scenes/intel_castle/castle.gltf

spp_of() { case $1 in primary) echo 1;; shadow) echo 16;; *) echo 20;; esac; }

for scene in "${scenes[@]}"; do
  if [[ $scene == castle ]]; then
    if [[ ! -f $castle ]]; then echo "bench_chcrt: $castle not found, skipping the castle"; continue; fi
    # Street-level camera of ../shared/scenes/README.md; a single view, so frame 0 repeated over the runs.
    scene_args=(--scene "$castle" --eye 27,2,-47 --target 41,8,50 --fov 60)
    paths=(street)
    scene_frames=0
    scene_runs=${CHCRT_BENCH_CASTLE_RUNS:-8}
  else
    scene_args=(--scene "$scene")
    paths=(near far)
    scene_frames=$frames
    scene_runs=$runs
  fi
  common=(-q --width "$size" --height "$size" --frames "$scene_frames" --runs "$scene_runs" --warmup 1 "${scene_args[@]}")
  path_args() { [[ $1 == street ]] || echo "--camera-path $1"; }
  if [[ " $tables " == *" 2 "* ]]; then
    for path in "${paths[@]}"; do
      for ray in primary shadow ao diffuse; do
        echo "bench_chcrt: $scene table 2, $path, $ray"
        # shellcheck disable=SC2046
        "$chcrt" bench "${common[@]}" $(path_args "$path") --ray-type "$ray" --spp "$(spp_of $ray)" \
          --method bvh,chcrt,chcrt-noadapt --steps --json "$out/${scene}_table2_${path}_${ray}.json"
      done
    done
  fi
  if [[ " $tables " == *" 4 "* ]]; then
    path=${paths[0]}
    for ray in primary ao; do
      for t in 0 20 100 200; do
        echo "bench_chcrt: $scene table 4, threshold $t, $ray"
        # shellcheck disable=SC2046
        "$chcrt" bench "${common[@]}" $(path_args "$path") --ray-type "$ray" --spp "$(spp_of $ray)" \
          --method bvh,chcrt-aggressive --chcrt-threshold "$t" --json "$out/${scene}_table4_${ray}_t${t}.json"
      done
    done
  fi
  if [[ " $tables " == *" 5 "* ]]; then
    path=${paths[0]}
    for ray in ao diffuse; do
      for r in 0 18 36 360; do
        echo "bench_chcrt: $scene table 5, rotation $r, $ray"
        # shellcheck disable=SC2046
        "$chcrt" bench "${common[@]}" $(path_args "$path") --ray-type "$ray" --spp "$(spp_of $ray)" \
          --rotation "$r" --method bvh,chcrt,chcrt-noadapt --json "$out/${scene}_table5_${ray}_r${r}.json"
      done
    done
  fi
  if [[ " $tables " == *" work "* ]]; then
    path=${paths[0]}
    for h in ${CHCRT_BENCH_HEIGHTS:-24 18 14 10 8 6}; do
      for ray in primary shadow ao diffuse; do
        echo "bench_chcrt: $scene work, height $h, $ray"
        # shellcheck disable=SC2046
        "$chcrt" bench "${common[@]}" $(path_args "$path") --ray-type "$ray" --spp 1 --chcrt-height "$h" --steps \
          --method bvh,chcrt-noadapt --json "$out/${scene}_work_h${h}_${ray}.json"
      done
    done
  fi
  python3 scripts/chcrt_tables.py "$out" "$scene"
done
