#!/usr/bin/env bash
# The GPU check (docs/gpu.md): from an unpacked bundle (scripts/gpu_bundle.sh) on a machine with a GPU and no
# network, measures what issue 14 asks for within a time budget (default 450 s, under 8 minutes) and writes, as it
# goes, OUTDIR/summary.md (GL renderer, driver, every command with its exit code and time), OUTDIR/results.json and
# results.md (every step and table), OUTDIR/data/*.json|md (each command's own output) and OUTDIR/logs/*.log.
# Steps run in order of importance, each under its own time limit; a step that does not fit the remaining time is
# skipped and listed as such, and a step that runs over its limit is stopped, so a run always ends in time and
# leaves what it measured.
#   1. info (and `info --devices` when the binary has it): GL vendor, renderer, version;
#   2. CHC+RT Table 2 at 1920x1080 on city:1m, near and far walkthroughs: primary 1 spp, shadow 16, AO 20, diffuse 20,
#      methods bvh, chcrt, chcrt-noadapt (with --shader-stage: compute first);
#   3. verify on the city: GLSL against Embree, CHC+RT against pure BVH (and with --shader-stage, the compute
#      tracers, and compute against fragment renders compared byte for byte);
#   4. the same Table 2 with fragment shaders (only with --shader-stage);
#   5. Table 2 at 1920x1080 on city:10m;
#   6. Line Space indirect (one-bounce diffuse, bvh+ls against bvh) on the procedural interior;
#   7. out of core: a city prepared on the machine (chcrt prepare), traced through a GPU cache smaller than it;
#   8. Table 2 at 1920x1080 on the interior and the plant (1M triangles each); 9. Table 2 at 1280x720 on every
#      scene; 10. with --shader-stage, Table 2 with fragment shaders on the other scenes at 1920x1080.
# Usage: gpu_check.sh [--quick] [--budget S] [--only ID,...] [--list] [--chcrt PATH] [--gl-device N] OUTDIR
#   --quick      tiny sizes (scenes of 100k-300k triangles, 160x90 and 240x135, few samples): a test of the script
#                itself on llvmpipe; its numbers mean nothing;
#   --budget S   total seconds for all steps (default 450; with --quick 1200);
#   --only IDS   run only the steps whose id starts with one of IDS (see --list), e.g. --only t2-1080-city10m;
#   --chcrt P    the chcrt to run (default: run.sh next to this script, else build/bin/chcrt of the source tree);
#   --gl-device  passed to every command (default: --gl-device auto when the binary accepts it).
# Needs bash and Python 3 only (no other program, no network). Flags the binary does not have (--shader-stage,
# info --devices, --gl-device auto) are detected from its --help and their steps skipped with a message.
set -euo pipefail
here=$(cd "${BASH_SOURCE[0]%/*}" 2>/dev/null && pwd -P || pwd -P)
python=${CHCRT_PYTHON:-python3}
if ! command -v "$python" >/dev/null; then
  echo "gpu_check: Python 3 ($python) is required" >&2
  exit 2
fi
read -r -d '' program <<'PYTHON' || true
import argparse, datetime, hashlib, json, os, platform, re, shlex, signal, subprocess, sys, time

here = sys.argv[1]
argv = sys.argv[2:]
parser = argparse.ArgumentParser(prog="gpu_check.sh", description="chcrt GPU check (docs/gpu.md)")
parser.add_argument("outdir")
parser.add_argument("--quick", action="store_true")
parser.add_argument("--budget", type=float)
parser.add_argument("--only", default="")
parser.add_argument("--list", action="store_true")
parser.add_argument("--chcrt")
parser.add_argument("--gl-device")

def fail(message):
    print("gpu_check: error: " + message, file=sys.stderr)
    sys.exit(2)

parser.error = lambda message: fail(message + " (usage: gpu_check.sh [--quick] [--budget S] [--only ID,...] [--list] "
                                    "[--chcrt PATH] [--gl-device N] OUTDIR)")
args = parser.parse_args(argv)

budget = args.budget if args.budget is not None else (1200.0 if args.quick else 450.0)
if budget <= 0:
    fail("--budget must be positive")
