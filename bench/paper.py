#!/usr/bin/env python3
"""The paper's experiments (Kadir & Khan, "Parallel Ray Tracing using MPI and OpenMP"), run by pvrt in one command:
figs. 4-13 and table 1, the performance model against every timed run, a load-balance simulator to 4096 ranks and
the memory model. Writes OUT/report.md, a PNG per figure and a CSV of every run (bench/README.md, "The paper").

    bench/paper.sh [--full | --quick] [--out DIR] [--pvrt build/pvrt] [--max-p N]
"""
import argparse
import os
import re
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

from bench import write_csv  # noqa: E402
from speedup import parse_stats, run  # noqa: E402
import pvrt_stats  # noqa: E402
import paper_analysis  # noqa: E402
import paper_builds  # noqa: E402
import paper_report  # noqa: E402

SCENES = {"scene1": os.path.join(ROOT, "scenes", "paper1.xml"), "scene2": os.path.join(ROOT, "scenes", "paper2.xml")}
RUN_FIELDS = ["figure", "scene", "backend", "strategy", "chunk", "tile", "gather", "p", "spp", "width", "height",
              "rep", "status", "wall_s", "render_s", "work_total", "work_max", "worker_work", "worker_s",
              "rank_compute_max_s", "rank_comm_max_s", "rank_idle_max_s", "peak_rss_kib", "note"]


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="bench/paper.sh", description=__doc__.split("\n\n")[0])
    ap.add_argument("--full", action="store_true", help="the paper's sizes: 1280x800, c up to 256, every compiler")
    ap.add_argument("--quick", action="store_true", help="tiny sizes, one repetition (the ctest smoke test)")
    ap.add_argument("--out", help="report folder (default bench/results/paper-<date-time>)")
    ap.add_argument("--pvrt", default=os.path.join(ROOT, "build", "pvrt"))
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--max-p", type=int, help="largest P (default: the CPUs this process may use)")
    ap.add_argument("--reps", type=int, help="repetitions of every timed run (default 3; full 5; quick 1)")
    ap.add_argument("--compilers", help="comma-separated table 1 builds, e.g. 'g++ -O2,clang++ -O3' "
                                        "(default clang++ -O3; full all eight; quick none)")
    a = ap.parse_args(argv)
    a.max_p = a.max_p or len(os.sched_getaffinity(0))
    a.mode = "full" if a.full else "quick" if a.quick else "default"
    size = {"full": (1280, 800), "default": (640, 400), "quick": (64, 40)}[a.mode]
    a.width, a.height = size
    a.reps = a.reps or {"full": 5, "default": 3, "quick": 1}[a.mode]
    a.fig10_spp = [1, 8, 256] if a.mode != "quick" else [1, 8, 32]
    a.chunks = {"full": [1, 2, 4, 8, 16, 32, 64], "default": [1, 4, 16, 64], "quick": [1, 8]}[a.mode]
    a.bench_reps = {"full": 200, "default": 50, "quick": 5}[a.mode]
    a.fig11_p = sorted(set(range(2, a.max_p + 1)) | ({4} if a.mode != "quick" else {2}))
    a.mem_sizes = {"full": [(320, 200), (1280, 800), (2560, 1600)], "default": [(320, 200), (640, 400), (1280, 800)],
                   "quick": [(32, 20), (64, 40)]}[a.mode]
    a.mem_objects = {"full": [1000, 10000, 100000], "default": [1000, 10000, 100000], "quick": [100, 1000]}[a.mode]
    a.sim_p = [2 ** k for k in range(13)] if a.mode != "quick" else [1, 2, 4, 8, 64]
    a.sim_tiles = {"full": ((8, 16, 32, 64, 128), (16, 32, 64, 128)), "default": ((8, 16, 32, 64, 128), (32, 64, 128)),
                   "quick": ((8, 32), (32,))}[a.mode]
    a.big = (7680, 4320) if a.mode != "quick" else (256, 160)
    all_builds = ["%s %s" % (c, o) for c in ("g++", "clang++") for o in ("-O0", "-O2", "-O3", "-O3 -march=native")]
    default = {"full": all_builds, "default": ["clang++ -O3"], "quick": []}[a.mode]
    a.compilers = [c.strip() for c in a.compilers.split(",") if c.strip()] if a.compilers is not None else default
    a.out = a.out or os.path.join(ROOT, "bench", "results", "paper-" + time.strftime("%Y%m%d-%H%M%S"))
    a.pvrt = os.path.abspath(a.pvrt)
    return a


