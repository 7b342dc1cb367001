#!/usr/bin/env python3
"""`chcrt report --from-json` on a bench JSON that `chcrt farm collect` wrote (tests/data/report/
bench_farm_collected.json: `chcrt farm bench --print` over city:10k, shadow and AO, bvh, chcrt and chcrt-noadapt at
32x24, each array task run here as Slurm would run it, then `chcrt farm collect`; docs/report.md): the figures and
CSVs hold its numbers, the page names every task's command line and the driver; the driver of other GL version
strings (NVIDIA's, one naming none) from edited copies.

Usage: report_farm_json_test.py CHCRT_BINARY SOURCE_DIR WORK_DIR
Standard library only (chcrt report finds a Python with matplotlib itself).
"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys

FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)
    return condition


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    return [dict(zip(rows[0], r)) for r in rows[1:]]


def short_path(row):
    return row["path"][len(row["scene"]) + 1:] if row["path"].startswith(row["scene"] + "-") else row["path"]


def same(csv_text, json_value, what):
    got = None if csv_text == "" else float(csv_text)
    want = None if json_value is None else float(json_value)
    return check(got == want, f"{what}: CSV {csv_text!r} != JSON {json_value!r}")


def compare_keyed(csv_rows, expected, key_fields, what):
    check(len(csv_rows) == len(expected), f"{what}: {len(csv_rows)} CSV rows, {len(expected)} expected from JSON")
    for r in csv_rows:
        key = tuple(r[k] for k in key_fields)
        if not check(key in expected, f"{what}: CSV row {key} is not in the JSON"):
            continue
        for column, v in expected[key].items():
            same(r[column], v, f"{what} {key} {column}")


def report(binary, out, inputs):
    r = subprocess.run([binary, "report", "-q", "--out", out, "--from-json"] + inputs, capture_output=True, text=True)
    return check(r.returncode == 0, f"chcrt report {' '.join(inputs)} failed ({r.returncode}): {r.stderr}")


def main():
    binary, source, work = sys.argv[1:4]
    fixture = os.path.join(source, "tests", "data", "report", "bench_farm_collected.json")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    collected = json.load(open(fixture))
    rows = collected["rows"]

    # The fixture is farm collect's shape: the run-level fields of the first task, no command line of its own, the
    # rows in row order and one task per row, each a `chcrt bench` of one scene, ray type and method.
    check("command_line" not in collected, "fixture: a collected bench JSON has no top-level command_line")
    check(all(k in collected for k in ("settings", "gl_renderer", "gl_version", "machine", "tasks")),
          "fixture: run-level fields or tasks missing")
    tasks = collected["tasks"]
    check(len(tasks) == len(rows) == 6, f"fixture: {len(tasks)} tasks, {len(rows)} rows, expected 6 of each")
    for i, (t, r) in enumerate(zip(tasks, rows)):
        words = t["command_line"]
        check(words[1] == "bench" and words[words.index("--json") + 1].endswith(f"parts/row_{i}.json"),
              f"fixture: task {i} is not a farm bench task: {words}")
        check(words[words.index("--method") + 1] == r["method"] and words[words.index("--ray-type") + 1] == r["ray_type"],
              f"fixture: task {i} did not write row {i}")
    check(re.search(r"Mesa 22\.3\.6$", collected["gl_version"]), f"fixture: GL version {collected['gl_version']!r}")

    out = os.path.join(work, "report")
    if not report(binary, out, [fixture]):
        print("\n".join(FAILURES))
        return 1
    figures = ["frame_times", "speedup", "phases", "subtrees_per_frame"]
    for name in figures:
        for ext in ("png", "svg", "csv"):
            path = os.path.join(out, "figures", f"{name}.{ext}")
            check(os.path.isfile(path) and os.path.getsize(path) > 100, f"{path} missing or empty")
    if FAILURES:
        print("\n".join(FAILURES))
        return 1
    fig = lambda name: read_csv(os.path.join(out, "figures", f"{name}.csv"))  # noqa: E731

    def key(r, *extra):
        return (r["scene"], short_path(r), r["ray_type"], str(r["spp"]), r["method"]) + tuple(str(e) for e in extra)

    base = ["scene", "path", "ray_type", "spp", "method"]
    compare_keyed(fig("frame_times"), {key(r, f["frame"], i): {"ms": ms} for r in rows for f in r["frame_times"]
                                       for i, ms in enumerate(f["ms_runs"])},
                  base + ["frame", "run"], "frame_times.csv")
    # Each task traced pure BVH beside its method: the row's speedup is against that, and the runs of that pure BVH
    # are not collected, so there is no per-run spread (min = max = the speedup; the table says "-").
    compare_keyed(fig("speedup"), {key(r): {"speedup_vs_bvh": r["speedup_vs_bvh"], "speedup_min": r["speedup_vs_bvh"],
                                            "speedup_max": r["speedup_vs_bvh"], "ms_median": r["ms_median"],
                                            "diff_pixels": r["diff_pixels"], "psnr_db": r["psnr_db"]}
                                   for r in rows if r["method"] != "bvh"}, base, "speedup.csv")
    bvh = {r["ray_type"]: r for r in rows if r["method"] == "bvh"}
    compare_keyed(fig("phases"), {key(r): {k: r["chcrt"]["per_frame"][k] for k in
                                           ("phase1_ms", "phase2_ms", "phase3_ms", "fallback_ms")}
                                  | {"ms_median": r["ms_median"], "bvh_ms_median": bvh[r["ray_type"]]["ms_median"]}
                                  for r in rows if "chcrt" in r}, base, "phases.csv")
    compare_keyed(fig("subtrees_per_frame"), {key(r, f["frame"]): {"subtrees_scheduled": f["chcrt"]["subtrees_scheduled"]}
                                              for r in rows if "chcrt" in r for f in r["frame_times"] if "chcrt" in f},
                  base + ["frame"], "subtrees_per_frame.csv")
    table2 = open(os.path.join(out, "tables", "table2.md"), encoding="utf-8").read().splitlines()[2:]
    check(len(table2) == len(rows), f"table2.md has {len(table2)} rows, expected {len(rows)}")
    for line, r in zip(table2, sorted(rows, key=lambda r: (["primary", "shadow", "ao"].index(r["ray_type"]),
                                                          ["bvh", "chcrt", "chcrt-noadapt"].index(r["method"])))):
        cells = [c.strip() for c in line.strip("|").split("|")]
        check(cells[2:9] == [r["ray_type"], "1", r["method"], f"{r['ms_median']:.2f}", f"{r['speedup_vs_bvh']:.2f}",
                             "-", str(r["diff_pixels"])], f"table2.md row {cells} does not hold {r['method']} {r['ray_type']}")

    page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
    md = open(os.path.join(out, "report.md"), encoding="utf-8").read()
    check("<dt>driver</dt><dd>Mesa 22.3.6</dd>" in page, "index.html does not name the driver Mesa 22.3.6")
    check("- **driver**: Mesa 22.3.6" in md, "report.md does not name the driver Mesa 22.3.6")
    check("6 task(s), one per row, on vm" in page, "index.html does not state the farm tasks")
    check("software rasteriser" in page, "index.html lacks the software rasteriser warning")
    for t in tasks:
        line = " ".join(t["command_line"])
        check(line in page and line in md, f"the page does not show the task's command line {line}")

    # The driver of other GL version strings: NVIDIA's proprietary driver, and a version that names none.
    nvidia = dict(collected, gl_vendor="NVIDIA Corporation", gl_renderer="NVIDIA H200/PCIe/SSE2",
                  gl_version="4.6.0 NVIDIA 550.54.15")
    bare = dict(collected, gl_vendor="Some Vendor", gl_renderer="Some GPU", gl_version="4.6")
    inputs = []
    for name, j in (("nvidia.json", nvidia), ("bare.json", bare)):
        inputs.append(os.path.join(work, name))
        with open(inputs[-1], "w") as f:
            json.dump(j, f)
    if report(binary, os.path.join(work, "drivers"), inputs):
        page = open(os.path.join(work, "drivers", "index.html"), encoding="utf-8").read()
        check("<dt>driver</dt><dd>NVIDIA 550.54.15</dd>" in page, "NVIDIA's GL version does not give its driver")
        check("<dt>driver</dt><dd>unknown</dd>" in page, "a GL version naming no driver does not give 'unknown'")
        check("software rasteriser" not in page, "a warning about a software rasteriser on NVIDIA and 'Some GPU'")

    if FAILURES:
        print("\n".join(FAILURES))
        return 1
    print("report_farm_json: a farm-collected bench JSON's figures, CSVs, table, tasks and driver checked")
    return 0


if __name__ == "__main__":
    sys.exit(main())
