#!/usr/bin/env python3
"""Figures, tables and pages of `chcrt report` (docs/report.md).

Usage: chcrt_report.py MANIFEST OUT_DIR

MANIFEST is the report's data/report.json written by `chcrt report`: the groups it ran (bench JSON files, image
renders), the report's own command line and the machine it ran on. This script reads them and writes into OUT_DIR:
  figures/<name>.png, .svg, .csv   every figure with the numbers it plots (CSV values are the JSON's own numbers,
                                   written with Python's shortest round-trip repr)
  tables/<name>.md, .csv           the tables in the papers' shapes
  images/<id>_diff_<method>.png    false-colour differences of approximate methods against pure BVH
  index.html, report.md            the page and its markdown twin
A figure whose data the report lacks is not drawn; the page says which and why. Exit 2 on malformed input.
"""
import csv
import html
import io
import json
import math
import os
import re
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402  (a dependency of matplotlib)

# Keep SVGs reproducible (no date, fixed ids) and text as text.
plt.rcParams.update({"svg.hashsalt": "chcrt", "svg.fonttype": "none", "font.size": 9,
                     "axes.titlesize": 9, "legend.fontsize": 7, "figure.dpi": 100})
SVG_METADATA = {"Date": None}
PNG_METADATA = {"Software": None}

REFERENCE = "bvh"
CHCRT_METHODS = ("chcrt", "chcrt-noadapt", "chcrt-aggressive")
RAY_ORDER = ["primary", "shadow", "ao", "diffuse"]
SOFTWARE_RASTERISERS = re.compile(r"llvmpipe|softpipe|swrast|lavapipe", re.I)
# One colour per method, the same in every figure.
METHOD_COLOURS = {"bvh": "#444444", "chcrt": "#1f77b4", "chcrt-noadapt": "#ff7f0e", "chcrt-aggressive": "#d62728",
                  "bvh+ls": "#2ca02c", "bvh+ls-exact": "#9467bd", "chcrt+ls": "#8c564b",
                  "chcrt+ls-exact": "#e377c2", "ntree+ls": "#bcbd22", "embree": "#17becf"}


class BadInput(Exception):
    pass


# ---------------------------------------------------------------------------------------------------------- input

def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError as e:
        raise BadInput(f"{path}: cannot read ({e.strerror})")
    except json.JSONDecodeError as e:
        raise BadInput(f"{path}: malformed JSON ({e})")


def flag_value(words, flag):
    for i, w in enumerate(words[:-1]):
        if w == flag:
            return words[i + 1]
    return None


def infer_study(bench):
    """The study of a bench JSON given with --from-json, from its command line: a threshold sweep is Table 4, a
    rotation sweep Table 5, a forced height the work study, Line Space flags a Line Space study; else compare."""
    words = bench.get("command_line") or next(iter(farm_command_lines(bench)), [])
    methods = set((flag_value(words, "--method") or "").split(",")) | {r.get("method") for r in bench["rows"]}
    if "--chcrt-threshold" in words and methods <= {REFERENCE, "chcrt-aggressive"}:
        return "aggressive"
    if "--rotation" in words:
        return "rotation"
    if "--chcrt-height" in words:
        return "work"
    if "--ls-ntree" in words:
        return "ls-ntree"
    if any(w in words for w in ("--ls-depth", "--ls-n", "--ls-modes")):
        return "ls-rc"
    return "compare"


def farm_tasks(bench):
    """The tasks of a bench JSON that `chcrt farm collect` wrote (one bench run per row), else []."""
    tasks = bench.get("tasks")
    return [t for t in tasks if isinstance(t, dict)] if isinstance(tasks, list) else []


def farm_command_lines(bench):
    """The command lines of a farm-collected bench JSON's tasks (it has none of its own)."""
    return [t["command_line"] for t in farm_tasks(bench) if isinstance(t.get("command_line"), list) and t["command_line"]]


def short_path(row):
    """"city:200000:seed=1-near" -> "near" (bench names a path after its scene)."""
    scene, path = row["scene"], row["path"]
    return path[len(scene) + 1:] if path.startswith(scene + "-") else path


def short_scene(scene):
    """"city:200000:seed=1" -> "city 200k"; a file keeps its name."""
    m = re.match(r"^([a-z-]+):(\d+)([km]?)(?::seed=(\d+))?$", scene, re.I)
    if not m:
        return os.path.splitext(os.path.basename(scene))[0]
    n = int(m.group(2)) * {"": 1, "k": 1000, "m": 1000000}[m.group(3).lower()]
    size = f"{n / 1e6:g}M" if n >= 1_000_000 else f"{n / 1e3:g}k" if n >= 1000 else str(n)
    seed = f" seed {m.group(4)}" if m.group(4) and m.group(4) != "1" else ""
    return f"{m.group(1)} {size}{seed}"


def check_row(row, where):
    for key, kind in (("scene", str), ("path", str), ("ray_type", str), ("method", str), ("ms_median", (int, float)),
                      ("ms_runs", list), ("speedup_vs_bvh", (int, float, type(None)))):
        if not isinstance(row.get(key), kind):
            raise BadInput(f"{where}: a row's \"{key}\" is missing or of the wrong type (not chcrt bench JSON)")
    if not all(isinstance(v, (int, float)) for v in row["ms_runs"]):
        raise BadInput(f"{where}: a row's \"ms_runs\" holds non-numbers")
    for f in row.get("frame_times") or []:
        if not isinstance(f, dict) or not isinstance(f.get("frame"), int) or not isinstance(f.get("ms_runs"), list):
            raise BadInput(f"{where}: a row's \"frame_times\" entry is malformed")


class Data:
    """All benches of a report: rows tagged with their study and file, the images groups, the machines."""

    def __init__(self, manifest, out):
        self.manifest = manifest
        self.out = out
        self.benches = []  # {"study", "file", "json", "commands"}
        self.images = []
        for g in manifest.get("groups", []):
            if g.get("kind") == "images":
                self.images.append(g)
                continue
            path = g["json"] if os.path.isabs(g["json"]) else os.path.join(out, g["json"])
            bench = read_json(path)
            if not isinstance(bench, dict) or not isinstance(bench.get("rows"), list) or not bench["rows"]:
                raise BadInput(f"{path}: not chcrt bench JSON (no \"rows\")")
            study = g.get("study", "compare")
            if study == "from-json":
                study = infer_study(bench)
            farm = bool(farm_tasks(bench))
            for row in bench["rows"]:
                check_row(row, path)
                row["_study"] = study
                row["_file"] = len(self.benches)
                row["_farm"] = farm
            self.benches.append({"study": study, "file": path, "json": bench, "group": g})

    def rows(self, study=None, method=None):
        for b in self.benches:
            if study is not None and b["study"] not in (study if isinstance(study, tuple) else (study,)):
                continue
            for r in b["json"]["rows"]:
                if method is None or r["method"] == method:
                    yield r

    def reference(self, row):
        """The pure-BVH row traced with the same rays (same bench file, ray type, path, spp)."""
        for r in self.benches[row["_file"]]["json"]["rows"]:
            if (r["method"] == REFERENCE and r["ray_type"] == row["ray_type"] and r["path"] == row["path"]
                    and r.get("spp") == row.get("spp")):
                return r
        return None