class Runner:
    def __init__(self, a):
        self.a = a
        self.rows = []
        self.logs = os.path.join(a.out, "logs")
        os.makedirs(self.logs, exist_ok=True)
        self.count = 0

    def render(self, figure, scene, spp, p, backend="openmp", strategy="cyclic", chunk=0, tile=32,
               gather="recursive-doubling", rep=0, extra=(), out=None, size=None, pvrt=None, env=None, note=""):
        a = self.a
        w, h = size or (a.width, a.height)
        self.count += 1
        tag = "%04d-%s" % (self.count, re.sub(r"[^A-Za-z0-9_.-]+", "_", "%s.%s.%s.%s.P%d.c%d" % (
            figure, scene, backend, strategy, p, spp)))
        image = out or os.path.join(a.out, "logs", tag + ".png")
        cmd = [pvrt or a.pvrt, "render", SCENES.get(scene, scene), "-o", image, "-W", str(w), "-H", str(h),
               "--sampler", "jitter", "--spp", str(spp), "--stats", "--quiet", *extra]
        if backend == "mpi":
            cmd = a.mpirun.split() + ["--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np", str(p)] \
                + cmd + ["--backend", "mpi", "--threads", "1", "--schedule", strategy, "--gather", gather,
                         "--tile-size", str(tile)]
        else:
            cmd += ["--backend", backend, "--threads", str(p), "--schedule", strategy]
            if chunk:
                cmd += ["--chunk", str(chunk)]
            if strategy == "tiles":
                cmd += ["--tile-size", str(tile)]
        log = os.path.join(self.logs, tag)
        wall, rss, rc, text = run(cmd + ["--stats-json", log + ".json"], log, env)
        figures = pvrt_stats.figures(pvrt_stats.read(log + ".json"))
        work, secs = figures.get("worker_work", []), figures.get("worker_seconds", [])
        row = dict(figure=figure, scene=scene, backend=backend, strategy=strategy, chunk=chunk or "",
                   tile=tile if strategy in ("tiles", "dynamic") else "", gather=gather if backend == "mpi" else "",
                   p=p, spp=spp, width=w, height=h, rep=rep, wall_s=wall, peak_rss_kib=rss, note=note,
                   status="ok" if rc == 0 else "failed (exit %d, logs/%s.err)" % (rc, tag))
        st = parse_stats(log + ".json")
        row.update({k: v for k, v in st.items() if k in RUN_FIELDS})
        if work:
            row.update(work_total=sum(work), work_max=max(work), worker_work=" ".join(map(str, work)),
                       worker_s=" ".join("%.4f" % s for s in secs))
        self.rows.append(row)
        print("  %-8s %-7s %-6s %-8s P=%-2d c=%-3d rep %d  render %s  %s" % (
            figure, scene, backend, strategy + (str(chunk) if chunk else ""), p, spp, rep,
            "%.4f s" % row["render_s"] if "render_s" in row else "n/a", row["status"]), flush=True)
        return row

    def rounds(self, confs):
        """Every configuration once a repetition, forward then backward (a slow phase hits all alike)."""
        for rep in range(self.a.reps):
            for conf in (confs if rep % 2 == 0 else confs[::-1]):
                self.render(rep=rep, **conf)


