#!/usr/bin/env python3
"""pvrt against POV-Ray 3.7 on the same scenes, and pvrt's parallel scaling (run through bench/run.sh).

Every comparison renders the same scene at the same resolution with the same sample pattern and the
same thread count: POV-Ray with `+A0.0 +AM1 +Rn -J` (or `-A` for n = 1), pvrt with `--sampler pov
--spp n*n`. The two programs alternate run by run (pvrt first in even runs, POV-Ray first in odd ones) so
that a slow phase of the machine hits both alike. Results go to OUT/results.csv (one row per run),
OUT/summary.csv, OUT/results.md and OUT/*.png; the logs of every run to OUT/logs/.

Only the standard library is needed; the plots need matplotlib and are skipped without it.
"""
import argparse
import csv
import datetime
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import pvrt_stats

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

RAW_FIELDS = [
    "experiment", "scene", "objects", "renderer", "run", "threads", "width", "height", "spp", "status",
    "wall_s", "render_s", "load_s", "build_s", "write_s", "bvh_build_s", "bvh_kib", "bvh_nodes", "peak_rss_kib",
    "primary_rays", "shadow_rays", "reflected_rays", "refracted_rays", "transmitted_rays", "total_rays",
    "intersection_tests", "rays_per_s",
]


# ---------------------------------------------------------------- options

def parse_args(argv):
    ap = argparse.ArgumentParser(prog="bench/run.sh", description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="tiny sizes and few runs (a smoke test, well under 2 minutes; timings meaningless)")
    ap.add_argument("--runs", type=int, help="measured runs of each program per scene (default 5; quick 2)")
    ap.add_argument("--warmup", type=int, help="unrecorded runs before them (default 1; quick 0)")
    ap.add_argument("--out", help="output folder (default bench/results/<date-time>/)")
    ap.add_argument("--pvrt", default=os.path.join(ROOT, "build", "pvrt"), help="pvrt binary (default build/pvrt)")
    ap.add_argument("--povray", default="povray", help="POV-Ray 3.7 binary (default povray)")
    ap.add_argument("--threads", type=int, help="threads for the comparison (default: nproc)")
    ap.add_argument("--width", type=int, help="image width (default 640; quick 160)")
    ap.add_argument("--height", type=int, help="image height (default 400; quick 100)")
    ap.add_argument("--aa", type=int, help="antialiasing depth n: +Rn / --spp n*n; 1 is -A (default 3; quick 2)")
    ap.add_argument("--max-objects", type=int, help="largest random scene, in spheres (default 1e6; quick 1e3)")
    ap.add_argument("--povray-max-objects", type=int,
                    help="largest random scene POV-Ray renders; larger ones are marked not run (default 1e4; quick 1e3)")
    ap.add_argument("--only", default="compare,scaling,speedup",
                    help="experiments to run, comma-separated: compare (fixed scenes), scaling (random scenes of "
                         "10^2..10^6 spheres), speedup (bench/speedup.py: OpenMP schedules, MPI strategies and "
                         "gathers, hybrid splits, up to --threads)")
    ap.add_argument("--mpirun", default="mpirun", help="mpirun for the speedup experiment ('' leaves MPI out)")
    a = ap.parse_args(argv)
    quick = a.quick
    a.runs = a.runs if a.runs is not None else (2 if quick else 5)
    a.warmup = a.warmup if a.warmup is not None else (0 if quick else 1)
    a.threads = a.threads or len(os.sched_getaffinity(0))
    a.width = a.width or (160 if quick else 640)
    a.height = a.height or (100 if quick else 400)
    a.aa = a.aa or (2 if quick else 3)
    a.max_objects = a.max_objects or (10 ** 3 if quick else 10 ** 6)
    a.povray_max_objects = a.povray_max_objects if a.povray_max_objects is not None else (
        10 ** 3 if quick else 10 ** 4)
    a.only = set(a.only.split(","))
    if os.sep in a.pvrt:  # the runs start in a work folder: a relative path must not depend on it
        a.pvrt = os.path.abspath(a.pvrt)
    unknown = a.only - {"compare", "scaling", "speedup"}
    if unknown or a.runs < 1 or a.warmup < 0 or a.aa < 1 or a.threads < 1:
        ap.error("bad value: " + (", ".join(sorted(unknown)) if unknown else "runs/warmup/aa/threads"))
    if not a.out:
        a.out = os.path.join(ROOT, "bench", "results", datetime.datetime.now().strftime("%Y-%m-%d-%H%M%S"))
    return a