start = time.monotonic()
deadline = start + budget
RESERVE_S = 4.0  # kept back for writing the summary

# --- the binary and what it supports -------------------------------------------------------------------------
if args.chcrt:
    chcrt = [os.path.abspath(args.chcrt)]
elif os.path.isfile(os.path.join(here, "run.sh")):
    chcrt = [os.path.join(here, "run.sh")]
elif os.path.isfile(os.path.join(here, "..", "build", "bin", "chcrt")):
    chcrt = [os.path.abspath(os.path.join(here, "..", "build", "bin", "chcrt"))]
else:
    fail("no chcrt found: run.sh is not next to this script and there is no ../build/bin/chcrt; pass --chcrt PATH")
if not os.access(chcrt[0], os.X_OK):
    fail(chcrt[0] + " is not executable")
out = os.path.abspath(args.outdir)

def help_text(*command):
    try:
        r = subprocess.run(chcrt + list(command) + ["--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           stdin=subprocess.DEVNULL, timeout=30)
        return r.stdout.decode(errors="replace") if r.returncode == 0 else ""
    except (OSError, subprocess.TimeoutExpired):
        return ""

bench_help = help_text("bench")
if not bench_help:
    fail(" ".join(chcrt) + " bench --help failed: is this a chcrt binary, and does it run here?")
info_help = help_text("info")
has_stage = "--shader-stage" in bench_help
has_devices = "--devices" in info_help
gl_device_line = next((l for l in bench_help.splitlines() if "--gl-device" in l), "")
has_device_auto = "auto" in gl_device_line
notes = []
if not has_stage:
    notes.append("this chcrt has no --shader-stage: every tracer runs as its fragment shader (the default); the "
                 "compute steps are skipped")
if not has_devices:
    notes.append("this chcrt has no `info --devices`: the device list step is skipped")
device_args = []
if args.gl_device is not None:
    device_args = ["--gl-device", args.gl_device]
elif has_device_auto:
    device_args = ["--gl-device", "auto"]
else:
    notes.append("this chcrt's --gl-device takes no `auto`: it renders on the first EGL device that makes a context")

# --- sizes ------------------------------------------------------------------------------------------------------
Q = args.quick
RES = {"1080": (240, 135) if Q else (1920, 1080), "720": (160, 90) if Q else (1280, 720)}
SCENES = {"city1m": "city:100k" if Q else "city:1m", "city10m": "city:300k" if Q else "city:10m",
          "interior": "interior:100k" if Q else "interior:1m", "plant": "plant:100k" if Q else "plant:1m"}
# Table 2 of CHC+RT: one bench per sample count (bench takes one --spp for all its ray types).
SPP_GROUPS = [("primary", 1), ("shadow", 2 if Q else 16), ("ao,diffuse", 2 if Q else 20)]
T2_FRAMES = {"compute": "0-1" if Q else "0-4", "fragment": "0-1" if Q else "0-1", None: "0-1" if Q else "0-4"}
T2_METHODS = "bvh,chcrt,chcrt-noadapt"
STAGES = ["compute", "fragment"] if has_stage else [None]

# --- steps ------------------------------------------------------------------------------------------------------
# A step: id, title, kind, seconds (its limit), commands (argv lists run in order; a failing command does not stop
# the later ones of its step unless `chain`), plus what the report needs.
steps = []
def step(id, title, kind, seconds, commands, chain=False, **extra):
    steps.append(dict(id=id, title=title, kind=kind, seconds=seconds, commands=commands, chain=chain, **extra))

def data(name):
    return os.path.join(out, "data", name)

def bench(scene_key, path, res, types, spp, stage, methods=T2_METHODS, frames=None, extra=()):
    w, h = RES[res]
    c = ["bench", "--scene", SCENES[scene_key], "--camera-path", path, "--width", str(w), "--height", str(h),
         "--ray-type", types, "--spp", str(spp), "--method", methods, "--frames", frames or T2_FRAMES[stage],
         "--runs", "1", "--warmup", "1", "-q", "--ls-cache", os.path.join(out, "cache")]
    if stage:
        c += ["--shader-stage", stage]
    return c + list(extra)

def table2_steps(res, scene_key, stage, seconds):
    label = stage or "default"
    for path in ("near", "far"):
        sid = "t2-%s-%s-%s-%s" % (res, scene_key, label, path)
        commands = []
        for types, spp in SPP_GROUPS:
            name = "%s-%s.json" % (sid, types.replace(",", "-"))
            commands.append(bench(scene_key, path, res, types, spp, stage) + ["--json", data(name)])
        step(sid, "Table 2, %s, %dx%d, %s walkthrough, %s shaders" % (SCENES[scene_key], RES[res][0],
             RES[res][1], path, label), "table2", seconds, commands, scene=SCENES[scene_key], res=res, path=path,
             stage=label)

# 1. info
info_cmds = [["info", "--no-scene", "--stats-json", data("info.json")]]
step("info", "OpenGL implementation", "info", 30 if not Q else 60, [info_cmds[0] + device_args])
if has_devices:
    step("info-devices", "EGL devices (info --devices)", "info", 20, [["info", "--devices", "--no-scene"]])
first_stage = STAGES[0]
# 2. Table 2, 1080p, city:1m
table2_steps("1080", "city1m", first_stage, 80 if not Q else 240)
# 3. verify on the city
vw, vh = RES["720"]
vbase = ["--scene", SCENES["city1m"], "--width", str(vw), "--height", str(vh), "--frames", "spread:2",
         "--ray-type", "primary,shadow,ao,diffuse", "-q"]
verify_cmds = [["verify"] + vbase + ["--stats-json", data("verify-bvh-embree.json")],
               ["verify", "--method", "chcrt"] + vbase + ["--stats-json", data("verify-chcrt.json")],
               ["verify", "--method", "chcrt-noadapt"] + vbase + ["--stats-json", data("verify-chcrt-noadapt.json")]]
if has_stage:
    verify_cmds += [["verify", "--shader-stage", "compute"] + vbase + ["--stats-json", data("verify-bvh-embree-compute.json")],
                    ["verify", "--method", "chcrt", "--shader-stage", "compute"] + vbase + ["--stats-json", data("verify-chcrt-compute.json")]]
step("verify", "verify on %s (%dx%d, 2 frames, every ray type)" % (SCENES["city1m"], vw, vh), "verify",
     90 if not Q else 300, verify_cmds)
if has_stage:
    rbase = ["render", "--scene", SCENES["city1m"], "--width", str(vw), "--height", str(vh), "--frames", "0",
             "--spp", "2", "-q"]
    step("stages", "compute against fragment: the same frame rendered with both, compared byte for byte", "stages",
         60 if not Q else 200,
         [rbase + ["--method", m, "--shader-stage", s, "-o", os.path.join(out, "images", "%s-%s.exr" % (m, s))]
          for m in ("bvh", "chcrt") for s in ("fragment", "compute")])
# 4. Table 2, 1080p, city:1m with fragment shaders
if has_stage:
    table2_steps("1080", "city1m", "fragment", 40 if not Q else 240)
# 5. Table 2, 1080p, city:10m
table2_steps("1080", "city10m", first_stage, 60 if not Q else 240)
# 6. Line Space indirect
lw, lh = RES["720"]
step("linespace", "Line Space indirect: one-bounce diffuse, bvh+ls against bvh, %s near, %dx%d" %
     (SCENES["interior"], lw, lh), "bench", 75 if not Q else 300,
     [["bench", "--scene", SCENES["interior"], "--camera-path", "near", "--width", str(lw), "--height", str(lh),
       "--ray-type", "diffuse", "--effects", "diffuse", "--spp", "2" if Q else "8", "--method", "bvh,bvh+ls",
       "--frames", "0-1", "--runs", "1", "--warmup", "1", "-q", "--ls-cache", os.path.join(out, "cache"),
       "--json", data("linespace.json")]])
# 7. out of core
chs = os.path.join(out, "cache", "city-ooc.chs")
ooc_scene = "city:200k" if Q else "city:2m"
ow, oh = RES["1080"]
# The near walkthrough's working set fits the cache after the warm-up; the far one sees the whole city and streams.
step("outofcore", "out of core: %s prepared here, traced through a %d MB GPU cache, near and far" %
     (ooc_scene, 8 if Q else 64), "outofcore", 80 if not Q else 300,
     [["prepare", "--scene", ooc_scene, "-o", chs, "-q", "--subtree-triangles", "16384" if Q else "65536"]] +
     [["bench", "--scene", chs, "--out-of-core", "--gpu-cache-mb", "8" if Q else "64", "--camera-path", path,
       "--width", str(ow), "--height", str(oh), "--ray-type", "primary,shadow", "--spp", "1", "--method", "chcrt",
       "--frames", "0-3", "--runs", "1", "--warmup", "1", "-q", "--json", data("outofcore-%s.json" % path)]
      for path in ("near", "far")],
     chain=True)
# 8., 9. the rest of Table 2
for key in ("interior", "plant"):
    table2_steps("1080", key, first_stage, 50 if not Q else 240)
for key in ("city1m", "city10m", "interior", "plant"):
    table2_steps("720", key, first_stage, 40 if not Q else 240)
if has_stage:
    for key in ("city10m", "interior", "plant"):
        table2_steps("1080", key, "fragment", 40 if not Q else 240)

for s in steps:  # every GL command renders on the chosen device
    for c in s["commands"]:
        if c[0] in ("bench", "render", "verify") and "--gl-device" not in c:
            c.extend(device_args)

if args.only:
    prefixes = [p for p in args.only.split(",") if p]
    steps = [s for s in steps if any(s["id"].startswith(p) for p in prefixes)]
    if not steps:
        fail("--only %s matches no step (see --list)" % args.only)
if args.list:
    for s in steps:
        print("%-34s %4ds  %s" % (s["id"], s["seconds"], s["title"]))
    sys.exit(0)

# --- running ----------------------------------------------------------------------------------------------------
try:
    for sub in ("", "data", "logs", "cache", "images"):
        os.makedirs(os.path.join(out, sub), exist_ok=True)
except OSError as e:
    fail("cannot create %s: %s" % (out, e.strerror))
records = []
run_started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")

def display(command):
    return " ".join(shlex.quote(a) for a in chcrt + command)

def run_command(command, limit, log_path):
    t0 = time.monotonic()
    with open(log_path, "ab") as log:
        log.write(("$ " + display(command) + "\n").encode())
        log.flush()
        try:
            p = subprocess.Popen(chcrt + command, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                 start_new_session=True, cwd=out)
        except OSError as e:
            log.write(("gpu_check: cannot start: %s\n" % e).encode())
            return dict(argv=display(command), rc=None, wall_s=0.0, status="failed to start")
        try:
            rc = p.wait(timeout=max(limit, 0.1))
            status = "ok" if rc == 0 else ("differences (exit 4)" if rc == 4 else "failed (exit %d)" % rc)
        except subprocess.TimeoutExpired:
            try:
                os.killpg(p.pid, signal.SIGTERM)
                try:
                    p.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()
            except ProcessLookupError:
                pass
            rc = None
            status = "stopped: its step's time ran out (after %.0f s)" % limit
            log.write(("gpu_check: %s\n" % status).encode())
    return dict(argv=display(command), rc=rc, wall_s=round(time.monotonic() - t0, 2), status=status)

def tail(path, offset, lines=12):
    """The last lines a command wrote to its step's log, from `offset` (the log's size before the command) on."""
    try:
        with open(path, "rb") as f:
            f.seek(offset)
            return f.read().decode(errors="replace").splitlines()[1:][-lines:]  # [1:]: the "$ command" line
    except OSError:
        return []

def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None

def json_outputs(command):
    return [command[i + 1] for i, a in enumerate(command[:-1]) if a in ("--json", "--stats-json")]

# --- reporting --------------------------------------------------------------------------------------------------
def fmt(x, digits=1):
    if x is None:
        return "-"
    if isinstance(x, float):
        return ("%%.%df" % digits) % x
    return str(x)

def gl_info():
    j = load_json(data("info.json")) or {}
    return j.get("gl", {})

def driver_info():
    lines = []
    try:
        with open("/proc/driver/nvidia/version") as f:
            lines.append(f.readline().strip())
    except OSError:
        pass
    return lines

def machine_info():
    cpu = ""
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "")
    except OSError:
        pass
    mem = ""
    try:
        with open("/proc/meminfo") as f:
            kb = int(next(l for l in f if l.startswith("MemTotal")).split()[1])
            mem = "%.0f GiB" % (kb / 1048576)
    except (OSError, StopIteration, ValueError):
        pass
    return dict(host=platform.node(), cpu=cpu, cores=os.cpu_count(), memory=mem, kernel=platform.release())

def bundle_manifest():
    path = os.path.join(here, "MANIFEST.txt")
    try:
        with open(path) as f:
            return f.readline().strip()
    except OSError:
        return ""

def table2_rows():
    rows = []
    for r in records:
        if r["kind"] != "table2":
            continue
        for c in r["commands"]:
            for path in json_outputs(c["argv_list"]):
                j = load_json(path)
                if not j:
                    continue
                by = {}
                for row in j.get("rows", []):
                    by.setdefault(row["ray_type"], {})[row["method"]] = row
                for ray_type, methods in by.items():
                    b = methods.get("bvh", {})
                    rows.append(dict(scene=r["scene"], res=r["res"], stage=r["stage"], path=r["path"],
                                     size="%sx%s" % (b.get("width"), b.get("height")), ray_type=ray_type,
                                     spp=b.get("spp"), frames=b.get("frames"),
                                     bvh_ms=b.get("ms_median"), bvh_mrays=b.get("mrays_per_s"),
                                     methods={m: dict(ms=v.get("ms_median"), speedup=v.get("speedup_vs_bvh"),
                                                      mrays=v.get("mrays_per_s"), diff=v.get("diff_pixels"))
                                              for m, v in methods.items() if m != "bvh"}))
    return rows

def stage_comparison():
    result = []
    for r in records:
        if r["kind"] != "stages":
            continue
        for m in ("bvh", "chcrt"):
            files = [os.path.join(out, "images", "%s-%s.exr" % (m, s)) for s in ("fragment", "compute")]
            digests = []
            for f in files:
                try:
                    with open(f, "rb") as fh:
                        digests.append(hashlib.sha256(fh.read()).hexdigest())
                except OSError:
                    digests.append(None)
            same = None if None in digests else digests[0] == digests[1]
            result.append(dict(method=m, fragment=files[0], compute=files[1], identical=same))
    return result

def write_reports(final):
    gl = gl_info()
    t2 = table2_rows()
    stages = stage_comparison()
    elapsed = time.monotonic() - start
    software = any(k in (gl.get("renderer", "") or "").lower() for k in ("llvmpipe", "softpipe", "swrast", "software"))
    result = dict(
        started_utc=run_started, elapsed_s=round(elapsed, 1), budget_s=budget, finished=final, quick=Q,
        chcrt=" ".join(chcrt), bundle=bundle_manifest(), gl=gl, software_renderer=software, driver=driver_info(),
        machine=machine_info(), supports=dict(shader_stage=has_stage, info_devices=has_devices,
                                              gl_device_auto=has_device_auto),
        notes=notes, steps=[dict({k: v for k, v in r.items() if k != "commands"},
                                 commands=[{k: v for k, v in c.items() if k != "argv_list"} for c in r["commands"]])
                            for r in records],
        table2=t2, stage_comparison=stages,
        linespace=(load_json(data("linespace.json")) or {}).get("rows"),
        outofcore=[row for path in ("near", "far") for row in (load_json(data("outofcore-%s.json" % path)) or {}).get("rows", [])])
    tmp = os.path.join(out, "results.json.tmp")
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    os.replace(tmp, os.path.join(out, "results.json"))

    md = ["# chcrt GPU check: results", ""]
    if software:
        md += ["**The GL renderer is a software renderer (%s): these are not GPU numbers.**" % gl.get("renderer"), ""]
    if Q:
        md += ["**--quick: tiny scenes and images, a test of the script; the numbers mean nothing.**", ""]
    md += ["## CHC+RT Table 2", "",
           "ms per frame (all samples of a frame), median over timed runs; × = speedup over pure BVH (bvh) on the "
           "same rays; diff = pixels whose hits differ from pure BVH (must be 0: both CHC+RT methods are exact).", ""]
    if t2:
        md.append("| scene | size | shaders | path | ray type | spp | frames | bvh ms | bvh Mrays/s | chcrt ms | chcrt × | "
                  "noadapt ms | noadapt × | diff chcrt/noadapt |")
        md.append("| --- | --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
        for row in t2:
            c = row["methods"].get("chcrt", {})
            n = row["methods"].get("chcrt-noadapt", {})
            md.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s/%s |" % (
                row["scene"], row["size"], row["stage"], row["path"], row["ray_type"], fmt(row["spp"]),
                fmt(row["frames"]), fmt(row["bvh_ms"], 2), fmt(row["bvh_mrays"], 1), fmt(c.get("ms"), 2),
                fmt(c.get("speedup"), 2), fmt(n.get("ms"), 2), fmt(n.get("speedup"), 2), fmt(c.get("diff")),
                fmt(n.get("diff"))))
    else:
        md.append("(no Table 2 bench finished)")
    md.append("")
    if stages:
        md += ["## Compute against fragment shaders", "",
               "The same frame (city, 2 spp, all effects) rendered with each shader stage, EXR files compared byte "
               "for byte.", "", "| method | identical |", "| --- | --- |"]
        md += ["| %s | %s |" % (s["method"], {True: "yes", False: "NO", None: "-"}[s["identical"]]) for s in stages]
        md.append("")
    ls = result["linespace"]
    if ls:
        md += ["## Line Space indirect", "", "| scene | method | ms | × | indirect PSNR dB | final PSNR dB |",
               "| --- | --- | ---: | ---: | ---: | ---: |"]
        for row in ls:
            e = row.get("image_error") or {}
            md.append("| %s | %s | %s | %s | %s | %s |" % (row.get("scene"), row.get("method"),
                      fmt(row.get("ms_median"), 2), fmt(row.get("speedup_vs_bvh"), 2),
                      fmt(e.get("indirect_psnr_db"), 1), fmt(e.get("final_psnr_db"), 1)))
        md.append("")
    ooc = result["outofcore"]
    if ooc:
        md += ["## Out of core", "", "Cache counters and MB uploaded are means per traced frame over the timed run "
               "(bench --json `outofcore`).", "",
               "| path | ray type | method | size | ms | Mrays/s | cache hits | misses | MB uploaded | resident MB |",
               "| --- | --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
        for row in ooc:
            o = row.get("outofcore") or {}
            mb = (o.get("mb_transferred_bvh") or 0) + (o.get("mb_transferred_geometry") or 0) if o else None
            md.append("| %s | %s | %s%s | %sx%s | %s | %s | %s | %s | %s | %s |" % (row.get("path"), row.get("ray_type"),
                      row.get("method"), " (out of core)" if row.get("out_of_core") else "", row.get("width"),
                      row.get("height"), fmt(row.get("ms_median"), 2), fmt(row.get("mrays_per_s"), 1),
                      fmt(o.get("cache_hits")), fmt(o.get("cache_misses")), fmt(mb, 1), fmt(o.get("resident_mb"), 1)))
        md.append("")
    verify = [r for r in records if r["kind"] == "verify"]
    if verify:
        md += ["## verify", ""]
        for r in verify:
            for c in r["commands"]:
                md.append("- `%s`: %s" % (c["argv"], c["status"]))
                md += ["  - " + l.strip() for l in c.get("output_tail", []) if l.strip().startswith(("PASS", "FAIL", "primary", "shadow", "ao", "diffuse", "verify"))]
        md.append("")
    tmp = os.path.join(out, "results.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(tmp, os.path.join(out, "results.md"))

    s = ["# chcrt GPU check: summary", ""]
    s.append("- started %s, %.0f s of a %.0f s budget%s" % (run_started, elapsed, budget, "" if final else " (still running)"))
    s.append("- GL vendor: %s" % gl.get("vendor", "?"))
    s.append("- GL renderer: %s%s" % (gl.get("renderer", "?"), " (**software renderer**)" if software else ""))
    s.append("- GL version (driver): %s" % gl.get("version", "?"))
    s.append("- GL context: %s" % gl.get("context", "?"))
    for d in driver_info():
        s.append("- kernel driver: %s" % d)
    m = machine_info()
    s.append("- machine: %s, %s, %s cores, %s memory, Linux %s" % (m["host"], m["cpu"], m["cores"], m["memory"], m["kernel"]))
    if bundle_manifest():
        s.append("- bundle: %s" % bundle_manifest())
    s.append("- chcrt: `%s`%s" % (" ".join(chcrt), " (--quick)" if Q else ""))
    for n in notes:
        s.append("- note: %s" % n)
    s += ["", "Results: [results.md](results.md), [results.json](results.json); each command's JSON in data/, its "
          "output in logs/.", "", "## Steps and commands", "",
          "| step | status | s | commands |", "| --- | --- | ---: | --- |"]
    for r in records:
        s.append("| %s | %s | %.1f | %d |" % (r["id"], r["status"], r["wall_s"], len(r["commands"])))
    s.append("")
    for r in records:
        s.append("### %s: %s" % (r["id"], r["title"]))
        s.append("")
        s.append("%s, %.1f s (limit %.0f s)" % (r["status"], r["wall_s"], r["limit_s"]))
        s.append("")
        for c in r["commands"]:
            s.append("- `%s`  \n  %s, %.1f s" % (c["argv"], c["status"], c["wall_s"]))
        s.append("")
    tmp = os.path.join(out, "summary.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(s) + "\n")
    os.replace(tmp, os.path.join(out, "summary.md"))

def finish(signum=None, frame=None):
    write_reports(True)
    print("gpu_check: interrupted; partial results in %s" % out, file=sys.stderr)
    sys.exit(130)
signal.signal(signal.SIGTERM, finish)
signal.signal(signal.SIGINT, finish)

print("gpu_check: %d steps, budget %.0f s, %s, results in %s" % (len(steps), budget, " ".join(chcrt), out), flush=True)
for n in notes:
    print("gpu_check: note: " + n, flush=True)
for s in steps:
    remaining = deadline - time.monotonic() - RESERVE_S
    record = dict(id=s["id"], title=s["title"], kind=s["kind"], limit_s=0.0, wall_s=0.0, commands=[],
                  **{k: s[k] for k in ("scene", "res", "path", "stage") if k in s})
    records.append(record)
    min_useful = min(15.0, s["seconds"])
    if remaining < min_useful:
        record["status"] = "skipped: out of time (%.0f s left)" % max(remaining, 0)
        print("gpu_check: %-34s %s" % (s["id"], record["status"]), flush=True)
        continue
    limit = min(float(s["seconds"]), remaining)
    record["limit_s"] = limit
    step_end = time.monotonic() + limit
    t0 = time.monotonic()
    log_path = os.path.join(out, "logs", s["id"] + ".log")
    statuses = []
    for command in s["commands"]:
        left = step_end - time.monotonic()
        if left < 1.0:
            c = dict(argv=display(command), rc=None, wall_s=0.0, status="skipped: the step's time is used up")
        elif s["chain"] and statuses and statuses[-1] != "ok":
            c = dict(argv=display(command), rc=None, wall_s=0.0, status="skipped: the previous command failed")
        else:
            offset = os.path.getsize(log_path) if os.path.exists(log_path) else 0
            c = run_command(command, left, log_path)
            c["output_tail"] = tail(log_path, offset)
        c["argv_list"] = command
        record["commands"].append(c)
        statuses.append(c["status"])
    record["wall_s"] = round(time.monotonic() - t0, 2)
    record["status"] = "ok" if all(x == "ok" for x in statuses) else "; ".join(sorted(set(x for x in statuses if x != "ok")))
    print("gpu_check: %-34s %-10s %6.1f s  (%.0f s left)" % (s["id"], record["status"], record["wall_s"],
          deadline - time.monotonic()), flush=True)
    write_reports(False)

write_reports(True)
print("gpu_check: done in %.0f s; %s" % (time.monotonic() - start, os.path.join(out, "summary.md")), flush=True)
PYTHON
exec "$python" -c "$program" "$here" "$@"