def run_speedups(row, ref):
    """Per timed run: pure BVH's time / the method's (all methods trace the same rays within a run). Not for farm
    rows: each row is its own task, its pure BVH row another task's runs in another process (the row's own
    speedup_vs_bvh is against the pure BVH its task traced, whose runs farm collect does not keep)."""
    if ref is None or row.get("_farm"):
        return []
    return [b / m for b, m in zip(ref["ms_runs"], row["ms_runs"]) if m > 0]


def row_key(row):
    ray = RAY_ORDER.index(row["ray_type"]) if row["ray_type"] in RAY_ORDER else len(RAY_ORDER)
    return (row["scene"], short_path(row), ray, row.get("spp", 0))


def panel_name(row):
    spp = row.get("spp")
    return f"{short_scene(row['scene'])} {short_path(row)} {row['ray_type']}" + (f" {spp} spp" if spp and spp != 1 else "")


# ---------------------------------------------------------------------------------------------------------- output

def num(v):
    """A JSON number exactly as parsed (shortest round-trip repr), '' for null."""
    if v is None:
        return ""
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, float):
        return repr(v)
    return str(v)


def fmt(v, digits=2):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f"{v:.{digits}f}"


def fmt_g(v):
    return "-" if v is None else f"{v:.3g}"


def write_csv(path, header, rows):
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        for r in rows:
            w.writerow([num(v) if not isinstance(v, str) else v for v in r])


class Table:
    def __init__(self, name, title, caption, header, rows):
        self.name, self.title, self.caption, self.header, self.rows = name, title, caption, header, rows

    def markdown(self):
        lines = ["| " + " | ".join(self.header) + " |", "| " + " | ".join("---" for _ in self.header) + " |"]
        lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in self.rows]
        return "\n".join(lines) + "\n"

    def html(self):
        head = "".join(f"<th>{html.escape(h)}</th>" for h in self.header)
        body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>" for r in self.rows)
        return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


class Report:
    def __init__(self, data, out):
        self.data, self.out = data, out
        self.figures = []   # {"name", "title", "caption"}
        self.omitted = []   # (title, why)
        self.tables = []
        for d in ("figures", "tables", "images"):
            os.makedirs(os.path.join(out, d), exist_ok=True)

    def save(self, fig, name, title, caption, header, rows):
        base = os.path.join(self.out, "figures", name)
        # The tight box measured once for both files: bbox_inches="tight" draws the whole figure again per file.
        box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(plt.rcParams["savefig.pad_inches"])
        fig.savefig(base + ".png", metadata=PNG_METADATA, bbox_inches=box)
        fig.savefig(base + ".svg", metadata=SVG_METADATA, bbox_inches=box)
        plt.close(fig)
        write_csv(base + ".csv", header, rows)
        self.figures.append({"name": name, "title": title, "caption": caption})

    def omit(self, title, why):
        self.omitted.append((title, why))

    def table(self, name, title, caption, header, rows):
        if not rows:
            return
        t = Table(name, title, caption, header, rows)
        with open(os.path.join(self.out, "tables", name + ".md"), "w", encoding="utf-8") as f:
            f.write(t.markdown())
        write_csv(os.path.join(self.out, "tables", name + ".csv"), header, rows)
        self.tables.append(t)


def grid(panels, cols_of, width=3.2, height=2.4):
    """A figure with one axes per panel: rows = scene x path, columns = ray types (as many as needed)."""
    rows = sorted({p[:2] for p in panels})
    cols = sorted({cols_of(p) for p in panels}, key=lambda c: (RAY_ORDER.index(c[0]) if c[0] in RAY_ORDER else 9, c))
    fig, axes = plt.subplots(len(rows), len(cols), figsize=(width * len(cols), height * len(rows)), squeeze=False)
    where = {}
    for p in panels:
        where[p] = axes[rows.index(p[:2])][cols.index(cols_of(p))]
    for r in range(len(rows)):
        for c in range(len(cols)):
            if not any(where[p] is axes[r][c] for p in panels):
                axes[r][c].set_visible(False)
    return fig, where


def figure_legend(fig, axes):
    """One legend above a grid of panels (per-panel legends hide the curves)."""
    seen = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(label, handle)
    fig.legend(list(seen.values()), list(seen), loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=min(len(seen), 6),
               frameon=False, fontsize=8)


def method_order(methods):
    known = list(METHOD_COLOURS)
    return sorted(methods, key=lambda m: (known.index(m) if m in known else len(known), m))


# ---------------------------------------------------------------------------------------------------------- figures

NO_COMPARE = "the report has no compare study (every method over the scenes, paths and ray types)"


def figure_frame_times(rep):
    title = "Frame time along the walkthrough (Figure 7)"
    if not any(rep.data.rows("compare")):
        rep.omit(title, NO_COMPARE)
        return
    rows = [r for r in rep.data.rows("compare") if r.get("frame_times")]
    if not rows:
        rep.omit(title, "no compare row has per-frame times (bench JSON without frame_times)")
        return
    if max(len(r["frame_times"]) for r in rows) < 2:
        rep.omit(title, "every walkthrough has a single frame, so there is no curve to draw")
        return
    panels = {}
    for r in rows:
        panels.setdefault(row_key(r), []).append(r)
    fig, where = grid(list(panels), lambda p: (RAY_ORDER[p[2]] if p[2] < len(RAY_ORDER) else "?", p[3]))
    csv_rows = []
    for key, group in sorted(panels.items()):
        ax = where[key]
        for r in sorted(group, key=lambda r: method_order([x["method"] for x in group]).index(r["method"])):
            frames = [f["frame"] for f in r["frame_times"]]
            med = [statistics.median(f["ms_runs"]) if f["ms_runs"] else float("nan") for f in r["frame_times"]]
            lo = [min(f["ms_runs"]) if f["ms_runs"] else float("nan") for f in r["frame_times"]]
            hi = [max(f["ms_runs"]) if f["ms_runs"] else float("nan") for f in r["frame_times"]]
            colour = METHOD_COLOURS.get(r["method"])
            ax.plot(frames, med, marker=".", label=r["method"], color=colour, lw=1.2)
            ax.fill_between(frames, lo, hi, color=colour, alpha=0.15, lw=0)
            for f in r["frame_times"]:
                for i, ms in enumerate(f["ms_runs"]):
                    csv_rows.append([r["scene"], short_path(r), r["ray_type"], r.get("spp"), r["method"], f["frame"], i, ms])
        ax.set_title(panel_name(group[0]))
        ax.set_xlabel("frame")
        ax.set_ylabel("ms per frame")
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    figure_legend(fig, where.values())
    rep.save(fig, "frame_times", title,
             "Tracing time of each frame of the walkthrough per method (median over the timed runs, band: min to "
             "max), one panel per scene, path and ray type. From the rows' frame_times.",
             ["scene", "path", "ray_type", "spp", "method", "frame", "run", "ms"], csv_rows)