# ---------------------------------------------------------------- running and parsing

def run_measured(cmd, cwd, log):
    """Runs cmd; returns (wall seconds, peak RSS in KiB, exit code). stdout and stderr go to log.*"""
    with open(log + ".out", "w") as out, open(log + ".err", "w") as err:
        start = time.perf_counter()
        try:
            p = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=err)
        except OSError as e:
            err.write(str(e))
            return time.perf_counter() - start, 0, 127
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - start
        p.returncode = os.waitstatus_to_exitcode(status)
    return wall, usage.ru_maxrss, p.returncode  # ru_maxrss is in KiB on Linux


def read(path):
    with open(path, errors="replace") as f:
        return f.read()


def parse_povray(text):
    """The figures of POV-Ray 3.7's statistics (stderr). Its "Rays" are the traced (non-shadow) rays."""
    r = {}
    seconds = lambda name: re.search(name + r":.*?\(([\d.]+) seconds\)", text)
    m = seconds("Trace Time")
    if m:
        r["render_s"] = float(m[1])
    m, b = seconds("Parse Time"), seconds("Bounding Time")
    if m:
        r["load_s"] = float(m[1])
    if b:
        r["build_s"] = r["bvh_build_s"] = float(b[1])
    counts = {"rays": r"Rays:\s+(\d+)", "shadow_rays": r"Shadow Ray Tests:\s+(\d+)",
              "reflected_rays": r"Reflected Rays:\s+(\d+)", "refracted_rays": r"Refracted Rays:\s+(\d+)"}
    for key, pattern in counts.items():
        m = re.search(pattern, text)
        if m:
            r[key] = int(m[1])
        elif "Render Statistics" in text:
            r[key] = 0  # POV-Ray leaves out the counters that stayed at zero
    if "rays" in r:
        r["primary_rays"] = r["rays"] - r.get("reflected_rays", 0) - r.get("refracted_rays", 0)
        r["total_rays"] = r.pop("rays") + r.get("shadow_rays", 0)
        if r.get("render_s"):
            r["rays_per_s"] = r["total_rays"] / r["render_s"]
    return r


# ---------------------------------------------------------------- scenes

def scene_objects(path):
    return sum(1 for line in open(path, errors="replace") if re.search(r"<(sphere|plane|box|cylinder|cone|disc|"
                                                                        r"triangle|smooth_triangle|mesh)\b", line))


def without_reflection(src, dst):
    """paper1 with every reflection removed (attribute and element); everything else as it was."""
    tree = ET.parse(src)
    for finish in tree.iter("finish"):
        finish.attrib.pop("reflection", None)
        for child in list(finish):
            if child.tag == "reflection":
                finish.remove(child)
    tree.write(dst, xml_declaration=True, encoding="unicode")


class Scenes:
    """Scene files in a private work folder, with their POV-Ray exports."""

    def __init__(self, args, work):
        self.args, self.work = args, work

    def generate(self, name, *options):
        path = os.path.join(self.work, name + ".xml")
        subprocess.run([self.args.pvrt, "generate", "-o", path, *options], check=True)
        return path

    def spheres(self, n):
        # The spheres keep to the same box as n grows, pvrt generate's default radii shrinking as
        # n^(-1/3) so that their total volume stays the same (bench/object_scaling.sh).
        return self.generate("spheres_%d" % n, "--spheres", str(n), "--lights", "5", "--seed", "1")

    def fixed(self):
        noref = os.path.join(self.work, "paper1_noreflection.xml")
        without_reflection(os.path.join(ROOT, "scenes", "paper1.xml"), noref)
        return [
            ("paper1", os.path.join(ROOT, "scenes", "paper1.xml")),
            ("paper2", os.path.join(ROOT, "scenes", "paper2.xml")),
            ("paper1_noreflection", noref),
            # Glass-heavy: the paper's random scene with every sphere glass (refraction and reflection).
            ("glass100", self.generate("glass100", "--spheres", "100", "--lights", "5", "--seed", "3",
                                       "--palette", "0", "0", "0", "1")),
            # A hand-made room corner: two mirrors, glass and an area light (issue 28).
            ("mirrors_glass", os.path.join(ROOT, "bench", "scenes", "mirrors_glass.xml")),
        ]

    def export(self, name, xml):
        pov = os.path.join(self.work, name + ".pov")
        subprocess.run([self.args.pvrt, "export-pov", xml, "-o", pov], check=True, stderr=subprocess.DEVNULL)
        return pov


