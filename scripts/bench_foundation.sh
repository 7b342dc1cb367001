#!/usr/bin/env bash
# Reproduces the foundation figures of docs/benchmarks.md: pure BVH GLSL tracing vs Embree on the default city
# (1M triangles) at 512x512 for the four ray types, on the near and far walkthroughs, plus a verify run.
# Output: out/bench/*.json|csv|md. Usage: scripts/bench_foundation.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
chcrt=${1:-build}/bin/chcrt
mkdir -p out/bench
for path in near far; do
  "$chcrt" bench --scene city --camera-path "$path" --ray-type primary,shadow,ao,diffuse --method bvh,embree \
    --frames spread:5 --runs 5 --warmup 1 -q \
    --json "out/bench/foundation_city_$path.json" --csv "out/bench/foundation_city_$path.csv" \
    --markdown "out/bench/foundation_city_$path.md"
done
"$chcrt" verify --scene city --ray-type primary,shadow,ao,diffuse --frames all:10 -q \
  --stats-json out/bench/verify_city_near.json
"$chcrt" info -q --stats-json out/bench/info_city.json
