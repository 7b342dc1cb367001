#!/usr/bin/env bash
# Soak runs (docs/robustness.md, "Long runs"): long walkthroughs that must keep the process's resident memory, open
# files, threads and live GL objects flat. Each run writes --resource-log samples (app/resource_log.h); after a
# warm-up of a tenth of its frames (the viewer's: at least one cycle) the script reports, per run, the samples at the end
# of the warm-up and at the end, the drift of resident memory over the rest (the largest excess of a sample over the
# warm-up sample it is compared with, see analyse) and the changes of open files, threads and GL objects, and fails
# (exit 1) when the memory drifts by 1 % or more or any of the counts changes.
#   render: a walkthrough of FRAMES frames at 32×24 (an orbit of the city, 30 fps) for each GPU method in turn
#           (`chcrt methods` but embree, which render does not run, and chcrt-lod), and out of core with chcrt and
#           chcrt-lod (a prepared city:200k through a 1 MiB GPU cache and a 2 MiB host store, so that every frame
#           uploads and reads subtrees);
#   view:   VIEW_FRAMES frames of a scripted viewer session (Xvfb, 128×72 window) in cycles of 500 frames: the scene
#           loaded again, then ten methods for 50 frames each, each block replaying the camera path.
# Usage: scripts/soak.sh [render|view|all] (default all). Environment: FRAMES (10000), VIEW_FRAMES (10000),
# METHODS (default: every method of `chcrt methods`), BUILD (build), OUT (out/soak), SAMPLE_EVERY (100).
# The runs set LP_NUM_THREADS=0 (llvmpipe rasterises on the calling thread): on a busy machine handing each draw to
# llvmpipe's worker threads made a 32×24 frame take ~1 s of waiting; the code soaked is the same.
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
frames=${FRAMES:-10000}
view_frames=${VIEW_FRAMES:-10000}
build=${BUILD:-build}
out=${OUT:-out/soak}
every=${SAMPLE_EVERY:-100}
chcrt=$build/bin/chcrt
export LP_NUM_THREADS=0
mkdir -p "$out"