# ---------------------------------------------------------------- experiments

class Bench:
    def __init__(self, args, work):
        self.args, self.work = args, work
        self.rows = []
        self.logs = os.path.join(args.out, "logs")
        os.makedirs(self.logs, exist_ok=True)
        self.povray = shutil.which(args.povray)
        self.agreement = {}  # scene -> `pvrt compare` verdict on the two programs' last images

    def pvrt_cmd(self, xml, out_png, threads):
        a = self.args
        return [a.pvrt, "render", xml, "-o", out_png, "-W", str(a.width), "-H", str(a.height), "--sampler", "pov",
                "--spp", str(a.aa * a.aa), "--threads", str(threads), "--schedule", "tiles", "--stats", "--quiet"]

    def povray_cmd(self, pov, out_png, threads):
        a = self.args
        aa = ["-A"] if a.aa == 1 else ["+A0.0", "+AM1", "+R%d" % a.aa, "-J"]
        return [self.povray, "+I" + pov, "+O" + out_png, "+W%d" % a.width, "+H%d" % a.height, "-D", "+FN",
                "+WT%d" % threads, *aa]

    def measure(self, experiment, scene, objects, renderer, run, threads, cmd, record=True):
        tag = "%s.%s.%s.t%d.r%s" % (experiment, scene, renderer, threads, run)
        log = os.path.join(self.logs, tag)
        if renderer == "pvrt":
            cmd = cmd + ["--stats-json", log + ".json"]
        wall, rss, rc = run_measured(cmd, self.work, log)
        row = dict(experiment=experiment, scene=scene, objects=objects, renderer=renderer, run=run,
                   threads=threads, width=self.args.width, height=self.args.height, spp=self.args.aa ** 2,
                   status="ok" if rc == 0 else "failed (exit %d, see logs/%s.err)" % (rc, tag),
                   wall_s=wall, peak_rss_kib=rss)
        if rc == 0:
            if renderer == "pvrt":
                row.update({k: v for k, v in pvrt_stats.figures(pvrt_stats.read(log + ".json")).items() if k in RAW_FIELDS})
            else:
                row.update(parse_povray(read(log + ".err")))
        if record:
            self.rows.append(row)
        print("  %-9s %-22s %-6s run %-6s %2d threads  wall %7.3f s  render %s  %s" % (
            experiment, scene, renderer, run, threads, wall,
            "%7.3f s" % row["render_s"] if "render_s" in row else "    n/a", row["status"]), flush=True)
        return row

    def not_run(self, experiment, scene, objects, renderer, threads, why):
        self.rows.append(dict(experiment=experiment, scene=scene, objects=objects, renderer=renderer, run="-",
                              threads=threads, width=self.args.width, height=self.args.height,
                              spp=self.args.aa ** 2, status="not run (%s)" % why))

    def compare_pair(self, experiment, scene, xml, pov_limit_ok):
        """pvrt and POV-Ray alternately on one scene, then whether their images agree."""
        a = self.args
        objects = scene_objects(xml)
        pov = self.export_for_povray(scene, xml) if (self.povray and pov_limit_ok) else None
        pv_png, po_png = os.path.join(self.work, scene + ".pvrt.png"), os.path.join(self.work, scene + ".pov.png")
        jobs = {"pvrt": self.pvrt_cmd(xml, pv_png, a.threads)}
        if pov:
            jobs["povray"] = self.povray_cmd(pov, po_png, a.threads)
        else:
            why = ("povray not found" if not self.povray else
                   "over --povray-max-objects %d" % a.povray_max_objects if not pov_limit_ok else "export failed")
            self.not_run(experiment, scene, objects, "povray", a.threads, why)
        order = list(jobs)
        for r in range(a.warmup + a.runs):
            measured = r >= a.warmup
            for renderer in (order if r % 2 == 0 else order[::-1]):
                self.measure(experiment, scene, objects, renderer, r - a.warmup if measured else "warmup%d" % r,
                             a.threads, jobs[renderer], record=measured)
        if pov and os.path.exists(pv_png) and os.path.exists(po_png):
            out = subprocess.run([a.pvrt, "compare", pv_png, po_png], capture_output=True, text=True).stdout
            m = re.search(r"Max error = (\d+) levels", out)
            over = re.search(r"(\d+) by more than 1 level \(([\d.]+)%\)", out)
            self.agreement[scene] = "max %s levels, %s%% over 1" % (m[1], over[2]) if m and over else "?"

    def export_for_povray(self, scene, xml):
        try:
            return Scenes(self.args, self.work).export(scene, xml)
        except subprocess.CalledProcessError:
            return None


