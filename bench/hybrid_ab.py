#!/usr/bin/env python3
"""Hybrid and MPI renders of two builds against OpenMP alone, in interleaved rounds (docs/parallel.md, run 6).

In each round: OpenMP with N threads (the new build), then hybrid `dynamic` 2 x N/2 and 4 x N/4 and MPI `dynamic`
N x 1 of the new build and of the base build; forward in even rounds, backward in odd ones. Per run: the render
and write stages and the slowest rank's compute, from `--stats-json`, and the whole command's wall time. Prints
medians and the per-round ratios; writes a CSV.

    bench/hybrid_ab.py --new BUNDLE/pvrt.sh --base BUNDLE/pvrt-base.sh --mpirun BUNDLE/mpirun.sh --csv OUT.csv
"""
import argparse
import json
import os
import statistics as st
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main(argv):
    ap = argparse.ArgumentParser(prog="bench/hybrid_ab.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("--new", required=True, help="pvrt of the change")
    ap.add_argument("--base", required=True, help="pvrt to set it against")
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--csv", required=True)
    ap.add_argument("--rounds", type=int, default=14)
    ap.add_argument("--cpus", type=int, default=len(os.sched_getaffinity(0)))
    ap.add_argument("-W", default="1280")
    ap.add_argument("-H", default="800")
    ap.add_argument("--spp", default="16")
    a = ap.parse_args(argv)
    n = a.cpus
    mpirun = a.mpirun.split() + ["--allow-run-as-root", "--oversubscribe", "--bind-to", "none"]

    def command(exe, ranks, threads, json_path):
        render = [exe, "render", os.path.join(ROOT, "scenes", "paper1.xml"), "-o", json_path + ".png", "-W", a.W,
                  "-H", a.H, "--sampler", "pov", "--spp", a.spp, "--threads", str(threads), "--stats-json",
                  json_path, "--quiet"]
        if not ranks:
            return render + ["--schedule", "tiles"]
        return mpirun + ["-np", str(ranks)] + render + ["--backend", "mpi", "--schedule", "dynamic"]

    confs = [("openmp%d" % n, a.new, 0, n)]
    for exe, tag in ((a.new, "new"), (a.base, "base")):
        for ranks in sorted({2, 4, n}):
            if n % ranks == 0:
                confs.append(("%dx%d-%s" % (ranks, n // ranks, tag), exe, ranks, n // ranks))
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for rnd in range(a.rounds):
            for name, exe, ranks, threads in (confs if rnd % 2 == 0 else confs[::-1]):
                path = os.path.join(work, "run.json")
                t0 = time.perf_counter()
                rc = subprocess.run(command(exe, ranks, threads, path), stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL).returncode
                wall = time.perf_counter() - t0
                try:
                    with open(path) as f:
                        d = json.load(f)
                    render, write = d["seconds"]["render"], d["seconds"]["write"]
                    compute = max((r["compute_seconds"] for r in d.get("ranks", [])), default=None)
                except (OSError, ValueError, KeyError):
                    render = write = compute = None
                rows.append(dict(round=rnd, config=name, rc=rc, wall_s=wall, render_s=render, write_s=write,
                                 max_rank_compute_s=compute))
    with open(a.csv, "w") as f:
        f.write(",".join(rows[0]) + "\n")
        for r in rows:
            f.write(",".join("" if v is None else str(v) for v in r.values()) + "\n")
    base = confs[0][0]
    by = {}
    for r in rows:
        if r["render_s"]:
            by.setdefault(r["round"], {})[r["config"]] = r
    for name, *_ in confs:
        v = [r["render_s"] for r in rows if r["config"] == name and r["render_s"]]
        gap = [r["render_s"] - r["max_rank_compute_s"] for r in rows if r["config"] == name and r["render_s"] and
               r["max_rank_compute_s"] is not None]
        line = "%-12s render median %.4f s [%.4f-%.4f], %d runs" % (name, st.median(v), min(v), max(v), len(v))
        if gap:
            line += "; render minus slowest rank's compute %.1f ms" % (1000 * st.median(gap))
        done = [r for r in rows if r["config"] == name and r["render_s"]]
        line += "; write %.1f ms; wall %.3f s" % (1000 * st.median(r["write_s"] for r in done),
                                                   st.median(r["wall_s"] for r in done))
        if name != base:
            line += "; / %s per round %.3f" % (base, st.median(
                [b[name]["render_s"] / b[base]["render_s"] for b in by.values() if name in b and base in b]))
        print(line)
    return 0 if all(r["rc"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