def figure_speedup(rep):
    title = "Speedup over pure BVH"
    if not any(rep.data.rows("compare")):
        rep.omit(title, NO_COMPARE)
        return
    rows = [r for r in rep.data.rows("compare") if r["method"] != REFERENCE and r.get("speedup_vs_bvh") is not None]
    if not rows:
        rep.omit(title, "no compare rows besides pure BVH")
        return
    groups = sorted({row_key(r) for r in rows})
    methods = method_order({r["method"] for r in rows})
    fig, ax = plt.subplots(figsize=(max(6, 0.32 * len(groups) * len(methods) + 1.5), 3.6))
    width = 0.8 / len(methods)
    csv_rows = []
    for mi, m in enumerate(methods):
        xs, ys, lo, hi = [], [], [], []
        for gi, g in enumerate(groups):
            for r in rows:
                if r["method"] == m and row_key(r) == g:
                    s = r["speedup_vs_bvh"]
                    runs = run_speedups(r, rep.data.reference(r)) or [s]
                    xs.append(gi + (mi - (len(methods) - 1) / 2) * width)
                    ys.append(s)
                    lo.append(max(0.0, s - min(runs)))
                    hi.append(max(0.0, max(runs) - s))
                    csv_rows.append([r["scene"], short_path(r), r["ray_type"], r.get("spp"), m, s, min(runs),
                                     max(runs), r["ms_median"], r.get("diff_pixels"), r.get("psnr_db")])
        ax.bar(xs, ys, width, yerr=[lo, hi], capsize=2, label=m, color=METHOD_COLOURS.get(m))
    ax.axhline(1.0, color="black", lw=0.8, ls="--")
    ax.set_xticks(range(len(groups)))
    labels = [f"{short_scene(g[0])}\n{g[1]} {RAY_ORDER[g[2]] if g[2] < len(RAY_ORDER) else '?'}" for g in groups]
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_ylabel("speedup vs pure BVH (x)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(ncol=min(len(methods), 5), loc="upper left")
    fig.tight_layout()
    rep.save(fig, "speedup", title,
             "Median over the timed runs of pure BVH's time over the method's in the same run (speedup_vs_bvh) per "
             "scene, path and ray type; the whiskers span those per-run speedups (from ms_runs), i.e. the spread "
             "over the timed runs. Dashed: as fast as pure BVH.",
             ["scene", "path", "ray_type", "spp", "method", "speedup_vs_bvh", "speedup_min", "speedup_max",
              "ms_median", "diff_pixels", "psnr_db"], csv_rows)


PHASES = [("phase1_ms", "phase 1 (queries / bounds)"), ("phase2_ms", "phase 2 (pair decisions)"),
          ("phase3_ms", "phase 3 (subtree traversal)"), ("fallback_ms", "fallback (pure pass)")]


def figure_phases(rep):
    title = "Time per phase (Figure 8)"
    if not any(rep.data.rows("compare")):
        rep.omit(title, NO_COMPARE)
        return
    rows = [r for r in rep.data.rows("compare") if r["method"] in CHCRT_METHODS and isinstance(r.get("chcrt"), dict)
            and isinstance(r["chcrt"].get("per_frame"), dict)]
    if not rows:
        rep.omit(title, "no CHC+RT rows with chcrt.per_frame counters")
        return
    rows.sort(key=lambda r: (row_key(r), method_order([r["method"]] + list(CHCRT_METHODS)).index(r["method"])))
    fig, ax = plt.subplots(figsize=(max(6, 0.45 * len(rows) + 1.5), 3.8))
    bottom = np.zeros(len(rows))
    colours = ["#9ecae1", "#fdae6b", "#3182bd", "#bdbdbd"]
    for (key, label), colour in zip(PHASES, colours):
        values = np.array([r["chcrt"]["per_frame"].get(key, 0.0) or 0.0 for r in rows])
        ax.bar(range(len(rows)), values, 0.7, bottom=bottom, label=label, color=colour)
        bottom += values
    refs = [rep.data.reference(r) for r in rows]
    ax.scatter(range(len(rows)), [ref["ms_median"] if ref else np.nan for ref in refs], marker="_", s=200,
               color="black", label="pure BVH ms/frame", zorder=3)
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels([f"{short_scene(r['scene'])} {short_path(r)}\n{r['ray_type']} {r['method']}" for r in rows],
                       rotation=60, ha="right", fontsize=6)
    ax.set_ylabel("ms per frame")
    ax.set_ylim(0, 1.08 * max(max(bottom), max([ref["ms_median"] for ref in refs if ref] or [0])))
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    rep.save(fig, "phases", title,
             "CHC+RT's tracer time per frame split into its phases (chcrt.per_frame phase1_ms, phase2_ms, phase3_ms, "
             "fallback_ms: means over the timed runs), next to pure BVH's time per frame (black tick).",
             ["scene", "path", "ray_type", "spp", "method"] + [k for k, _ in PHASES] + ["ms_median", "bvh_ms_median"],
             [[r["scene"], short_path(r), r["ray_type"], r.get("spp"), r["method"]]
              + [r["chcrt"]["per_frame"].get(k) for k, _ in PHASES] + [r["ms_median"], ref["ms_median"] if ref else None]
              for r, ref in zip(rows, refs)])


def figure_counters_per_frame(rep, counter, name, title, ylabel, caption):
    if not any(rep.data.rows("compare")):
        rep.omit(title, NO_COMPARE)
        return
    rows = [r for r in rep.data.rows("compare") if r["method"] in CHCRT_METHODS and r.get("frame_times")
            and any(isinstance(f.get("chcrt"), dict) and counter in f["chcrt"] for f in r["frame_times"])]
    if not rows:
        rep.omit(title, f"no CHC+RT rows with per-frame counters (frame_times[].chcrt.{counter})")
        return
    if all(all((f.get("chcrt") or {}).get(counter, 0) == 0 for f in r["frame_times"]) for r in rows):
        rep.omit(title, f"every frame counted 0 {counter.replace('_', ' ')} (e.g. --chcrt-queries bounds-only "
                        "decides pairs without GL queries)")
        return
    panels = {}
    for r in rows:
        panels.setdefault(row_key(r), []).append(r)
    fig, where = grid(list(panels), lambda p: (RAY_ORDER[p[2]] if p[2] < len(RAY_ORDER) else "?", p[3]))
    csv_rows = []
    for key, group in sorted(panels.items()):
        ax = where[key]
        for r in group:
            pts = [(f["frame"], f["chcrt"][counter]) for f in r["frame_times"]
                   if isinstance(f.get("chcrt"), dict) and counter in f["chcrt"]]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=".", label=r["method"],
                    color=METHOD_COLOURS.get(r["method"]))
            for f in r["frame_times"]:
                if isinstance(f.get("chcrt"), dict) and counter in f["chcrt"]:
                    csv_rows.append([r["scene"], short_path(r), r["ray_type"], r.get("spp"), r["method"], f["frame"],
                                     f["chcrt"][counter]])
        ax.set_title(panel_name(group[0]))
        ax.set_xlabel("frame")
        ax.set_ylabel(ylabel)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    figure_legend(fig, where.values())
    rep.save(fig, name, title, caption, ["scene", "path", "ray_type", "spp", "method", "frame", counter], csv_rows)


