#!/usr/bin/env python3
"""Medians per segment (method, primary visibility, CHC+RT always-cull) of a viewer --stats-json file, skipping each
segment's first 3 frames (shader warm-up, CHC+RT's first visibility fronts). Usage: summarize_frames.py s.json"""
import json
import statistics
import sys

frames = json.load(open(sys.argv[1]))["frames"]
segments = []  # consecutive frames with the same method / primary / always-cull
for f in frames:
    key = (f["method"], f["primary"], f.get("chcrt", {}).get("always_cull", False))
    if not segments or segments[-1][0] != key:
        segments.append((key, []))
    segments[-1][1].append(f)

print("| method | primary | frames | whole loop ms (fps) | render+display | renderer | G-buffer | ray gen | trace primary"
      " | trace shadow | shading | CHC+RT phase 1 / 2 / 3 / fallback ms | queries |")
print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for (method, primary, always_cull), group in segments:
    group = group[3:]
    if not group:
        continue
    med = lambda fn: statistics.median(fn(x) for x in group)
    chcrt = lambda k: med(lambda x: x.get("chcrt", {}).get(k, 0))
    loop = med(lambda x: x["loop_ms"])
    phases = (f"{chcrt('phase1_ms'):.1f} / {chcrt('phase2_ms'):.1f} / {chcrt('phase3_ms'):.1f} / "
              f"{chcrt('fallback_ms'):.1f}" if method.startswith("chcrt") else "-")
    name = method + (" (always cull)" if always_cull else "")
    print(f"| {name} | {primary} | {len(group)} | {loop:.1f} ({1000 / loop:.1f}) | {med(lambda x: x['frame_ms']):.1f} | "
          f"{med(lambda x: x['renderer_ms']):.1f} | {med(lambda x: x['gbuffer_ms']):.1f} | "
          f"{med(lambda x: x['raygen_ms']):.1f} | {med(lambda x: x['trace']['primary']['ms']):.1f} | "
          f"{med(lambda x: x['trace']['shadow']['ms']):.1f} | {med(lambda x: x['shade_ms']):.1f} | {phases} | "
          f"{chcrt('queries'):.0f} |")