# ---------------------------------------------------------------- summaries

def ok_rows(rows, **match):
    return [r for r in rows if r["status"] == "ok" and all(r.get(k) == v for k, v in match.items())]


def spread(values):
    values = [v for v in values if v is not None]
    if not values:
        return None
    return statistics.median(values), min(values), max(values)


def summarise(rows):
    """One row per (experiment, scene, renderer, threads) with medians and min-max spreads."""
    keys = []
    for r in rows:
        k = (r["experiment"], r["scene"], r["renderer"], r["threads"])
        if k not in keys:
            keys.append(k)
    out = []
    for exp, scene, renderer, threads in keys:
        group = [r for r in rows if (r["experiment"], r["scene"], r["renderer"], r["threads"]) ==
                 (exp, scene, renderer, threads)]
        good = [r for r in group if r["status"] == "ok"]
        s = dict(experiment=exp, scene=scene, renderer=renderer, threads=threads, objects=group[0]["objects"],
                 runs=len(good), status="ok" if good else group[0]["status"])
        for field in ("wall_s", "render_s", "load_s", "build_s", "bvh_build_s", "peak_rss_kib", "rays_per_s"):
            sp = spread([r.get(field) for r in good])
            if sp:
                s[field + "_median"], s[field + "_min"], s[field + "_max"] = sp
        for field in ("bvh_kib", "bvh_nodes", "primary_rays", "shadow_rays", "reflected_rays", "refracted_rays",
                      "transmitted_rays", "total_rays", "intersection_tests"):
            if good and good[0].get(field) is not None:
                s[field] = good[0][field]
        out.append(s)
    # POV-Ray time / pvrt time, from the medians and from each alternating pair.
    for s in out:
        if s["renderer"] != "pvrt":
            continue
        pov = next((p for p in out if p["renderer"] == "povray" and p["experiment"] == s["experiment"]
                    and p["scene"] == s["scene"] and p["threads"] == s["threads"] and p["runs"]), None)
        if not pov or not s["runs"]:
            continue
        for field in ("wall_s", "render_s"):
            if field + "_median" in s and field + "_median" in pov:
                s["ratio_" + field] = pov[field + "_median"] / s[field + "_median"]
                pairs = [(a.get(field), b.get(field))
                         for a in ok_rows(rows, experiment=s["experiment"], scene=s["scene"], renderer="pvrt")
                         for b in ok_rows(rows, experiment=s["experiment"], scene=s["scene"], renderer="povray")
                         if a["run"] == b["run"]]
                ratios = [b / a for a, b in pairs if a and b]
                if ratios:
                    s["ratio_%s_min" % field], s["ratio_%s_max" % field] = min(ratios), max(ratios)
    return out


def write_csv(path, rows, fields=None):
    if fields is None:
        fields = []
        for r in rows:
            fields += [k for k in r if k not in fields]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.6g" % v if isinstance(v, float) else v) for k, v in r.items()})