def figure_culling_efficiency(rep):
    title = "Culling efficiency (time speedup / steps ratio)"
    if not any(rep.data.rows("compare")):
        rep.omit(title, NO_COMPARE)
        return
    rows = []
    for r in rep.data.rows("compare"):
        ref = rep.data.reference(r)
        if (r["method"] in CHCRT_METHODS and ref and r.get("steps_per_ray") and ref.get("steps_per_ray")
                and r.get("speedup_vs_bvh")):
            rows.append((r, ref))
    if not rows:
        rep.omit(title, "no BVH traversal steps in the data (bench --steps; the preset's compare study runs it "
                        "unless it is switched off)")
        return
    rows.sort(key=lambda p: (row_key(p[0]), p[0]["method"]))
    groups = sorted({row_key(r) for r, _ in rows})
    methods = method_order({r["method"] for r, _ in rows})
    fig, axes = plt.subplots(1, 2, figsize=(max(8, 0.5 * len(groups) * len(methods) + 3), 3.6))
    width = 0.8 / len(methods)
    csv_rows = []
    for mi, m in enumerate(methods):
        xs, eff, ratio = [], [], []
        for gi, g in enumerate(groups):
            for r, ref in rows:
                if r["method"] == m and row_key(r) == g:
                    steps_ratio = ref["steps_per_ray"] / r["steps_per_ray"]
                    xs.append(gi + (mi - (len(methods) - 1) / 2) * width)
                    ratio.append(steps_ratio)
                    eff.append(r["speedup_vs_bvh"] / steps_ratio)
                    csv_rows.append([r["scene"], short_path(r), r["ray_type"], r.get("spp"), m, r["speedup_vs_bvh"],
                                     ref["steps_per_ray"], r["steps_per_ray"], steps_ratio, eff[-1]])
        axes[0].bar(xs, ratio, width, label=m, color=METHOD_COLOURS.get(m))
        axes[1].bar(xs, eff, width, label=m, color=METHOD_COLOURS.get(m))
    labels = [f"{short_scene(g[0])}\n{g[1]} {RAY_ORDER[g[2]] if g[2] < len(RAY_ORDER) else '?'}" for g in groups]
    for ax, ylabel in zip(axes, ["steps ratio (BVH steps / method steps)", "efficiency (speedup / steps ratio)"]):
        ax.axhline(1.0, color="black", lw=0.8, ls="--")
        ax.set_xticks(range(len(groups)))
        ax.set_xticklabels(labels, fontsize=6)
        ax.set_ylabel(ylabel)
        ax.grid(axis="y", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    rep.save(fig, "culling_efficiency", title,
             "Left: how much BVH traversal work culling removes (pure BVH's steps_per_ray over the method's). Right: "
             "how much of that saving the time keeps (speedup_vs_bvh / steps ratio; 1 = every step saved is time "
             "saved, below 1 = culling's own cost eats into it).",
             ["scene", "path", "ray_type", "spp", "method", "speedup_vs_bvh", "bvh_steps_per_ray", "steps_per_ray",
              "steps_ratio", "efficiency"], csv_rows)


def ls_depth(row):
    m = re.search(r"\bD=(\d+)", (row.get("linespace") or {}).get("params", ""))
    return int(m.group(1)) if m else None


def figure_linespace(rep):
    title = "Line Space: speed against image error per depth"
    rows = prefer_study([r for r in rep.data.rows() if isinstance(r.get("linespace"), dict)
                         and isinstance(r.get("image_error"), dict) and r.get("speedup_vs_bvh") is not None],
                        ("ls-rc", "ls-ao", "ls-ss", "ls-sscand"))
    if not rows:
        rep.omit(title, "no approximate Line Space rows (bvh+ls, chcrt+ls) with image error")
        return
    identical = [r for r in rows if r["image_error"].get("final_psnr_db") is None]
    plotted = [r for r in rows if r["image_error"].get("final_psnr_db") is not None]
    if not plotted:
        rep.omit(title, "every Line Space frame equals pure BVH's (no finite PSNR to plot)")
        return
    scenes = sorted({r["scene"] for r in plotted})
    fig, axes = plt.subplots(1, len(scenes), figsize=(3.6 * len(scenes), 3.2), squeeze=False)
    markers = {"primary": "o", "shadow": "s", "ao": "^", "diffuse": "D"}
    csv_rows = []
    for ax, scene in zip(axes[0], scenes):
        for ray in RAY_ORDER + sorted({r["ray_type"] for r in plotted} - set(RAY_ORDER)):
            for m in method_order({r["method"] for r in plotted}):
                pts = sorted([r for r in plotted if r["scene"] == scene and r["ray_type"] == ray and r["method"] == m],
                             key=lambda r: ls_depth(r) or 0)
                if not pts:
                    continue
                ax.plot([r["image_error"]["final_psnr_db"] for r in pts], [r["speedup_vs_bvh"] for r in pts],
                        marker=markers.get(ray, "x"), ls=":", color=METHOD_COLOURS.get(m), label=f"{m} {ray}")
                for r in pts:
                    ax.annotate(f"D{ls_depth(r)}", (r["image_error"]["final_psnr_db"], r["speedup_vs_bvh"]),
                                fontsize=6, xytext=(2, 2), textcoords="offset points")
        ax.axhline(1.0, color="black", lw=0.8, ls="--")
        ax.set_title(short_scene(scene))
        ax.set_xlabel("PSNR of the final frame (dB)")
        ax.set_ylabel("speedup vs pure BVH (x)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6)
    for r in sorted(rows, key=lambda r: (row_key(r), r["method"], ls_depth(r) or 0)):
        csv_rows.append([r["scene"], short_path(r), r["ray_type"], r.get("spp"), r["method"], ls_depth(r),
                         r["linespace"].get("params", ""), r["linespace"].get("modes", ""), r["speedup_vs_bvh"],
                         r["ms_median"], r["image_error"].get("final_psnr_db"), r["image_error"].get("final_mae"),
                         r["image_error"].get("indirect_psnr_db")])
    fig.tight_layout()
    note = f" {len(identical)} row(s) with frames identical to pure BVH's (no PSNR) are in the CSV only." if identical else ""
    rep.save(fig, "linespace_psnr", title,
             "Speedup of each approximate Line Space row against the PSNR of its whole rendered frames (image_error."
             "final_psnr_db; further right = closer to pure BVH), labelled with the Line Space depth D, per scene; "
             "one series per method and ray type." + note,
             ["scene", "path", "ray_type", "spp", "method", "depth", "params", "modes", "speedup_vs_bvh", "ms_median",
              "final_psnr_db", "final_mae", "indirect_psnr_db"], csv_rows)


def prefer_study(rows, studies):
    """The rows of the dedicated studies when there are any (a sweep), else all (e.g. compare's default row)."""
    dedicated = [r for r in rows if r["_study"] in studies]
    return dedicated or rows


def aggressive_rows(data):
    """chcrt-aggressive rows, one per scene, path, ray type, spp and threshold: a threshold sweep's row where both
    the sweep and the compare study measured the same threshold."""
    rows = {}
    for r in data.rows(method="chcrt-aggressive"):
        if threshold(r) is None:
            continue
        key = row_key(r) + (threshold(r),)
        if key not in rows or r["_study"] == "aggressive":
            rows[key] = r
    return [rows[k] for k in sorted(rows)]


def threshold(row):
    return ((row.get("chcrt") or {}).get("options") or {}).get("threshold")


def figure_aggressive(rep):
    title = "Aggressive visibility thresholds against image error (Table 4)"
    rows = [r for r in aggressive_rows(rep.data) if isinstance(r.get("image_error"), dict)]
    if len({threshold(r) for r in rows}) < 2:
        rep.omit(title, "fewer than two chcrt-aggressive thresholds measured (the aggressive study sweeps "
                        "--chcrt-threshold)")
        return
    rows.sort(key=lambda r: (row_key(r), threshold(r)))
    fig, axes = plt.subplots(1, 2, figsize=(8, 3.2))
    series = {}
    for r in rows:
        series.setdefault((r["scene"], short_path(r), r["ray_type"]), []).append(r)
    seen_mae = set()
    for (scene, path, ray), pts in sorted(series.items()):
        if (scene, path) not in seen_mae:  # the image error is of whole frames: the same for every ray type
            seen_mae.add((scene, path))
            axes[0].plot([threshold(r) for r in pts], [r["image_error"].get("final_mae") or 0.0 for r in pts],
                         marker="o", label=f"{short_scene(scene)} {path}")
        axes[1].plot([threshold(r) for r in pts], [r["speedup_vs_bvh"] for r in pts], marker="o",
                     label=f"{short_scene(scene)} {path} {ray}")
    axes[0].set_ylabel("MAE of the final frame")
    axes[1].set_ylabel("speedup vs pure BVH (x)")
    axes[1].axhline(1.0, color="black", lw=0.8, ls="--")
    for ax in axes:
        ax.set_xlabel("visibility threshold (rays)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    rep.save(fig, "aggressive_mae", title,
             "chcrt-aggressive per visibility threshold (chcrt.options.threshold): left, the mean absolute error of "
             "its whole rendered frames against pure BVH's (image_error.final_mae); right, its speedup per ray type.",
             ["scene", "path", "ray_type", "spp", "threshold", "speedup_vs_bvh", "ms_median", "diff_pixels",
              "final_mae", "final_psnr_db", "final_pixels_over_2_255"],
             [[r["scene"], short_path(r), r["ray_type"], r.get("spp"), threshold(r), r["speedup_vs_bvh"],
               r["ms_median"], r.get("diff_pixels"), r["image_error"].get("final_mae"),
               r["image_error"].get("final_psnr_db"), r["image_error"].get("final_pixels_over_2_255")] for r in rows])


def read_png(path):
    img = plt.imread(path)
    if img.dtype != np.float32 and img.dtype != np.float64:
        img = img.astype(np.float64) / 255.0
    if img.ndim == 2:
        img = np.stack([img] * 3, axis=-1)
    return img[..., :3]


def figure_images(rep):
    title = "Debug images and image error"
    if not rep.data.images:
        rep.omit(title, "no images study in this report (--from-json reports bench data only)")
        return
    for g in rep.data.images:
        files = g.get("files", {})
        missing = [k for k, f in files.items() if not os.path.exists(os.path.join(rep.out, f))]
        if "bvh" not in files or missing:
            rep.omit(f"{title}: {g.get('id')}", f"image files missing: {', '.join(missing) or 'bvh'}")
            continue
        reference = read_png(os.path.join(rep.out, files["bvh"]))
        debug = [k for k in ("overdraw", "subtrees", "batches", "cost") if k in files]
        methods = [k for k in files if k not in debug and k != "bvh"]
        cols = max(1 + len(debug), 2 * len(methods), 1)
        nrows = 2 if methods else 1
        fig, axes = plt.subplots(nrows, cols, figsize=(2.2 * cols, 2.5 * nrows), squeeze=False)
        for ax in axes.flat:
            ax.axis("off")
        captions = {"bvh": "frame (pure BVH)", "overdraw": "overdraw (queries/pixel)",
                    "subtrees": "subtrees (last hit)", "batches": "batches (subtrees/pixel)",
                    "cost": "cost (traversal steps)"}
        for i, k in enumerate(["bvh"] + debug):
            axes[0][i].imshow(plt.imread(os.path.join(rep.out, files[k])))
            axes[0][i].set_title(captions[k], fontsize=7)
        csv_rows = []
        for i, m in enumerate(methods):
            img = read_png(os.path.join(rep.out, files[m]))
            if img.shape != reference.shape:
                raise BadInput(f"{files[m]}: size differs from {files['bvh']}")
            diff = np.abs(img - reference).max(axis=2) * 255.0
            vmax = max(float(diff.max()), 1.0)
            diff_file = f"images/{g['id']}_diff_{re.sub(r'[^A-Za-z0-9.-]', '-', m)}.png"
            plt.imsave(os.path.join(rep.out, diff_file), diff, cmap="inferno", vmin=0, vmax=vmax,
                       metadata=PNG_METADATA)
            differing = int((diff > 0.5).sum())
            axes[1][2 * i].imshow(plt.imread(os.path.join(rep.out, files[m])))
            axes[1][2 * i].set_title(f"{m}", fontsize=7)
            im = axes[1][2 * i + 1].imshow(diff, cmap="inferno", vmin=0, vmax=vmax)
            axes[1][2 * i + 1].set_title(f"|{m} - bvh| (max {diff.max():.0f}/255)", fontsize=7)
            fig.colorbar(im, ax=axes[1][2 * i + 1], fraction=0.046, pad=0.02)
            csv_rows.append([g.get("scene", ""), g.get("path", ""), g.get("frame", 0), m, files[m], diff_file,
                             float(diff.mean()), float(diff.max()), differing, int(diff.size)])
        fig.suptitle(f"{short_scene(g.get('scene', ''))} {g.get('path', '')}, frame {g.get('frame', 0)}", fontsize=9)
        fig.tight_layout()
        rep.save(fig, "images_" + re.sub(r"^images_", "", g["id"]), f"{title}: {short_scene(g.get('scene', ''))} "
                 f"{g.get('path', '')}",
                 "Top: the frame rendered with pure BVH and CHC+RT's debug images of chcrt-noadapt (render "
                 "--debug-image: overdraw = query fragments per pixel with GL occlusion queries (--chcrt-queries gl), "
                 "Figure 4; subtrees = the termination subtree "
                 "that last changed the hit, Figure 5 left; batches = subtrees traversed per pixel, Figure 5 right; "
                 "cost = traversal steps, log scale). Bottom: each approximate method's frame beside its false-colour "
                 "difference to pure BVH's (largest channel difference in 1/255, scaled to its maximum).",
                 ["scene", "path", "frame", "method", "image", "diff_image", "mean_abs_diff_255", "max_abs_diff_255",
                  "pixels_differing", "pixels"], csv_rows)


# ---------------------------------------------------------------------------------------------------------- tables

def error_cells(r):
    """Differing hit pixels and, for approximate methods, the image error of their frames."""
    ie = r.get("image_error") if isinstance(r.get("image_error"), dict) else {}
    psnr = ie.get("final_psnr_db", r.get("psnr_db"))
    return [str(r.get("diff_pixels", "-")), fmt(psnr, 1) if psnr is not None else ("identical" if ie else "-"),
            fmt_g(ie.get("final_mae")) if ie else "-"]


def speed_cells(r, ref):
    runs = run_speedups(r, ref)
    spread = f"{min(runs):.2f}-{max(runs):.2f}" if len(runs) > 1 else "-"
    return [fmt(r["ms_median"]), fmt(r.get("speedup_vs_bvh")), spread]


def table2(rep):
    rows = sorted(rep.data.rows("compare"), key=lambda r: (row_key(r), method_order([r["method"]] + list(METHOD_COLOURS)).index(r["method"])))
    out = []
    for r in rows:
        ref = rep.data.reference(r)
        c = (r.get("chcrt") or {}).get("sum") or {}  # shares and means are ratios: the sum object holds them whole
        steps = r.get("steps_per_ray")
        ratio = ref["steps_per_ray"] / steps if steps and ref and ref.get("steps_per_ray") else None
        eff = r["speedup_vs_bvh"] / ratio if ratio and r.get("speedup_vs_bvh") else None
        out.append([short_scene(r["scene"]), short_path(r), r["ray_type"], str(r.get("spp", "-")), r["method"]]
                   + speed_cells(r, ref) + error_cells(r)
                   + [f"{100 * c['culled_share']:.0f}%" if "culled_share" in c else "-",
                      fmt(c.get("mean_height"), 1) if c.get("culled_share") else "-",  # no culled trace: no height
                      fmt(steps, 1) if steps else "-", fmt(ratio), fmt(eff)])
    rep.table("table2", "Table 2: time per frame and speedup over pure BVH",
              "Median ms per frame over the timed runs, speedup over pure BVH with its spread over the runs, the "
              "hit pixels differing from pure BVH (diff px; 0 for exact methods), the PSNR and MAE of approximate "
              "methods' whole frames, CHC+RT's culled share of traces and mean termination height, BVH traversal "
              "steps per active ray, their ratio to pure BVH's and the culling efficiency (speedup / steps ratio).",
              ["scene", "path", "ray", "spp", "method", "ms/frame", "speedup", "spread", "diff px", "PSNR dB", "MAE",
               "culled", "H", "steps/ray", "steps ratio", "efficiency"], out)


def table_figure8(rep):
    rows = sorted([r for r in rep.data.rows("compare") if r["method"] in CHCRT_METHODS
                   and isinstance((r.get("chcrt") or {}).get("per_frame"), dict)], key=lambda r: (row_key(r), r["method"]))
    out = []
    for r in rows:
        c = r["chcrt"]["per_frame"]
        out.append([short_scene(r["scene"]), short_path(r), r["ray_type"], r["method"]]
                   + [fmt(c.get(k)) for k, _ in PHASES]
                   + [fmt(c.get("queries"), 1), fmt(c.get("subtrees_scheduled"), 1), fmt(r["ms_median"]),
                      fmt(r.get("speedup_vs_bvh")), str(r.get("diff_pixels", "-"))])
    rep.table("figure8", "Figure 8 numbers: time per phase",
              "CHC+RT's tracer time per frame by phase (means over the timed runs), queries and scheduled subtrees "
              "per frame, next to the row's ms per frame, speedup and differing pixels.",
              ["scene", "path", "ray", "method", "phase 1 ms", "phase 2 ms", "phase 3 ms", "fallback ms",
               "queries", "subtrees", "ms/frame", "speedup", "diff px"], out)


def table4(rep):
    rows = aggressive_rows(rep.data)
    out = []
    for r in rows:
        ref = rep.data.reference(r)
        ie = r.get("image_error") or {}
        over = ie.get("final_pixels_over_2_255")
        out.append([short_scene(r["scene"]), short_path(r), r["ray_type"], str(r.get("spp", "-")), str(threshold(r)),
                    fmt(ref["ms_median"]) if ref else "-"] + speed_cells(r, ref) + error_cells(r)
                   + [f"{100 * over:.2f}%" if over is not None else "-"])
    rep.table("table4", "Table 4: aggressive visibility thresholds",
              "chcrt-aggressive per visibility threshold: pure BVH's and its ms per frame, speedup with the spread "
              "over runs, the hit pixels differing from pure BVH, the PSNR and MAE of its whole frames and the "
              "share of pixels off by more than 2/255.",
              ["scene", "path", "ray", "spp", "threshold", "bvh ms", "ms/frame", "speedup", "spread", "diff px",
               "PSNR dB", "MAE", "pixels > 2/255"], out)


def setting(r, rep, key):
    return (rep.data.benches[r["_file"]]["json"].get("settings") or {}).get(key)


def table5(rep):
    rows = sorted([r for r in rep.data.rows("rotation") if r["method"] != REFERENCE],
                  key=lambda r: (row_key(r), setting(r, rep, "rotation") or 0, r["method"]))
    out = []
    for r in rows:
        ref = rep.data.reference(r)
        out.append([short_scene(r["scene"]), short_path(r), r["ray_type"], str(r.get("spp", "-")),
                    fmt_g(setting(r, rep, "rotation")), r["method"], fmt(ref["ms_median"]) if ref else "-"]
                   + speed_cells(r, ref) + [str(r.get("diff_pixels", "-"))])
    rep.table("table5", "Table 5: per-pixel sample rotation",
              "Rays of one pass share a sample rotated per pixel by up to this angle (--rotation): pure BVH's and the "
              "method's ms per frame, speedup with its spread and the hit pixels differing from pure BVH.",
              ["scene", "path", "ray", "spp", "rotation", "method", "bvh ms", "ms/frame", "speedup", "spread",
               "diff px"], out)


def table_work(rep):
    rows = sorted(rep.data.rows("work"), key=lambda r: (row_key(r), r["method"]))
    out = []
    for r in rows:
        ref = rep.data.reference(r)
        height = ((r.get("chcrt") or {}).get("options") or {}).get("height")
        steps = r.get("steps_per_ray")
        ratio = ref["steps_per_ray"] / steps if steps and ref and ref.get("steps_per_ray") else None
        out.append([short_scene(r["scene"]), short_path(r), r["ray_type"], r["method"], str(height or "-"),
                    fmt(steps, 1) if steps else "-", fmt(ratio)] + speed_cells(r, ref) + [str(r.get("diff_pixels", "-"))])
    rep.table("work", "Traversal work per termination height",
              "BVH traversal steps per active ray of pure BVH and always-culling CHC+RT per forced termination height, "
              "next to the times.",
              ["scene", "path", "ray", "method", "height", "steps/ray", "steps ratio", "ms/frame", "speedup",
               "spread", "diff px"], out)


def ls_mb(ls):
    """Line Space MB of a row; an N-tree's are its Line Spaces and its node pool."""
    if ls.get("mb") is not None:
        return ls["mb"]
    if ls.get("linespace_mb") is not None:
        return ls["linespace_mb"] + (ls.get("node_pool_mb") or 0.0)
    return None


def table_linespace(rep):
    rows = sorted([r for r in rep.data.rows(("ls-rc", "ls-ao", "ls-ss", "ls-sscand", "ls-ntree"))
                   if r["method"] != REFERENCE], key=lambda r: (row_key(r), r["_study"], r["method"], ls_depth(r) or 0))
    out = []
    for r in rows:
        ref = rep.data.reference(r)
        ls = r.get("linespace") or r.get("ntree") or {}
        shadow = r.get("shadow_samples_differing_fraction")
        out.append([short_scene(r["scene"]), r["_study"], r["ray_type"], str(r.get("spp", "-")), r["method"],
                    ls.get("params", "-"), fmt(ref["ms_median"]) if ref else "-"] + speed_cells(r, ref)
                   + error_cells(r) + [f"{100 * shadow:.2f}%" if shadow is not None else "-",
                                       fmt(ls_mb(ls), 1) if ls_mb(ls) is not None else "-",
                                       fmt(ls.get("build_s"), 2) if ls.get("build_s") is not None else "-"])
    rep.table("linespace", "Line Space: speed against image error (RC / SS Table 1 shape)",
              "Line Space methods per parameter set: pure BVH's and the method's ms per frame, speedup with its "
              "spread, differing hit pixels, PSNR and MAE of the whole frames, the share of shadow samples whose "
              "answer differs, the Line Spaces' size and build time.",
              ["scene", "study", "ray", "spp", "method", "parameters", "bvh ms", "ms/frame", "speedup", "spread",
               "diff px", "PSNR dB", "MAE", "shadow samples differing", "MB", "build s"], out)


# ---------------------------------------------------------------------------------------------------------- pages

# The driver's name and version as GL_VERSION carries it after the GL version itself.
DRIVER_PATTERNS = [
    (re.compile(r"\bMesa (\d[\w.+~-]*)"), "Mesa {}"),                          # "4.5 (Core Profile) Mesa 22.3.6"
    (re.compile(r"\bNVIDIA (\d[\d.]*)"), "NVIDIA {}"),                         # "4.6.0 NVIDIA 535.104.05"
    (re.compile(r"\bProfile Context (?:FireGL )?(\d[\d.]*)"), "AMD {}"),      # "4.6.14830 Compatibility Profile Context 22.20"
    (re.compile(r"\bBuild (\d[\d.]*)"), "Intel build {}"),                     # "4.6.0 - Build 31.0.101.4255"
]


def gl_driver(version):
    """The driver named in a GL_VERSION string ("Mesa 22.3.6", "NVIDIA 535.104.05", ...), or "unknown"."""
    for pattern, name in DRIVER_PATTERNS:
        m = pattern.search(version or "")
        if m:
            return name.format(m.group(1))
    return "unknown"


def machine_facts(data):
    """What the report ran on: the report's own machine and every distinct measurement setup of its benches."""
    facts = []
    m = data.manifest.get("machine") or {}
    setups = {}
    for b in data.benches:
        j = b["json"]
        jm = j.get("machine") or {}
        key = (j.get("gl_vendor"), j.get("gl_renderer"), j.get("gl_version"), jm.get("cpu"), jm.get("cores"),
               jm.get("commit"))
        s = setups.setdefault(key, {"files": 0, "started": [], "finished": [], "before": [], "after": []})
        s["files"] += 1
        for k, src in (("started", "started_utc"), ("finished", "finished_utc")):
            if jm.get(src):
                s[k].append(jm[src])
        if jm.get("load_before"):
            s["before"].append(jm["load_before"][0])
        if jm.get("load_after"):
            s["after"].append(jm["load_after"][0])
    for (vendor, renderer, version, cpu, cores, commit), s in setups.items():
        facts.append(("GL", f"{vendor or '?'} / {renderer or '?'} / {version or '?'}"))
        facts.append(("driver", gl_driver(version)))
        facts.append(("CPU", f"{cpu or '?'}, {cores or '?'} cores"))
        facts.append(("commit", commit or "?"))
        if s["started"]:
            facts.append(("measured", f"{min(s['started'])} to {max(s['finished'] or s['started'])} UTC "
                                      f"({s['files']} bench run(s))"))
        if s["before"]:
            facts.append(("load (1 min) before/after each bench",
                          f"{min(s['before']):.2f}-{max(s['before']):.2f} / {min(s['after'] or [0]):.2f}-"
                          f"{max(s['after'] or [0]):.2f} on {cores or '?'} cores"))
    for b in data.benches:
        tasks = farm_tasks(b["json"])
        if tasks:
            hosts = sorted({t.get("host") or "?" for t in tasks})
            walls = [t["wall_s"] for t in tasks if isinstance(t.get("wall_s"), (int, float))]
            facts.append(("farm tasks", f"{os.path.basename(b['file'])}: {len(tasks)} task(s), one per row, on "
                                        f"{', '.join(hosts)}" + (f", {min(walls):.1f}-{max(walls):.1f} s each" if walls
                                                                 else "")))
    facts.append(("report made", f"{m.get('started_utc', '?')} to {m.get('finished_utc', '?')} UTC on "
                                  f"{m.get('cpu', '?')}, {m.get('cores', '?')} cores, commit {m.get('commit', '?')}"))
    if m.get("load_before"):
        facts.append(("load average before/after the report", f"{' '.join(f'{v:.2f}' for v in m['load_before'])} / "
                                                                f"{' '.join(f'{v:.2f}' for v in m.get('load_after', []))}"))
    return facts


def warnings(data):
    out = []
    renderers = {b["json"].get("gl_renderer") or "" for b in data.benches}
    soft = sorted(r for r in renderers if SOFTWARE_RASTERISERS.search(r))
    if soft:
        out.append(f"The renderer is a software rasteriser ({', '.join(soft)}): absolute times are CPU times of the "
                   "GL driver and say little about a GPU; the ratios between methods traced in the same run are what "
                   "these numbers show.")
    # The load before the first bench: later benches' load averages include the report's own earlier benches.
    machine = data.manifest.get("machine") or {}
    cores, before = machine.get("cores") or 0, (machine.get("load_before") or [None])[0]
    if data.manifest.get("from_json"):
        first = min((b["json"].get("machine") or {} for b in data.benches),
                    key=lambda m: m.get("started_utc") or "~", default={})
        cores, before = first.get("cores") or 0, (first.get("load_before") or [None])[0]
    if cores and before is not None and before >= 0.5 * cores:
        out.append(f"The machine was busy before the first bench (1-minute load average {before:.2f} on {cores} "
                   "cores): other work may have inflated the times.")
    return out


def command_lines(data):
    lines = []
    words = data.manifest.get("command_line") or []
    if words:
        lines.append(("report", " ".join(shell_quote(w) for w in words)))
    for g in data.manifest.get("groups", []):
        for c in g.get("commands", []):
            lines.append((g.get("id", ""), c))
        if g.get("study") == "from-json":
            b = next((b for b in data.benches if b["group"] is g), None)
            if b and b["json"].get("command_line"):
                lines.append((g.get("id", ""), " ".join(shell_quote(w) for w in b["json"]["command_line"])))
            elif b:
                for t in farm_tasks(b["json"]):
                    if t.get("command_line"):
                        lines.append((f"{g.get('id', '')} farm task: {t.get('row', '')}",
                                      " ".join(shell_quote(w) for w in t["command_line"])))
    return lines


def shell_quote(w):
    return w if re.fullmatch(r"[A-Za-z0-9_\-+=.,:/@]+", w or "") else "'" + w.replace("'", "'\\''") + "'"


CSS = """body{font-family:sans-serif;max-width:1400px;margin:1em auto;padding:0 1em;color:#222}
table{border-collapse:collapse;font-size:12px;margin:.5em 0 1.5em}th,td{border:1px solid #ccc;padding:2px 6px;
text-align:right}th{background:#f0f0f0}td:nth-child(-n+5){text-align:left}.warn{background:#fff3cd;border:1px solid
#e0c060;padding:.5em 1em}figure{margin:1em 0 2em}figure img{max-width:100%;border:1px solid #eee}figcaption{
font-size:13px;color:#444;max-width:1000px}code,pre{font-size:11px}pre{background:#f7f7f7;padding:.5em;overflow-x:auto}
dl{display:grid;grid-template-columns:max-content auto;gap:2px 1em}dt{font-weight:bold}dd{margin:0}"""


def write_pages(rep):
    data = rep.data
    title = "chcrt report"
    preset = data.manifest.get("preset")
    subtitle = f"preset {preset}" if preset else "from bench JSON"
    facts = machine_facts(data)
    warns = warnings(data)
    cmds = command_lines(data)

    h = [f"<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{title}</title>",
         "<link rel=\"icon\" href=\"data:,\">", f"<style>{CSS}</style></head><body>",
         f"<h1>{title} <small>({html.escape(subtitle)})</small></h1>", "<h2>What it ran on</h2><dl>"]
    h += [f"<dt>{html.escape(k)}</dt><dd>{html.escape(str(v))}</dd>" for k, v in facts]
    h.append("</dl>")
    h += [f"<p class=\"warn\">{html.escape(w)}</p>" for w in warns]
    md = [f"# {title} ({subtitle})", "", "## What it ran on", ""]
    md += [f"- **{k}**: {v}" for k, v in facts]
    md.append("")
    md += [f"> **Warning:** {w}\n" for w in warns]

    h.append("<h2>Figures</h2>")
    md += ["## Figures", ""]
    for f in rep.figures:
        n = f["name"]
        h.append(f"<figure id=\"{n}\"><h3>{html.escape(f['title'])}</h3><img src=\"figures/{n}.png\" "
                 f"alt=\"{html.escape(f['title'])}\"><figcaption>{html.escape(f['caption'])} "
                 f"(<a href=\"figures/{n}.svg\">SVG</a>, <a href=\"figures/{n}.csv\">CSV</a>)</figcaption></figure>")
        md += [f"### {f['title']}", "", f"![{f['title']}](figures/{n}.png)", "",
               f"{f['caption']} ([SVG](figures/{n}.svg), [CSV](figures/{n}.csv))", ""]
    if rep.omitted:
        h.append("<h3>Figures not drawn</h3><ul>")
        h += [f"<li><b>{html.escape(t)}</b>: {html.escape(w)}</li>" for t, w in rep.omitted]
        h.append("</ul>")
        md += ["### Figures not drawn", ""] + [f"- **{t}**: {w}" for t, w in rep.omitted] + [""]

    h.append("<h2>Tables</h2>")
    md += ["## Tables", ""]
    for t in rep.tables:
        h.append(f"<h3 id=\"{t.name}\">{html.escape(t.title)}</h3><p>{html.escape(t.caption)} "
                 f"(<a href=\"tables/{t.name}.csv\">CSV</a>, <a href=\"tables/{t.name}.md\">markdown</a>)</p>")
        h.append(t.html())
        md += [f"### {t.title}", "", t.caption, "", t.markdown()]

    h.append("<h2>Commands</h2><p>The exact command lines of this report and of every bench and render it ran "
             "(rerun one to reproduce its numbers).</p><pre>")
    h += [html.escape(f"# {gid}\n{c}") for gid, c in cmds]
    h.append("</pre></body></html>")
    md += ["## Commands", "", "```sh"] + [f"# {gid}\n{c}" for gid, c in cmds] + ["```", ""]
    with open(os.path.join(rep.out, "index.html"), "w", encoding="utf-8") as f:
        f.write("\n".join(h) + "\n")
    with open(os.path.join(rep.out, "report.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(md))


def main(argv):
    if len(argv) != 3:
        print("usage: chcrt_report.py MANIFEST OUT_DIR", file=sys.stderr)
        return 2
    manifest_path, out = argv[1], argv[2]
    try:
        manifest = read_json(manifest_path)
        if not isinstance(manifest, dict) or not isinstance(manifest.get("groups"), list):
            raise BadInput(f"{manifest_path}: not a chcrt report manifest (no \"groups\")")
        data = Data(manifest, out)
        rep = Report(data, out)
        figure_frame_times(rep)
        figure_speedup(rep)
        figure_phases(rep)
        figure_counters_per_frame(rep, "queries", "queries_per_frame", "Occlusion queries per frame", "queries",
                                  "GL occlusion queries CHC+RT issued in each frame of the walkthrough "
                                  "(frame_times[].chcrt.queries, mean over the timed runs).")
        figure_counters_per_frame(rep, "subtrees_scheduled", "subtrees_per_frame", "Subtrees traced per frame",
                                  "subtrees scheduled",
                                  "Termination subtrees CHC+RT scheduled for traversal in each frame of the "
                                  "walkthrough (frame_times[].chcrt.subtrees_scheduled, mean over the timed runs).")
        figure_culling_efficiency(rep)
        figure_linespace(rep)
        figure_aggressive(rep)
        figure_images(rep)
        table2(rep)
        table_figure8(rep)
        table4(rep)
        table5(rep)
        table_work(rep)
        table_linespace(rep)
        write_pages(rep)
    except BadInput as e:
        print(f"chcrt: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