# An orbit of the scene's bounds (from `chcrt info`) at a fifth of its height, one lap per 300 frames.
orbit() { # scene file frames
  local bounds
  bounds=$("$chcrt" info --scene "$1" | sed -n 's/^  bounds *//p')
  python3 - "$bounds" "$2" "$3" <<'EOF'
import json, math, re, sys
nums = [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?", sys.argv[1])[:6]]
lo, hi = nums[:3], nums[3:]
frames = int(sys.argv[3])
cx, cz = (lo[0] + hi[0]) / 2, (lo[2] + hi[2]) / 2
r = 0.35 * min(hi[0] - lo[0], hi[2] - lo[2])
h = lo[1] + 0.2 * (hi[1] - lo[1])
keys = []
for k in range(frames // 300 * 8 + 9):  # 8 keyframes a lap, a lap per 10 s
    a = 2 * math.pi * k / 8
    keys.append({"t": k * 10.0 / 8, "eye": [cx + r * math.cos(a), h, cz + r * math.sin(a)],
                 "target": [cx + r * math.cos(a + 0.6), h, cz + r * math.sin(a + 0.6)]})
json.dump({"version": 1, "fps": 30, "keyframes": keys}, open(sys.argv[2], "w"))
EOF
}

# Prints a run's figures; returns 1 when it drifted. With a period P (the viewer's cycle of methods and reloads,
# whose methods hold different memory and objects), each sample after the warm-up is compared with the sample at the
# same point of the first cycle after the warm-up; without (0), with the first sample after the warm-up.
analyse() { # name log warmup-frame period
  python3 - "$@" <<'EOF'
import json, sys
name, log, warmup, period = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
samples = [json.loads(l) for l in open(log) if l.strip()]
after = [s for s in samples if s["frame"] >= warmup]
if len(after) < 2:
    print(f"{name}: only {len(samples)} samples"); sys.exit(1)
reference = {}
for s in after:
    reference.setdefault(s["frame"] % period if period else 0, s)
def ref(s): return reference[s["frame"] % period if period else 0]
def counts(s): return (s["open_files"], s["threads"], s["gl_objects"]["total"])
drift = max((s["rss_mb"] - ref(s)["rss_mb"]) / ref(s)["rss_mb"] * 100 for s in after)
changed = [s for s in after if counts(s) != counts(ref(s))]
w, e = after[0], after[-1]
end = (e["rss_mb"] - ref(e)["rss_mb"]) / ref(e)["rss_mb"] * 100
note = "; counts changed at frame %d" % changed[0]["frame"] if changed else ""
# What malloc has handed out, beside the resident memory: a growth of both is live memory, of the resident alone
# fragmentation or memory mapped outside malloc.
heap = max(s["heap_in_use_mb"] - ref(s)["heap_in_use_mb"] for s in after) if "heap_in_use_mb" in w else float("nan")
print(f"{name}: {e['frame'] + 1} frames; RSS {w['rss_mb']:.1f} MB at frame {w['frame']}, {e['rss_mb']:.1f} MB at the end "
      f"({end:+.2f} % against frame {ref(e)['frame']}); drift {drift:.2f} %; GL objects {w['gl_objects']['total']} -> "
      f"{e['gl_objects']['total']}, open files {w['open_files']} -> {e['open_files']}, threads {w['threads']} -> "
      f"{e['threads']}; heap in use {w.get('heap_in_use_mb', float('nan')):.1f} MB, at most {heap:+.2f} MB over its "
      f"reference{note}")
sys.exit(1 if drift >= 1.0 or changed else 0)
EOF
}

status=0
if [[ $what == render || $what == all ]]; then
  # In core: every GPU method but chcrt-lod, which traces the proxies of a prepared scene (run out of core below).
  methods=${METHODS:-$("$chcrt" methods | awk 'NR > 2 && $1 != "embree" && $1 != "chcrt-lod" {print $1}')}
  orbit city:20k "$out/orbit20k.json" "$frames"
  for m in $methods; do
    rm -rf "$out/frames" && mkdir -p "$out/frames"
    nice -n 19 "$chcrt" render --scene city:20k --camera-path "$out/orbit20k.json" --frames "0-$((frames - 1))" \
      --width 32 --height 24 --spp 1 --effects shadow --method "$m" --ls-cache "$out/ls-cache" -q \
      -o "$out/frames/f.png" --resource-log "$out/render_$m.jsonl" --resource-every "$every"
    analyse "render $m" "$out/render_$m.jsonl" "$((frames / 10))" 0 || status=1
  done
  [[ -f $out/city200k.chs ]] || nice -n 19 "$chcrt" prepare --scene city:200k --subtree-triangles 4000 \
    -o "$out/city200k.chs" -q
  orbit city:200k "$out/orbit200k.json" "$frames" # the prepared scene's bounds (info on a .chs gives none)
  for m in chcrt chcrt-lod; do
    rm -rf "$out/frames" && mkdir -p "$out/frames"
    nice -n 19 "$chcrt" render --scene "$out/city200k.chs" --out-of-core --load-in-core off --gpu-cache-mb 1 \
      --host-cache-mb 2 --camera-path "$out/orbit200k.json" --frames "0-$((frames - 1))" --width 32 --height 24 \
      --spp 1 --effects shadow --method "$m" -q -o "$out/frames/f.png" \
      --resource-log "$out/render_outofcore_$m.jsonl" --resource-every "$every"
    analyse "render $m out of core" "$out/render_outofcore_$m.jsonl" "$((frames / 10))" 0 || status=1
  done
  rm -rf "$out/frames"
fi

if [[ $what == view || $what == all ]]; then
  python3 - "$out/view_script.json" "$view_frames" <<'EOF'
import json, sys
methods = ["bvh", "chcrt", "raster", "chcrt-noadapt", "bvh+ls", "chcrt-aggressive", "bvh+ls-exact", "chcrt+ls",
           "chcrt+ls-exact", "ntree+ls"]
steps, blocks = [], int(sys.argv[2]) // 50
for b in range(blocks):
    if b % 10 == 0:  # a cycle: the scene loaded again, then each method for 50 frames
        steps.append({"loadScene": "city:20k"})
    steps.append({"set": {"method": methods[b % len(methods)]}, "pathFrame": 0, "play": True, "frames": 50})
json.dump(steps, open(sys.argv[1], "w"))
EOF
  Xvfb :97 -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 &
  xvfb=$!
  trap 'kill $xvfb 2>/dev/null || true' EXIT
  sleep 1
  DISPLAY=:97 nice -n 19 "$chcrt" view --scene city:20k --width 128 --height 72 --render-scale 0.5 --no-accumulate \
    --ls-cache "$out/ls-cache" -q --script "$out/view_script.json" --resource-log "$out/view.jsonl" \
    --resource-every "$every"
  # The warm-up is at least one whole cycle: the first builds each method's structures and caches.
  warm=$((view_frames / 10 > 500 ? view_frames / 10 : 500))
  analyse "view" "$out/view.jsonl" "$warm" 500 || status=1
fi
exit $status