def fmt_spread(s, field, unit="s", scale=1.0, digits=3):
    if field + "_median" not in s:
        return s["status"] if s["status"] != "ok" else "n/a"
    med, lo, hi = (s[field + k] * scale for k in ("_median", "_min", "_max"))
    return "%.*f %s [%.*f–%.*f]" % (digits, med, unit, digits, lo, digits, hi)


def fmt_ratio(s, field):
    if "ratio_" + field not in s:
        return "–"
    lo, hi = s.get("ratio_%s_min" % field), s.get("ratio_%s_max" % field)
    return "%.2f× [%.2f–%.2f]" % (s["ratio_" + field], lo, hi) if lo else "%.2f×" % s["ratio_" + field]


def num(v, pattern="{:,}"):
    return "–" if v is None else pattern.format(v)


def markdown(args, summary, meta, agreement, plots):
    L = ["# pvrt benchmark, " + meta["date"], ""]
    L += ["| | |", "|---|---|"]
    L += ["| %s | %s |" % (k, v) for k, v in meta.items() if k != "date"]
    L += ["", "Wall: the whole process (start to exit: load, BVH/bounding, render, write). Render: pvrt's "
          "`render` stage from `--stats`, POV-Ray's *Trace Time*. Each cell: median [min–max] over %d runs; the "
          "two programs alternate run by run. Ratio: POV-Ray time / pvrt time (above 1: pvrt is faster), from "
          "the medians, [min–max] over the alternating pairs." % args.runs, ""]
    for exp, title in (("compare", "Scenes"), ("scaling", "Random scenes: time against the number of objects")):
        rows = [s for s in summary if s["experiment"] == exp and s["renderer"] == "pvrt"]
        if not rows:
            continue
        L += ["## " + title, "",
              "| scene | objects | pvrt wall | POV-Ray wall | wall ratio | pvrt render | POV-Ray render | "
              "render ratio | images agree |",
              "|---|--:|--:|--:|--:|--:|--:|--:|---|"]
        for s in rows:
            pov = next((p for p in summary if p["experiment"] == exp and p["scene"] == s["scene"]
                        and p["renderer"] == "povray"), None)
            L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                s["scene"], num(s["objects"]), fmt_spread(s, "wall_s"), fmt_spread(pov, "wall_s") if pov else "–",
                fmt_ratio(s, "wall_s"), fmt_spread(s, "render_s"), fmt_spread(pov, "render_s") if pov else "–",
                fmt_ratio(s, "render_s"), agreement.get(s["scene"], "–")))
        L.append("")
    pv = [s for s in summary if s["experiment"] in ("compare", "scaling") and s["renderer"] == "pvrt" and s["runs"]]
    if pv:
        L += ["## pvrt: rays by kind, memory, BVH", "",
              "Rays per second: all rays (camera, shadow, reflected, refracted, transmitted) over the median "
              "render time. Peak RSS: the process's maximum resident set (getrusage).", "",
              "| scene | primary | shadow | reflected | refracted | transmitted | total | Mrays/s | tests/ray | "
              "peak RSS MiB | load s | BVH nodes | BVH KiB | BVH build s |",
              "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"]
        for s in pv:
            mrays = s["total_rays"] / s["render_s_median"] / 1e6 if s.get("total_rays") and s.get(
                "render_s_median") else None
            tpr = s["intersection_tests"] / s["total_rays"] if s.get("total_rays") else None
            L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                s["scene"], num(s.get("primary_rays")), num(s.get("shadow_rays")), num(s.get("reflected_rays")),
                num(s.get("refracted_rays")), num(s.get("transmitted_rays")), num(s.get("total_rays")),
                num(mrays, "{:.2f}"), num(tpr, "{:.2f}"), num(s.get("peak_rss_kib_median", 0) / 1024, "{:.1f}"),
                num(s.get("load_s_median"), "{:.4f}"), num(s.get("bvh_nodes")), num(s.get("bvh_kib"), "{:,.1f}"),
                num(s.get("bvh_build_s_median"), "{:.4f}")))
        L.append("")
    po = [s for s in summary if s["experiment"] in ("compare", "scaling") and s["renderer"] == "povray" and s["runs"]]
    if po:
        L += ["## POV-Ray: rays, memory, parse and bounding", "",
              "As POV-Ray counts them: traced rays (camera, reflected, refracted) and shadow ray tests.", "",
              "| scene | traced rays | shadow tests | reflected | refracted | Mrays/s | peak RSS MiB | parse s | "
              "bounding s |", "|---|--:|--:|--:|--:|--:|--:|--:|--:|"]
        for s in po:
            traced = s["total_rays"] - s.get("shadow_rays", 0) if s.get("total_rays") else None
            mrays = s["total_rays"] / s["render_s_median"] / 1e6 if s.get("total_rays") and s.get(
                "render_s_median") else None
            L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                s["scene"], num(traced), num(s.get("shadow_rays")), num(s.get("reflected_rays")),
                num(s.get("refracted_rays")), num(mrays, "{:.2f}"),
                num(s.get("peak_rss_kib_median", 0) / 1024, "{:.1f}"), num(s.get("load_s_median"), "{:.4f}"),
                num(s.get("bvh_build_s_median"), "{:.4f}")))
        L.append("")
    if plots:
        L += ["## Plots", ""] + ["![%s](%s)" % (p, p) for p in plots] + [""]
    return "\n".join(L)


