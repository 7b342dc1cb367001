#!/usr/bin/env python3
"""`chcrt report --from-json` on the fixed bench JSON of tests/data/report (docs/report.md):
every figure is drawn with PNG, SVG and CSV, each CSV holds exactly the JSON's numbers, the markdown tables (Tables
2, 4 and 5, Figure 8's numbers, the work and Line Space tables) equal the expected files, the page states the machine and warns about the software rasteriser; bad input exits 2 with
one line and leaves no report folder.

Usage: report_from_json_test.py CHCRT_BINARY SOURCE_DIR WORK_DIR
Standard library only (chcrt report finds a Python with matplotlib itself).
"""
import csv
import json
import os
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
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]]


def short_path(row):
    return row["path"][len(row["scene"]) + 1:] if row["path"].startswith(row["scene"] + "-") else row["path"]


def value(text):
    """A CSV cell as the JSON value it must equal: '' is null."""
    return None if text == "" else float(text)


def same(csv_text, json_value, what):
    got = value(csv_text)
    want = None if json_value is None else float(json_value)
    return check(got == want, f"{what}: CSV {csv_text!r} != JSON {json_value!r}")


def compare_keyed(csv_rows, expected, key_fields, what):
    """expected: {key tuple: {column: json value}}; every CSV row matches one expected row exactly, and all exist."""
    check(len(csv_rows) == len(expected), f"{what}: {len(csv_rows)} CSV rows, {len(expected)} expected from JSON")
    for r in csv_rows:
        key = tuple(r[k] for k in key_fields)
        if not check(key in expected, f"{what}: CSV row {key} is not in the JSON"):
            continue
        for column, v in expected[key].items():
            same(r[column], v, f"{what} {key} {column}")


