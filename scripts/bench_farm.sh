#!/usr/bin/env bash
# The farm's target (docs/farm.md): one walkthrough rendered by one local `chcrt render` process and as a Slurm
# job array (`chcrt farm submit --wait`), on the same machine, one after the other; prints both wall times, their
# ratio, each task's start-up and wall time, and how many frames differ (must be 0).
# Usage: scripts/bench_farm.sh [OUT_DIR]   (a cluster must answer: scripts/slurm-local.sh start)
# Environment: SCENE (city), FRAMES (0-299), CHUNK (30), SIZE (640x360), EXTRA (more render flags), CHCRT.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
chcrt=${CHCRT:-$root/build/bin/chcrt}
out=$(realpath -m "${1:-/tmp/chcrt_bench_farm}")
scene=${SCENE:-city} frames=${FRAMES:-0-299} chunk=${CHUNK:-30} size=${SIZE:-640x360}
flags=(--scene "$scene" --width "${size%x*}" --height "${size#*x}" ${EXTRA:-})
command -v sbatch > /dev/null || { echo "bench_farm: sbatch not found (scripts/slurm-local.sh start)" >&2; exit 2; }

rm -rf "$out"
mkdir -p "$out/local"
now() { date +%s.%N; }
t0=$(now)
"$chcrt" render "${flags[@]}" --frames "$frames" -o "$out/local/f_####.png" --stats-json "$out/local/stats.json" -q \
  > "$out/local.log"
t1=$(now)
"$chcrt" farm submit "${flags[@]}" --frames "$frames" --chunk "$chunk" -o "$out/farm/f_####.png" \
  --stats-json "$out/farm/stats.json" --job-name chcrt-bench --wait > "$out/farm.log"
t2=$(now)
"$chcrt" farm collect "$out/farm/stats.json" >> "$out/farm.log"

differing=0
for f in "$out"/local/f_*.png; do
  cmp -s "$f" "$out/farm/$(basename "$f")" || differing=$((differing + 1))
done
python3 - "$out" "$t0" "$t1" "$t2" "$differing" "$chunk" << 'EOF'
import json, statistics, sys
out, t0, t1, t2, differing, chunk = sys.argv[1], *map(float, sys.argv[2:5]), int(sys.argv[5]), sys.argv[6]
local, farm = t1 - t0, t2 - t1
stats = json.load(open(f"{out}/farm/stats.json"))
tasks = stats["tasks"]
startup = [t["startup_s"] for t in tasks]
walls = [t["wall_s"] for t in tasks]
print(f"scene {stats['scene']['name']}, {len(stats['frames'])} frames {stats['width']}x{stats['height']}, "
      f"{stats['spp']} spp, effects {stats['effects']}, chunks of {chunk}: {len(tasks)} array tasks on {stats['gl_renderer']}")
print(f"local render  {local:8.1f} s")
print(f"farm (--wait) {farm:8.1f} s   = {farm / local:.3f} x local")
print(f"task start-up {min(startup):.2f}-{max(startup):.2f} s (median {statistics.median(startup):.2f}); "
      f"task wall {min(walls):.1f}-{max(walls):.1f} s")
print(f"frames differing from the local render: {differing}")
EOF
