#!/usr/bin/env bash
# Line Space comparison tables (issue #4; linespace/README.md, docs/benchmarks.md), all through `chcrt bench`,
# which traces the same rays with every method in one process (ratios within a run) and, for approximate
# methods, renders whole frames with pure BVH and with the method to report the image error:
#   RC Table 1 shape  pure BVH vs BVH+LS(D) for the depths in CHCRT_LS_DEPTHS: Line Space build s, MB,
#                     ms/frame and Mrays/s for AO and diffuse rays, speedup, image error (final and indirect-only
#                     PSNR/MAE). Shadow rays stay exact here (--ls-modes shadow=exact,bounce=exact) so that the
#                     error is the indirect approximation's. bvh+ls-exact (exact skipping) runs alongside.
#                     AO rays are traced with pure BVH (ao=off, bvh+ls's default when these tables were made;
#                     its AO row is then ~1x); the given --ls-modes also stops bvh+ls-exact from falling back,
#                     so its rows measure skipping. Every table names its modes in full: bvh+ls's own defaults
#                     changed since (AO candidates, shadows off: app/methods.cpp), the tables' settings did not.
#   SS Table 1 shape  25 shadow rays per pixel (--spp 25 --effects shadow): BVH vs BVH+LS with shadow
#                     termination for N in CHCRT_LS_SS_N at depth CHCRT_LS_SS_DEPTH; pixels > 2/255 differing.
#   N-tree rows    the same 25 shadow rays per pixel: BVH vs ntree+ls (SS Algorithm 1 over the N-tree; start
#                  node skipped as SS §4.1) for (N:d) in CHCRT_LS_NTREE ("4:4 6:3 8:3"), --ls-ntree-near
#                  CHCRT_LS_NTREE_NEAR (0 = the paper); trees cached in CHCRT_LS_CACHE like the Line Spaces (the
#                  JSON's ntree.build_s is the stored build time, ntree.cache says whether it was loaded).
#   SS candidates  (opt-in table "sscand") the same 25 shadow rays per pixel with representative candidates
#                  (--ls-modes shadow=candidate: a candidate plane hit ends the ray) for the N:D pairs in
#                  CHCRT_LS_SS_CANDIDATE ("7:11 8:11", the dragon's soft-shadow target, linespace/README.md).
#   AO candidates  (opt-in table "ao") AO rays only, bvh+ls with ao=candidate (the start node acts as a leaf, RC)
#                  for faces=both (the paper) and faces=front-start, and ao=candidate-exact-start (the node the ray
#                  starts in traversed exactly), D in CHCRT_LS_DEPTHS; shadows and diffuse exact, so the image error
#                  is the AO approximation's alone.
# CHCRT_LS_TABLES selects the tables ("rc ss ntree", default; add "ao" / "sscand" for the opt-in tables).
# Usage: scripts/bench_linespace.sh [build dir (build)] [out dir (out/bench/linespace)] [scene ...]
#   scenes: city interior bunny dragon castle (default: all; the last three only when ../shared/scenes has them)
# Environment: CHCRT_BENCH_SIZE (256), CHCRT_BENCH_FRAMES (0,5), CHCRT_BENCH_RUNS (3), CHCRT_LS_DEPTHS ("6 9"),
#   CHCRT_LS_SPP (1: samples per pixel of the RC and AO tables; every pixel of a pass shares one Halton direction,
#   CHC+RT §5.3, so a 1-spp image error depends on that one direction: use 4 or more for error figures),
#   CHCRT_LS_N (6), CHCRT_LS_SS_N ("4 6"), CHCRT_LS_SS_DEPTH (9), CHCRT_LS_CACHE (out/cache/linespace).
# Output: <out>/<scene>_rc_D<d>.json, <out>/<scene>_ss_N<n>.json, <out>/<scene>_ntree_<N>_<d>[_near<K>].json,
#   <out>/<scene>_ao_D<d>_<faces>.json, <out>/<scene>_ss_N<n>_D<d>_candidate.json (bench rows), <out>/linespace_tables.md, <out>/summary.md (compact RC
#   Table 1 with indirect = AO + diffuse, SS Table 1, AO table), <out>/*.csv (scripts/linespace_tables.py).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-out/bench/linespace}
shift $(( $# > 2 ? 2 : $# )) || true
scenes=("$@")
((${#scenes[@]})) || scenes=(city interior bunny dragon castle)
chcrt="$build/bin/chcrt"
size=${CHCRT_BENCH_SIZE:-256}
frames=${CHCRT_BENCH_FRAMES:-0,5}
runs=${CHCRT_BENCH_RUNS:-3}
spp=${CHCRT_LS_SPP:-1}
depths=${CHCRT_LS_DEPTHS:-"6 9"}
n=${CHCRT_LS_N:-6}
ss_n=${CHCRT_LS_SS_N:-"4 6"}
ss_depth=${CHCRT_LS_SS_DEPTH:-9}
cache=${CHCRT_LS_CACHE:-out/cache/linespace}
ntree=${CHCRT_LS_NTREE:-"4:4 6:3 8:3"}
ss_candidate=${CHCRT_LS_SS_CANDIDATE:-"7:11 8:11"}
tables=${CHCRT_LS_TABLES:-"rc ss ntree"}
ntree_near=${CHCRT_LS_NTREE_NEAR:-0}
near_suffix=""; [[ $ntree_near == 0 ]] || near_suffix="_near${ntree_near}"
mkdir -p "$out"
shared=../shared/scenes

for scene in "${scenes[@]}"; do
  case $scene in
    bunny) file=$shared/stanford_bunny/bunny.glb; scene_args=(--scene "$file"); scene_frames=0 ;;
    dragon) file=$shared/stanford_dragon/dragon.glb; scene_args=(--scene "$file"); scene_frames=0 ;;
    castle) file=$shared/intel_castle/castle.gltf
            scene_args=(--scene "$file" --eye 27,2,-47 --target 41,8,50 --fov 60); scene_frames=0 ;;
    *) file=""; scene_args=(--scene "$scene"); scene_frames=$frames ;;
  esac
  if [[ -n $file && ! -f $file ]]; then echo "bench_linespace: $file not found, skipping $scene"; continue; fi
  common=(-q --width "$size" --height "$size" --frames "$scene_frames" --runs "$runs" --warmup 1 --ls-cache "$cache"
          "${scene_args[@]}")
  for d in $depths; do
    [[ " $tables " == *" rc "* ]] || break
    echo "bench_linespace: $scene RC table, D=$d"
    "$chcrt" bench "${common[@]}" --method bvh,bvh+ls-exact,bvh+ls --ray-type primary,ao,diffuse --spp "$spp" \
      --effects shadow,ao,diffuse --ls-n "$n" --ls-depth "$d" --ls-modes shadow=exact,bounce=exact,ao=off \
      --json "$out/${scene}_rc_D${d}.json"
  done
  for d in $depths; do
    [[ " $tables " == *" ao "* ]] || break
    for variant in both front-start exact-start; do
      # exact-start: candidate-exact-start (the node the ray starts in traversed exactly), faces=front-start.
      mode=candidate faces=$variant
      [[ $variant == exact-start ]] && mode=candidate-exact-start faces=front-start
      echo "bench_linespace: $scene AO candidates, D=$d, $variant"
      "$chcrt" bench "${common[@]}" --method bvh,bvh+ls --ray-type ao --spp "$spp" --effects shadow,ao,diffuse \
        --ls-n "$n" --ls-depth "$d" --ls-modes shadow=exact,bounce=exact,diffuse=exact,ao=$mode,faces=$faces \
        --json "$out/${scene}_ao_D${d}_${variant}.json"
    done
  done
  for nd in $ntree; do
    [[ " $tables " == *" ntree "* ]] || break
    echo "bench_linespace: $scene N-tree table, N:d=$nd, near $ntree_near"
    "$chcrt" bench "${common[@]}" --method bvh,ntree+ls --ray-type shadow --spp 25 --effects shadow \
      --ls-ntree "$nd" --ls-ntree-start skip --ls-ntree-near "$ntree_near" \
      --json "$out/${scene}_ntree_${nd/:/_}${near_suffix}.json"
  done
  for sn in $ss_n; do
    [[ " $tables " == *" ss "* ]] || break
    echo "bench_linespace: $scene SS table, N=$sn D=$ss_depth"
    "$chcrt" bench "${common[@]}" --method bvh,bvh+ls --ray-type shadow --spp 25 --effects shadow \
      --ls-n "$sn" --ls-depth "$ss_depth" --ls-modes shadow=shadow,bounce=shadow,ao=exact,diffuse=exact \
      --json "$out/${scene}_ss_N${sn}.json"
  done
  for nd in $ss_candidate; do
    [[ " $tables " == *" sscand "* ]] || break
    echo "bench_linespace: $scene SS table with candidates, N:D=$nd"
    "$chcrt" bench "${common[@]}" --method bvh,bvh+ls --ray-type shadow --spp 25 --effects shadow \
      --ls-n "${nd%%:*}" --ls-depth "${nd##*:}" --ls-modes shadow=candidate,bounce=shadow,ao=exact,diffuse=exact \
      --json "$out/${scene}_ss_N${nd%%:*}_D${nd##*:}_candidate.json"
  done
done
python3 scripts/linespace_tables.py "$out"