def main():
    binary, source, work = sys.argv[1:4]
    data = os.path.join(source, "tests", "data", "report")
    inputs = [os.path.join(data, "bench_compare.json"), os.path.join(data, "bench_aggressive_t100.json")]
    out = os.path.join(work, "report")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    run = subprocess.run([binary, "report", "-q", "--out", out, "--from-json"] + inputs, capture_output=True, text=True)
    if run.returncode != 0:
        print(f"chcrt report failed ({run.returncode}): {run.stderr}")
        return 1

    compare = json.load(open(inputs[0]))
    aggressive = json.load(open(inputs[1]))
    rows = compare["rows"]
    bvh = {r["ray_type"]: r for r in rows if r["method"] == "bvh"}

    figures = ["frame_times", "speedup", "phases", "queries_per_frame", "subtrees_per_frame", "culling_efficiency",
               "linespace_psnr", "aggressive_mae"]
    for name in figures:
        for ext in ("png", "svg", "csv"):
            path = os.path.join(out, "figures", f"{name}.{ext}")
            check(os.path.isfile(path) and os.path.getsize(path) > 100, f"{path} missing or empty")
    for name in figures:
        with open(os.path.join(out, "figures", f"{name}.png"), "rb") as f:
            check(f.read(8) == b"\x89PNG\r\n\x1a\n", f"{name}.png is not a PNG")
    if FAILURES:
        print("\n".join(FAILURES))
        return 1
    fig = lambda name: read_csv(os.path.join(out, "figures", f"{name}.csv"))[1]  # noqa: E731

    def key(r, *extra):
        return (r["scene"], short_path(r), r["ray_type"], str(r["spp"]), r["method"]) + tuple(str(e) for e in extra)

    base = ["scene", "path", "ray_type", "spp", "method"]
    # Figure 7: every frame's every run.
    compare_keyed(fig("frame_times"), {key(r, f["frame"], i): {"ms": ms} for r in rows for f in r["frame_times"]
                                       for i, ms in enumerate(f["ms_runs"])},
                  base + ["frame", "run"], "frame_times.csv")
    # Speedups, their spread over the runs (pure BVH's run time over the method's of the same run), the error.
    expected = {}
    for r in rows:
        if r["method"] == "bvh":
            continue
        runs = [b / m for b, m in zip(bvh[r["ray_type"]]["ms_runs"], r["ms_runs"])]
        expected[key(r)] = {"speedup_vs_bvh": r["speedup_vs_bvh"], "speedup_min": min(runs), "speedup_max": max(runs),
                            "ms_median": r["ms_median"], "diff_pixels": r["diff_pixels"], "psnr_db": r["psnr_db"]}
    compare_keyed(fig("speedup"), expected, base, "speedup.csv")
    chcrt_rows = [r for r in rows if "chcrt" in r]
    check(len(chcrt_rows) == 6, f"fixture: {len(chcrt_rows)} CHC+RT rows, expected 6")
    compare_keyed(fig("phases"), {key(r): {k: r["chcrt"]["per_frame"][k] for k in
                                           ("phase1_ms", "phase2_ms", "phase3_ms", "fallback_ms")}
                                  | {"ms_median": r["ms_median"], "bvh_ms_median": bvh[r["ray_type"]]["ms_median"]}
                                  for r in chcrt_rows}, base, "phases.csv")
    for counter, name in (("queries", "queries_per_frame"), ("subtrees_scheduled", "subtrees_per_frame")):
        compare_keyed(fig(name), {key(r, f["frame"]): {counter: f["chcrt"][counter]} for r in chcrt_rows
                                  for f in r["frame_times"] if "chcrt" in f}, base + ["frame"], f"{name}.csv")
    expected = {}
    for r in chcrt_rows:
        ratio = bvh[r["ray_type"]]["steps_per_ray"] / r["steps_per_ray"]
        expected[key(r)] = {"speedup_vs_bvh": r["speedup_vs_bvh"], "steps_per_ray": r["steps_per_ray"],
                            "bvh_steps_per_ray": bvh[r["ray_type"]]["steps_per_ray"], "steps_ratio": ratio,
                            "efficiency": r["speedup_vs_bvh"] / ratio}
    compare_keyed(fig("culling_efficiency"), expected, base, "culling_efficiency.csv")
    ls_rows = [r for r in rows if "linespace" in r]
    compare_keyed(fig("linespace_psnr"), {key(r): {"speedup_vs_bvh": r["speedup_vs_bvh"], "ms_median": r["ms_median"],
                                                   "final_psnr_db": r["image_error"]["final_psnr_db"],
                                                   "final_mae": r["image_error"]["final_mae"]} for r in ls_rows},
                  base, "linespace_psnr.csv")
    agg = [r for r in rows + aggressive["rows"] if r["method"] == "chcrt-aggressive"]
    check(len({r["chcrt"]["options"]["threshold"] for r in agg}) == 2, "fixture: two aggressive thresholds")
    compare_keyed(fig("aggressive_mae"),
                  {(r["scene"], short_path(r), r["ray_type"], str(r["spp"]), str(r["chcrt"]["options"]["threshold"])):
                   {"speedup_vs_bvh": r["speedup_vs_bvh"], "ms_median": r["ms_median"],
                    "diff_pixels": r["diff_pixels"], "final_mae": r["image_error"]["final_mae"]} for r in agg},
                  ["scene", "path", "ray_type", "spp", "threshold"], "aggressive_mae.csv")

    # The tables in the papers' shapes, as markdown, against the expected files.
    for name in ("table2", "table4", "figure8"):
        got = open(os.path.join(out, "tables", f"{name}.md"), encoding="utf-8").read()
        want = open(os.path.join(data, f"expected_{name}.md"), encoding="utf-8").read()
        check(got == want, f"tables/{name}.md differs from tests/data/report/expected_{name}.md:\n{got}")
        check(want.strip() in open(os.path.join(out, "report.md"), encoding="utf-8").read(),
              f"report.md lacks tables/{name}.md")

    # The sweeps' tables (Table 5, the work table, the Line Space table) from their own bench JSON, in a second
    # report: with an ls-rc study the Line Space figure plots its rows rather than the compare study's.
    sweeps = [os.path.join(data, f) for f in ("bench_rotation_r0.json", "bench_rotation_r36.json",
                                              "bench_work_h8.json", "bench_ls_D3.json")]
    sweeps_out = os.path.join(work, "sweeps")
    run = subprocess.run([binary, "report", "-q", "--out", sweeps_out, "--from-json"] + sweeps, capture_output=True,
                         text=True)
    if check(run.returncode == 0, f"chcrt report of the sweeps failed ({run.returncode}): {run.stderr}"):
        sweep_md = open(os.path.join(sweeps_out, "report.md"), encoding="utf-8").read()
        for name in ("table5", "work", "linespace"):
            got = open(os.path.join(sweeps_out, "tables", f"{name}.md"), encoding="utf-8").read()
            want = open(os.path.join(data, f"expected_{name}.md"), encoding="utf-8").read()
            check(got == want, f"sweeps tables/{name}.md differs from tests/data/report/expected_{name}.md:\n{got}")
            check(want.strip() in sweep_md, f"sweeps report.md lacks tables/{name}.md")
        rotation = [r for f in sweeps[:2] for r in json.load(open(f))["rows"]]
        check(sorted({json.load(open(f))["settings"]["rotation"] for f in sweeps[:2]}) == [0, 36],
              "fixture: rotations 0 and 36")
        check(sum(r["method"] != "bvh" for r in rotation) == 4, "fixture: four Table 5 rows besides pure BVH")
        ls = [r for r in json.load(open(sweeps[3]))["rows"] if "linespace" in r and r["method"] == "bvh+ls"]
        compare_keyed(read_csv(os.path.join(sweeps_out, "figures", "linespace_psnr.csv"))[1],
                      {key(r): {"speedup_vs_bvh": r["speedup_vs_bvh"], "ms_median": r["ms_median"],
                                "final_psnr_db": r["image_error"]["final_psnr_db"],
                                "final_mae": r["image_error"]["final_mae"]} for r in ls},
                      base, "sweeps linespace_psnr.csv")

    page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
    for name in figures:
        check(f'src="figures/{name}.png"' in page, f"index.html does not show figures/{name}.png")
    for fact in (compare["gl_renderer"], compare["gl_vendor"], compare["gl_version"], compare["machine"]["cpu"],
                 compare["machine"]["commit"], "software rasteriser", "load"):
        check(fact in page, f"index.html does not state {fact!r}")
    check("Debug images and image error</b>: no images study" in page, "index.html does not say why images are missing")
    check("--chcrt-threshold 100" in page, "index.html lacks the benches' command lines")

    # Bad input: one line on stderr, exit 2, no report folder.
    malformed = os.path.join(work, "malformed.json")
    with open(malformed, "w") as f:
        f.write('{"rows": [')
    not_bench = os.path.join(work, "not_bench.json")
    with open(not_bench, "w") as f:
        json.dump({"frames": []}, f)
    bad_row = os.path.join(work, "bad_row.json")
    broken = json.loads(json.dumps(compare))
    broken["rows"][0]["ms_runs"] = "fast"
    with open(bad_row, "w") as f:
        json.dump(broken, f)
    bad = {"unknown preset": ["--preset", "nosuch"], "unknown scene": ["--scenes", "nosuch"],
           "unknown method": ["--methods", "bvh,nosuch"], "unknown study": ["--studies", "nosuch"],
           "missing --from-json file": ["--from-json", os.path.join(work, "missing.json")],
           "malformed JSON": ["--from-json", malformed], "JSON without rows": ["--from-json", not_bench],
           "row of the wrong type": ["--from-json", bad_row]}
    for what, args in bad.items():
        target = os.path.join(work, "bad_" + what.replace(" ", "_").replace("-", ""))
        r = subprocess.run([binary, "report", "-q", "--out", target] + args, capture_output=True, text=True)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2, f"{what}: exit {r.returncode}, expected 2 ({r.stderr.strip()})")
        check(len(lines) == 1 and lines[0].startswith("chcrt: error:"), f"{what}: stderr is not one error line: {r.stderr!r}")
        check(not os.path.exists(target), f"{what}: left {target} behind")

    if FAILURES:
        print("\n".join(FAILURES))
        return 1
    print("report_from_json: all figures, CSVs, tables and bad-input cases checked")
    return 0


if __name__ == "__main__":
    sys.exit(main())
