#!/usr/bin/env python3
"""Out-of-core viewer frames (--stats-json of `chcrt view --out-of-core`): medians of the frame-time split and of
the per-frame Table 3 statistics (CHC+RT §5.4), skipping the first 3 frames (shader warm-up, cold cache), plus
the cold frames' uploads. Usage: summarize_outofcore.py s.json"""
import json
import statistics
import sys

frames = json.load(open(sys.argv[1]))["frames"]
steady = frames[3:]
if not steady:
    sys.exit("fewer than 4 frames")
med = lambda fn: statistics.median(fn(f) for f in steady)
ooc = lambda k: (lambda f: f.get("outofcore", {}).get(k, 0))
loop = med(lambda f: f["loop_ms"])
print(f"{len(steady)} frames after the first 3: whole loop {loop:.1f} ms ({1000 / loop:.1f} fps), "
      f"render+display {med(lambda f: f['frame_ms']):.1f}, renderer {med(lambda f: f['renderer_ms']):.1f}, "
      f"G-buffer (resolve) {med(lambda f: f['gbuffer_ms']):.1f}, ray gen {med(lambda f: f['raygen_ms']):.1f}, "
      f"trace primary {med(lambda f: f['trace']['primary']['ms']):.1f}, "
      f"trace shadow {med(lambda f: f['trace']['shadow']['ms']):.1f}, shading {med(lambda f: f['shade_ms']):.1f} ms")
print(f"  loop ms min {min(f['loop_ms'] for f in steady):.1f} / max {max(f['loop_ms'] for f in steady):.1f}")
print(f"  per frame (median): {med(ooc('queries')):.0f} queries, {med(ooc('cache_hits')):.0f} hits, "
      f"{med(ooc('cache_misses')):.0f} misses, {med(ooc('cache_evictions')):.0f} evictions, "
      f"{med(ooc('mb_transferred_bvh')):.1f} MB BVH + {med(ooc('mb_transferred_geometry')):.1f} MB geometry uploaded, "
      f"{med(ooc('mb_read_from_file')):.1f} MB read from the file, {med(ooc('mrays_per_s')):.2f} Mrays/s")
last = steady[-1].get("outofcore", {})
print(f"  resident {last.get('resident_mb', 0):.1f} / allocated {last.get('allocated_mb', 0):.1f} MB "
      f"(budget {last.get('gpu_cache_mb', 0):.0f} MB, {last.get('slots', 0)} slots, file {last.get('file_subtrees', 0)} "
      f"subtrees)")
for f in frames[:3]:
    o = f.get("outofcore", {})
    print(f"  frame {f['frame']}: loop {f.get('loop_ms', 0):.1f} ms, {o.get('cache_misses', 0):.0f} misses, "
          f"{o.get('mb_transferred_bvh', 0) + o.get('mb_transferred_geometry', 0):.1f} MB uploaded")
