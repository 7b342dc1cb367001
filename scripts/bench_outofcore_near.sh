#!/usr/bin/env bash
# Issue #5 near-view target: the out-of-core 140M city against the in-core 10M city on the same near walkthrough
# (640×360, shadow + AO, 1 spp), in ROUNDS interleaved rounds (out of core, then in core) so that both see the
# same machine state. Per run: median frame time of frames 1-11 (`ms_total` of --stats-json; frame 0 compiles
# shaders and, out of core, fills the caches); prints each round's ratio, the median of the ratios and the
# ratio of the medians.
# Usage: scripts/bench_outofcore_near.sh BUILD_DIR PREPARED.chs OUT_DIR [ROUNDS=6]
#   (PREPARED.chs: chcrt prepare --scene city:140m -o city140m.chs --memory-mb 2048)
set -euo pipefail
build=${1:?build dir}; chs=${2:?prepared .chs}; out=${3:?output dir}; rounds=${4:-6}
mkdir -p "$out"
common=(--camera-path near --frames 0-11 --width 640 --height 360 --effects shadow,ao --spp 1 -q)
for ((r = 1; r <= rounds; ++r)); do
  "$build/bin/chcrt" render --scene "$chs" --out-of-core --method chcrt --gpu-cache-mb 1024 --host-cache-mb 2048 \
    "${common[@]}" -o "$out/ooc.png" --stats-json "$out/ooc_$r.json" >/dev/null
  "$build/bin/chcrt" render --scene city:10m --method chcrt --primary traced \
    "${common[@]}" -o "$out/incore.png" --stats-json "$out/incore_$r.json" >/dev/null
done
rm -f "$out"/ooc_*.png "$out"/incore_*.png
python3 - "$out" "$rounds" <<'PY'
import json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
def run(kind, r):
    frames = json.load(open(f"{out}/{kind}_{r}.json"))["frames"]
    steady = frames[4:]
    return (statistics.median([f["ms_total"] for f in frames[1:]]),
            statistics.median([f["ms_gbuffer"] for f in steady]), statistics.median([f["ms_trace"] for f in steady]))
print("| round | out of core ms (G-buffer / trace) | in core ms (G-buffer / trace) | ratio |")
print("| ---: | ---: | ---: | ---: |")
ooc, inc, ratios = [], [], []
for r in range(1, rounds + 1):
    o, i = run("ooc", r), run("incore", r)
    ooc.append(o[0]); inc.append(i[0]); ratios.append(o[0] / i[0])
    print(f"| {r} | {o[0]:.1f} ({o[1]:.1f} / {o[2]:.1f}) | {i[0]:.1f} ({i[1]:.1f} / {i[2]:.1f}) | {o[0] / i[0]:.2f} |")
print(f"median out of core {statistics.median(ooc):.1f} ms, in core {statistics.median(inc):.1f} ms: "
      f"ratio of medians {statistics.median(ooc) / statistics.median(inc):.2f}, "
      f"median of ratios {statistics.median(ratios):.2f} (range {min(ratios):.2f}-{max(ratios):.2f})")
PY
