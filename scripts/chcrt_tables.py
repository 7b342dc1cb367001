#!/usr/bin/env python3
"""Turns the bench JSON of scripts/bench_chcrt.sh into the CHC+RT tables (markdown + CSV).
Usage: chcrt_tables.py <out dir> <scene>"""
import csv
import glob
import json
import os
import sys


def load(path):
    with open(path) as f:
        return json.load(f)


def rows_by_method(data):
    return {r["method"]: r for r in data["rows"]}


def write(out, name, header, rows, note):
    with open(os.path.join(out, name + ".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    with open(os.path.join(out, name + ".md"), "w") as f:
        f.write(note + "\n\n")
        f.write("| " + " | ".join(header) + " |\n")
        f.write("| " + " | ".join("---" for _ in header) + " |\n")
        for r in rows:
            f.write("| " + " | ".join(str(c) for c in r) + " |\n")


def setup(data):
    r = data["rows"][0]
    return "%dx%d, spp primary 1 / shadow 16 / AO 20 / diffuse 20, %d frame(s), median of %d run(s) after 1 warm-up, %s" % (
        r["width"], r["height"], r["frames"], r["runs"], data.get("gl_renderer", "?"))


def work_setup(data):
    r = data["rows"][0]
    return "%dx%d, 1 spp per ray type, %d frame(s), median of %d run(s) after 1 warm-up, %s" % (
        r["width"], r["height"], r["frames"], r["runs"], data.get("gl_renderer", "?"))


def steps_ratio(bvh, method):
    """Pure BVH traversal steps per ray / the method's (None where a run did not count steps)."""
    if not method or not bvh.get("steps_per_ray") or not method.get("steps_per_ray"):
        return None
    return bvh["steps_per_ray"] / method["steps_per_ray"]


def main():
    out, scene = sys.argv[1], sys.argv[2]
    f2 = sorted(glob.glob(os.path.join(out, scene + "_table2_*.json")))
    if f2:
        rows, phases = [], []
        order = {"primary": 0, "shadow": 1, "ao": 2, "diffuse": 3}
        entries = []
        for path in f2:
            d = load(path)
            m = rows_by_method(d)
            b = m["bvh"]
            entries.append((b["path"], order.get(b["ray_type"], 9), d, m))
        entries.sort(key=lambda e: (e[0], e[1]))
        for _, _, d, m in entries:
            b, c, n = m["bvh"], m.get("chcrt"), m.get("chcrt-noadapt")
            cs = c["chcrt"]["sum"] if c and "chcrt" in c else {}
            culled = 1.0 - cs.get("fallback_traces", 0) / max(1, cs.get("traces", 1))
            ratio = steps_ratio(b, n)
            rows.append([b["path"].split("-")[-1], b["ray_type"], b["spp"], "%.1f" % b["ms_median"],
                         "%.1f" % c["ms_median"], "%.2f" % c["speedup_vs_bvh"], "%.0f%%" % (100 * culled),
                         "%.1f" % cs["mean_height"] if cs.get("mean_height") else "-",
                         "%.1f" % n["ms_median"], "%.2f" % n["speedup_vs_bvh"],
                         "%.2f" % ratio if ratio else "-",
                         "%.2f" % (n["speedup_vs_bvh"] / ratio) if ratio else "-",
                         c["diff_pixels"] + n["diff_pixels"]])
            if n and "chcrt" in n:
                p = n["chcrt"]["per_frame"]
                phases.append([b["path"].split("-")[-1], b["ray_type"], "%.1f" % n["ms_median"],
                               "%.1f" % p["phase1_ms"], "%.1f" % p["phase2_ms"], "%.1f" % p["phase3_ms"],
                               "%.1f" % p.get("bounds_ms", 0), "%.1f" % p.get("decide_ms", 0),
                               "%.1f" % p.get("cell_list_ms", 0),
                               "%.0f" % p["queries"], "%.0f" % p["subtrees_scheduled"],
                               "%.0f" % p["shader_calls"], "%.2f" % ratio if ratio else "-",
                               "%.2f" % (n["speedup_vs_bvh"] / ratio) if ratio else "-"])
        note = "CHC+RT Table 2, %s (%s). ms per frame (all samples of a frame); speedup = bvh / method; " \
               "culled = share of chcrt's traces that culled (the rest: the adaptive choice's pure passes), H = their " \
               "mean termination height; steps ratio = bvh / chcrt-noadapt traversal steps per ray; culling " \
               "efficiency = noadapt speedup / steps ratio (how much of the removed work became time); diff px = " \
               "differing hit pixels of chcrt + chcrt-noadapt vs pure BVH." % (scene, setup(entries[0][2]))
        write(out, scene + "_table2",
              ["path", "ray type", "spp", "bvh ms", "chcrt ms", "chcrt speedup", "culled", "H", "noadapt ms",
               "noadapt speedup", "steps ratio", "culling efficiency", "diff px"], rows, note)
        note = "CHC+RT Figure 8 (time per phase), %s, chcrt-noadapt (always culls), per frame: Phase 1 = init + " \
               "previously visible leaves, Phase 2 = issuing queries (bounds-only: deciding pairs), Phase 3 = " \
               "results, traversal, newly visible; bounds = ray bounds reductions, decide = CPU pair decisions, cell " \
               "lists = CPU list building and uploads (all three inside the phases) (%s)." \
               % (scene, setup(entries[0][2]))
        write(out, scene + "_figure8",
              ["path", "ray type", "ms", "phase 1 ms", "phase 2 ms", "phase 3 ms", "bounds ms", "decide ms",
               "cell lists ms", "queries", "subtrees", "shader calls", "steps ratio", "culling efficiency"], phases,
              note)
    f4 = sorted(glob.glob(os.path.join(out, scene + "_table4_*.json")))
    if f4:
        rows = []
        for path in f4:
            d = load(path)
            m = rows_by_method(d)
            a = m["chcrt-aggressive"]
            t = os.path.basename(path).rsplit("_t", 1)[1].split(".")[0]
            pixels = a["width"] * a["height"] * a["spp"] * a["frames"]
            err = a.get("image_error") or {}
            mae = err.get("final_mae")
            psnr = err.get("final_psnr_db")
            rows.append([a["ray_type"], int(t), "%.1f" % m["bvh"]["ms_median"], "%.1f" % a["ms_median"],
                         "%.2f" % a["speedup_vs_bvh"], a["diff_pixels"], "%.3f%%" % (100.0 * a["diff_pixels"] / pixels),
                         "-" if mae is None else "%.5f" % mae, "inf" if psnr is None else "%.1f" % psnr])
        rows.sort(key=lambda r: (r[0], r[1]))
        write(out, scene + "_table4", ["ray type", "threshold (rays)", "bvh ms", "aggressive ms", "speedup",
                                       "diff px", "diff %", "image MAE", "image PSNR dB"], rows,
              "CHC+RT Table 4 (aggressive culling), %s (%s). diff px = hit pixels (over all frames and samples) "
              "that differ from pure BVH tracing; image MAE / PSNR: the whole shaded frames (bench image_error, "
              "final tone-mapped image) vs pure BVH." % (scene, setup(load(f4[0]))))
    f5 = sorted(glob.glob(os.path.join(out, scene + "_table5_*.json")))
    if f5:
        rows = []
        for path in f5:
            d = load(path)
            m = rows_by_method(d)
            r = int(os.path.basename(path).rsplit("_r", 1)[1].split(".")[0])
            rows.append([m["bvh"]["ray_type"], r, "%.1f" % m["bvh"]["ms_median"], "%.1f" % m["chcrt"]["ms_median"],
                         "%.2f" % m["chcrt"]["speedup_vs_bvh"], "%.1f" % m["chcrt-noadapt"]["ms_median"],
                         "%.2f" % m["chcrt-noadapt"]["speedup_vs_bvh"],
                         m["chcrt"]["diff_pixels"] + m["chcrt-noadapt"]["diff_pixels"]])
        rows.sort(key=lambda r: (r[0], r[1]))
        write(out, scene + "_table5", ["ray type", "rotation (deg)", "bvh ms", "chcrt ms", "chcrt speedup",
                                       "noadapt ms", "noadapt speedup", "diff px"], rows,
              "CHC+RT Table 5 (per-pixel sample rotation), %s (%s)." % (scene, setup(load(f5[0]))))
    fw = sorted(glob.glob(os.path.join(out, scene + "_work_h*.json")))
    if fw:
        rows = []
        order = {"primary": 0, "shadow": 1, "ao": 2, "diffuse": 3}
        for path in fw:
            d = load(path)
            m = rows_by_method(d)
            b, n = m["bvh"], m["chcrt-noadapt"]
            h = int(os.path.basename(path).split("_work_h", 1)[1].split("_")[0])
            p = n["chcrt"]["per_frame"]
            ratio = steps_ratio(b, n)
            rows.append([b["ray_type"], h, "%.1f" % b["steps_per_ray"], "%.1f" % n["steps_per_ray"],
                         "%.2f" % ratio, "%.1f" % b["ms_median"],
                         "%.1f" % n["ms_median"], "%.2f" % n["speedup_vs_bvh"],
                         "%.2f" % (n["speedup_vs_bvh"] / ratio), "%.1f" % p["phase1_ms"],
                         "%.1f" % (p["phase2_ms"] + p["phase3_ms"]), "%.0f" % p["queries"],
                         "%.0f" % p["subtrees_scheduled"], b["diff_pixels"] + n["diff_pixels"]])
        rows.sort(key=lambda r: (order.get(r[0], 9), -r[1]))
        write(out, scene + "_work", ["ray type", "height", "bvh steps/ray", "chcrt steps/ray", "steps ratio",
                                     "bvh ms", "noadapt ms", "noadapt speedup", "culling efficiency",
                                     "phase 1 ms", "phase 2+3 ms",
                                     "queries", "subtrees traced", "diff px"], rows,
              "How much traversal culling can save, %s (%s): steps = BVH inner nodes + leaves + triangles per active "
              "ray (chcrt bench --steps) of pure BVH and always-culling CHC+RT (chcrt-noadapt) at termination height "
              "H; per frame: ms, phase times, queries, subtrees traced (scheduled (tile, subtree) pairs)."
              % (scene, work_setup(load(fw[0]))))


if __name__ == "__main__":
    main()