# ---------------------------------------------------------------- plots

def plot(out, summary):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("bench: matplotlib not found, no plots (tools/install-deps.sh installs python3-matplotlib)")
        return []
    made = []
    colours = {"pvrt": "tab:blue", "povray": "tab:orange"}

    def errorbars(ax, rows, field, label, colour, style):
        rows = [r for r in rows if field + "_median" in r]
        if not rows:
            return
        x = [r["objects"] for r in rows]
        y = [r[field + "_median"] for r in rows]
        err = [[m - r[field + "_min"] for m, r in zip(y, rows)], [r[field + "_max"] - m for m, r in zip(y, rows)]]
        ax.errorbar(x, y, yerr=err, fmt=style, color=colour, label=label, capsize=3)

    scaling = [s for s in summary if s["experiment"] == "scaling"]
    if scaling:
        fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
        for renderer in ("pvrt", "povray"):
            rows = [s for s in scaling if s["renderer"] == renderer]
            errorbars(ax, rows, "render_s", renderer + " render", colours[renderer], "o-")
            errorbars(ax, rows, "wall_s", renderer + " wall", colours[renderer], "s--")
            rss = [r for r in rows if "peak_rss_kib_median" in r]
            if rss:
                ax2.plot([r["objects"] for r in rss], [r["peak_rss_kib_median"] / 1024 for r in rss], "o-",
                         color=colours[renderer], label=renderer + " peak RSS")
        bvh = [s for s in scaling if s["renderer"] == "pvrt" and s.get("bvh_kib")]
        if bvh:
            ax2.plot([r["objects"] for r in bvh], [r["bvh_kib"] / 1024 for r in bvh], "^:", color="tab:green",
                     label="pvrt BVH")
        for a, ylabel, title in ((ax, "seconds", "time against objects"), (ax2, "MiB", "memory against objects")):
            a.set_xscale("log")
            a.set_yscale("log")
            a.set_xlabel("spheres")
            a.set_ylabel(ylabel)
            a.set_title(title)
            a.grid(True, which="both", alpha=0.3)
            a.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "time_vs_objects.png"), dpi=110)
        plt.close(fig)
        made.append("time_vs_objects.png")

    ratio = [s for s in summary if s["renderer"] == "pvrt" and "ratio_wall_s" in s]
    if ratio:
        fig, ax = plt.subplots(figsize=(max(6, 0.9 * len(ratio) + 2), 4.5))
        xs = range(len(ratio))
        for off, field, label in ((-0.2, "wall_s", "wall"), (0.2, "render_s", "render")):
            vals = [s.get("ratio_" + field, 0) for s in ratio]
            lo = [v - s.get("ratio_%s_min" % field, v) for v, s in zip(vals, ratio)]
            hi = [s.get("ratio_%s_max" % field, v) - v for v, s in zip(vals, ratio)]
            ax.bar([x + off for x in xs], vals, width=0.4, yerr=[lo, hi], capsize=3, label=label)
        ax.axhline(1, color="black", linewidth=0.8)
        ax.set_xticks(list(xs))
        ax.set_xticklabels([s["scene"] for s in ratio], rotation=30, ha="right")
        ax.set_ylabel("POV-Ray time / pvrt time")
        ax.set_title("pvrt against POV-Ray (above 1: pvrt faster)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(out, "ratio.png"), dpi=110)
        plt.close(fig)
        made.append("ratio.png")
    return made


# ---------------------------------------------------------------- main

def metadata(args, povray):
    def cmd(*c):
        try:
            return subprocess.run(c, capture_output=True, text=True, timeout=30).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return ""
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
               platform.processor())
    pov = ""
    if povray:
        out = subprocess.run([povray, "--version"], capture_output=True, text=True)
        pov = next((line for line in (out.stdout + out.stderr).splitlines() if line.startswith("POV-Ray")), "")
    commit = cmd("git", "-C", ROOT, "rev-parse", "--short", "HEAD")
    if cmd("git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"):
        commit += " (with uncommitted changes)"
    return {
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "machine": "%s, %d cores usable, %s" % (cpu, len(os.sched_getaffinity(0)), platform.platform()),
        "load average at start": " ".join("%.2f" % v for v in os.getloadavg()),
        "pvrt": "%s, commit %s" % (args.pvrt, commit),
        "POV-Ray": pov or "not found",
        "settings": "%d x %d, +A0.0 +AM1 +R%d -J = `--sampler pov --spp %d`, %d threads, %d runs (+%d warm-up)%s" % (
            args.width, args.height, args.aa, args.aa ** 2, args.threads, args.runs, args.warmup,
            ", --quick" if args.quick else ""),
        "command": " ".join(["bench/run.sh"] + sys.argv[1:]),
    }


