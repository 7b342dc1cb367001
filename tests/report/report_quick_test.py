#!/usr/bin/env python3
"""`chcrt report --preset quick` end to end on the procedural scenes at a small size (docs/report.md): every
study's groups run, the page has every figure the preset makes (the debug and difference images included), and an
interrupted report resumes: a rerun keeps every measured group, and after one group's output is removed only that
group runs again.

Usage: report_quick_test.py CHCRT_BINARY WORK_DIR   (the report lands in WORK_DIR/quick; report_browser uses it)
Standard library only.
"""
import glob
import json
import os
import shutil
import subprocess
import sys

FLAGS = ["--preset", "quick", "--size", "32", "--frames", "0-2", "--runs", "2", "--warmup", "0"]


def main():
    binary, work = sys.argv[1:3]
    out = os.path.join(work, "quick")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.chdir(work)  # the benches' default Line Space cache (out/cache/linespace) lands here
    command = [binary, "report", "--out", out] + FLAGS
    first = subprocess.run(command, capture_output=True, text=True)
    failures = []
    if first.returncode != 0:
        print(f"chcrt report failed ({first.returncode}):\n{first.stderr}")
        return 1
    if "report: [1/" not in first.stderr or "ETA" not in first.stderr:
        failures.append(f"no progress lines with an ETA on stderr:\n{first.stderr[:500]}")

    manifest = json.load(open(os.path.join(out, "data", "report.json")))
    groups = manifest["groups"]
    studies = {g["study"] for g in groups}
    if studies != {"compare", "aggressive", "rotation", "ls-rc", "images"}:
        failures.append(f"studies run: {sorted(studies)}")
    if any(g["resumed"] for g in groups):
        failures.append("a fresh report claims resumed groups")
    figures = ["frame_times", "speedup", "phases", "subtrees_per_frame", "culling_efficiency", "linespace_psnr",
               "aggressive_mae"] + [f"images_{s}-200k_near" for s in ("city", "interior", "plant")]
    page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
    for name in figures:
        for ext in ("png", "svg", "csv"):
            if not os.path.isfile(os.path.join(out, "figures", f"{name}.{ext}")):
                failures.append(f"figures/{name}.{ext} missing")
        if f'src="figures/{name}.png"' not in page:
            failures.append(f"index.html does not show {name}")
    for table in ("table2", "table4", "table5", "figure8", "linespace"):
        if not os.path.isfile(os.path.join(out, "tables", f"{table}.md")):
            failures.append(f"tables/{table}.md missing")
    diffs = glob.glob(os.path.join(out, "images", "*_diff_*.png"))
    if len(diffs) != 6:  # bvh+ls and chcrt-aggressive on three scenes
        failures.append(f"{len(diffs)} difference images, expected 6")
    for g in groups:
        if g["kind"] == "bench":
            bench = json.load(open(os.path.join(out, g["json"])))
            if not bench["rows"] or not all("frame_times" in r for r in bench["rows"]):
                failures.append(f"{g['json']}: rows without frame_times")

    # Resume: nothing measured twice; a removed group runs again, alone.
    again = subprocess.run(command, capture_output=True, text=True)
    resumed = json.load(open(os.path.join(out, "data", "report.json")))["groups"]
    if again.returncode != 0 or not all(g["resumed"] for g in resumed):
        failures.append(f"rerun: exit {again.returncode}, not every group kept: "
                        f"{[g['id'] for g in resumed if not g['resumed']]}")
    victim = next(g for g in groups if g["study"] == "rotation")
    os.remove(os.path.join(out, victim["json"]))
    third = subprocess.run(command, capture_output=True, text=True)
    rerun = [g["id"] for g in json.load(open(os.path.join(out, "data", "report.json")))["groups"] if not g["resumed"]]
    if third.returncode != 0 or rerun != [victim["id"]]:
        failures.append(f"after removing {victim['json']}: exit {third.returncode}, groups run again: {rerun}")
    if not os.path.isfile(os.path.join(out, victim["json"])):
        failures.append(f"{victim['json']} was not measured again")

    if failures:
        print("\n".join(failures))
        return 1
    print(f"report_quick: {len(groups)} groups, {len(figures)} figures checked, resume checked")
    return 0


if __name__ == "__main__":
    sys.exit(main())
