#!/usr/bin/env bash
# Reproduces the foundation figures of docs/benchmarks.md: pure BVH GLSL tracing vs Embree on the default city
# (1M triangles) at 512x512 for the four ray types, on the near and far walkthroughs, plus a verify run. The tables
# and figures come from `chcrt report --from-json` (docs/report.md), the one way the project makes them.
# Output: out/bench/foundation_city_{near,far}.json, verify and info JSON, and the report in out/bench/foundation/.
# Usage: scripts/bench_foundation.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
chcrt=${1:-build}/bin/chcrt
mkdir -p out/bench
for path in near far; do
  "$chcrt" bench --scene city --camera-path "$path" --ray-type primary,shadow,ao,diffuse --method bvh,embree \
    --frames spread:5 --runs 5 --warmup 1 -q --json "out/bench/foundation_city_$path.json"
done
"$chcrt" report -q --from-json out/bench/foundation_city_near.json out/bench/foundation_city_far.json \
  --out out/bench/foundation
"$chcrt" verify --scene city --ray-type primary,shadow,ao,diffuse --frames all:10 -q \
  --stats-json out/bench/verify_city_near.json
"$chcrt" info -q --stats-json out/bench/info_city.json