def main(argv):
    args = parse_args(argv)
    if not os.access(args.pvrt, os.X_OK):
        sys.exit("bench: %s is not built (cmake --build build --target pvrt)" % args.pvrt)
    os.makedirs(args.out, exist_ok=True)
    # POV-Ray may only write below /tmp or its working folder (Debian's povray.conf).
    work = tempfile.mkdtemp(prefix="pvrt-bench-", dir="/tmp")
    try:
        bench = Bench(args, work)
        meta = metadata(args, bench.povray)
        print("bench: %s -> %s" % (meta["settings"], args.out), flush=True)
        scenes = Scenes(args, work)
        started = time.perf_counter()
        if "compare" in args.only:
            for name, xml in scenes.fixed():
                bench.compare_pair("compare", name, xml, True)
        if "scaling" in args.only:
            n = 100
            while n <= args.max_objects:
                xml = scenes.spheres(n)
                bench.compare_pair("scaling", "spheres_%d" % n, xml, n <= args.povray_max_objects)
                n *= 10
        speedup_md = ""
        if "speedup" in args.only:
            import speedup  # here: speedup.py imports this module's write_csv
            sp_args = ["--out", args.out, "--pvrt", args.pvrt, "--mpirun", args.mpirun, "--max-p", str(args.threads),
                       "--width", str(args.width), "--height", str(args.height), "--spp", str(args.aa ** 2),
                       "--runs", str(args.runs)] + (["--quick"] if args.quick else [])
            if speedup.main(sp_args) != 0:
                print("bench: some speedup runs failed (see %s/logs)" % args.out)
            with open(os.path.join(args.out, "scaling.md")) as f:
                speedup_md = f.read()
        meta["bench time"] = "%.0f s" % (time.perf_counter() - started)
        write_csv(os.path.join(args.out, "results.csv"), bench.rows, RAW_FIELDS)
        summary = summarise(bench.rows)
        write_csv(os.path.join(args.out, "summary.csv"), summary)
        plots = plot(args.out, summary)
        with open(os.path.join(args.out, "results.md"), "w") as f:
            f.write(markdown(args, summary, meta, bench.agreement, plots))
            if speedup_md:
                f.write("\n" + speedup_md)
        print("bench: wrote %s/results.csv, summary.csv, results.md%s" % (
            args.out, "".join(", " + p for p in plots)))
        failed = [r for r in bench.rows if r["status"].startswith("failed")]
        if failed:
            print("bench: %d runs failed (see the logs)" % len(failed))
            return 1
        return 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
