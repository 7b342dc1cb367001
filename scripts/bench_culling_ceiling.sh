#!/usr/bin/env bash
# What CHC+RT could reach on this machine if traversing its cell lists cost nothing (culling/README.md, "Performance
# on llvmpipe", "The ceiling of the passes"): the near-path bench of each scene and ray type, `bvh,chcrt-noadapt`, with
# two copies of the shaders loaded from disk (CHCRT_SHADER_DIR):
#   built    — the shaders as built (loaded the same way as the variant, so that both pay the same);
#   no-lists — the cell passes' list traversal runs for no ray: its code stays in the pass, behind a condition no
#              cell's list meets, so that every fixed cost of a culled trace remains — clears, hint pass, reduction,
#              decisions and lists, the cell pass's fetches, stores, hint visits and the one masked trip through the
#              traversal code that llvmpipe makes for every SIMD group (docs/architecture.md) — and none of the
#              traversal work culling leaves. Its hits are wrong (the bench's diff_px says so); its speedup over pure
#              BVH is what culling could reach with passes shaped as they are.
# no-lists undercounts where the hint pass runs (shadow rays): a ray the lists would have finished records its hit's
# leaf as its next hint, so without them more rays are left to later traces. Hence a second figure from the built
# runs alone: pure BVH's time over the culled trace's without its cell passes' GPU time (`subtree_pass_ms` less
# `hint_pass_ms`) — the speedup if the cell passes, floor and all, took no time: an upper bound.
# Processes alternate the two variants. Prints one row per scene and ray type: pure BVH's ms per frame, the speedup as
# built, the no-lists speedup and the bound, each the median over ROUNDS processes.
# Usage: scripts/bench_culling_ceiling.sh BUILD_DIR OUT_DIR [ROUNDS=2]
# Environment: SCENES ("city interior"), RAYS ("primary:1 shadow:16 ao:20 diffuse:20": ray type:spp), SIZE (256),
# FRAMES (0-7), RUNS (3).
set -euo pipefail
build=${1:?build dir}; out=${2:?output dir}; rounds=${3:-2}
scenes=${SCENES:-city interior}; rays=${RAYS:-primary:1 shadow:16 ao:20 diffuse:20}
size=${SIZE:-256}; frames=${FRAMES:-0-7}; runs=${RUNS:-3}
src=$(cd "$(dirname "$0")/../shaders" && pwd)
mkdir -p "$out"

rm -rf "${out:?}/built" "$out/no-lists"
cp -r "$src" "$out/built"
cp -r "$src" "$out/no-lists"
python3 - "$out/no-lists/culling/cell_pixel.glsl" <<'PY'
import sys
path = sys.argv[1]
old = "    traverseCellList(hintLeaf, header.x, header.x + header.y,"
text = open(path).read()
if text.count(old) != 1:
    sys.exit(f"{path}: expected one '{old.strip()}' (the shader changed: update this script)")
open(path, "w").write(text.replace(old, "    if (header.y == 0xFFFFFFFFu) traverseCellList(hintLeaf, header.x, header.x + header.y,"))
PY

for ((r = 1; r <= rounds; ++r)); do
  for scene in $scenes; do
    for ray in $rays; do
      for v in built no-lists; do
        CHCRT_SHADER_DIR="$out/$v" "$build/bin/chcrt" bench --scene "$scene" --camera-path near --ray-type "${ray%:*}" \
          --spp "${ray#*:}" --method bvh,chcrt-noadapt --frames "$frames" --runs "$runs" --warmup 1 --width "$size" \
          --height "$size" --chcrt-pass-timer-interval 1 -q --json "$out/${scene}_${ray%:*}_${v}_$r.json" >/dev/null
      done
    done
  done
done
python3 - "$out" "$rounds" "$scenes" "$rays" <<'PY'
import json, statistics, sys
out, rounds, scenes, rays = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(), sys.argv[4].split()
def rows(scene, ray, v, r):
    return {row["method"]: row for row in json.load(open(f"{out}/{scene}_{ray}_{v}_{r}.json"))["rows"]}
def speedup(t):
    return t["bvh"]["ms_median"] / t["chcrt-noadapt"]["ms_median"]
def bound(t):
    c = t["chcrt-noadapt"]
    f = c["chcrt"]["per_frame"]
    return t["bvh"]["ms_median"] / (c["ms_median"] - (f["subtree_pass_ms"] - f["hint_pass_ms"]))
print("| scene | ray | spp | bvh ms/frame | `chcrt-noadapt` as built | no list traversal | no cell passes (bound) | "
      "per round (built / no lists / bound) |")
print("| --- | --- | ---: | ---: | ---: | ---: | ---: | --- |")
for scene in scenes:
    for entry in rays:
        ray, spp = entry.split(":")
        built = [rows(scene, ray, "built", r) for r in range(1, rounds + 1)]
        nolists = [rows(scene, ray, "no-lists", r) for r in range(1, rounds + 1)]
        b, n, u = [speedup(t) for t in built], [speedup(t) for t in nolists], [bound(t) for t in built]
        each = ", ".join(f"{x:.2f} / {y:.2f} / {z:.2f}" for x, y, z in zip(b, n, u))
        bvh = statistics.median(t["bvh"]["ms_median"] for t in built)
        print(f"| {scene} | {ray} | {spp} | {bvh:.1f} | {statistics.median(b):.2f}× | {statistics.median(n):.2f}× | "
              f"{statistics.median(u):.2f}× | {each} |")
PY