def experiments(a, r):
    ps = list(range(1, a.max_p + 1))
    ctx = {}
    print("figs. 4, 5 and the model's work maps: load maps at c = 8 and 16", flush=True)
    ctx["maps"] = {}
    for scene in SCENES:
        for c in (8, 16):
            prefix = os.path.join(a.out, "maps", "%s_c%d" % (scene, c))
            os.makedirs(os.path.dirname(prefix), exist_ok=True)
            r.render("map", scene, c, a.max_p, strategy="tiles", extra=["--load-map", prefix])
            ctx["maps"][(scene, c)] = prefix + ".exr"
    print("tau_f: serial runs", flush=True)
    r.rounds([dict(figure="serial", scene=s, spp=16, p=1, backend="serial", strategy="block") for s in SCENES])
    print("figs. 6, 9 (and the simulator's check): block and cyclic, MPI and OpenMP; MPI tiles and dynamic",
          flush=True)
    confs = []
    for p in ps:
        for scene in SCENES:
            for backend in ("openmp", "mpi"):
                for strategy in ("block", "cyclic"):
                    confs.append(dict(figure="fig9", scene=scene, spp=16, p=p, backend=backend, strategy=strategy))
        for strategy in ("tiles", "dynamic"):
            confs.append(dict(figure="sim", scene="scene1", spp=16, p=p, backend="mpi", strategy=strategy))
    r.rounds(confs)
    print("the machine's ceiling: one single-thread render alone, then %d at once" % a.max_p, flush=True)
    ctx["ceiling"] = paper_analysis.ceiling(a, r)
    print("figs. 7, 8: 8 ranks (more than cores where marked), block and cyclic, c = 8, each pixel's own work",
          flush=True)
    for scene in SCENES:
        for strategy in ("block", "cyclic"):
            r.render("fig78", scene, 8, 8, backend="mpi", strategy=strategy,
                     extra=["--load-map", os.path.join(a.out, "logs", "fig78-%s-%s" % (scene, strategy))],
                     note="8 ranks on %d cores" % a.max_p if a.max_p < 8 else "")
    print("fig. 10: c = %s" % a.fig10_spp, flush=True)
    ctx["fig10"] = []
    for c in a.fig10_spp:
        png = os.path.join(a.out, "fig10_c%d.png" % c)
        r.render("fig10", "scene1", c, a.max_p, strategy="tiles", out=png)
        ctx["fig10"].append((c, png))
    print("fig. 12: OpenMP static, dynamic, guided, chunks %s" % a.chunks, flush=True)
    r.rounds([dict(figure="fig12", scene=s, spp=8, p=a.max_p, strategy=sched, chunk=ch)
              for s in SCENES for sched in ("static", "dynamic", "guided") for ch in a.chunks])
    print("fig. 13: c = 8 P", flush=True)
    r.rounds([dict(figure="fig13", scene="scene1", spp=8 * p, p=p, backend=b, strategy="cyclic")
              for p in ps for b in ("openmp", "mpi")])
    print("fig. 11: gathers, P = %s" % a.fig11_p, flush=True)
    ctx["bench"] = paper_analysis.gathers(a, r)
    print("memory: peak resident set per rank", flush=True)
    ctx["memory"] = paper_analysis.memory(a, r)
    print("table 1: compilers %s" % (a.compilers or "(none built)"), flush=True)
    ctx["table1"] = paper_builds.table1(a, r)
    return ctx


def main(argv):
    a = parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    started = time.time()
    meta = paper_report.machine(a)
    r = Runner(a)
    ctx = experiments(a, r)
    write_csv(os.path.join(a.out, "runs.csv"), r.rows, RUN_FIELDS)
    results = paper_analysis.analyse(a, r.rows, ctx)
    meta["total time"] = "%.0f s" % (time.time() - started)
    meta["load average at end"] = " ".join("%.2f" % v for v in os.getloadavg())
    paper_report.write(a, meta, r.rows, ctx, results)
    failed = [x for x in r.rows if str(x.get("status", "")).startswith("failed")]
    print("paper: wrote %s/report.md (%d runs, %d failed) in %.0f s" % (a.out, len(r.rows), len(failed),
                                                                       time.time() - started))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
