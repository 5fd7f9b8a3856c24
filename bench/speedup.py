#!/usr/bin/env python3
"""pvrt's parallel scaling on this machine: OpenMP schedules, MPI strategies and gathers, hybrid splits.

Every configuration renders the same picture (paper scene 1 by default); the image is the same bits whatever the
configuration, so only time changes. Configurations run in rounds: each round runs every configuration once, in
forward order in even rounds and backward in odd ones, so a slow phase of the machine hits all alike. Per run:
the render stage from `--stats` (for MPI, rank 0's, from the first item to the gathered image), the whole command's
wall time (for MPI, `mpirun`'s), and for MPI the ranks' compute times.

The machine's ceiling: one single-thread render alone against N of them at once (independent processes). On a
shared or virtual machine N busy cores are slower than one (clock, memory, neighbours): efficiency is given raw
(speedup / P) and against that ceiling (raw x the ceiling's slow-down).

    bench/speedup.py --out DIR [--pvrt build/pvrt] [--mpirun mpirun] [--max-p N] [--runs 5] [--quick]
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import time

from bench import write_csv
import pvrt_stats

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

FIELDS = ["group", "config", "kind", "schedule", "gather", "ranks", "threads", "p", "run", "spp", "width", "height",
          "status", "wall_s", "render_s", "load_s", "build_s", "write_s", "peak_rss_kib", "rank_compute_min_s",
          "rank_compute_max_s", "rank_compute_mean_s", "rank_comm_max_s", "rank_idle_max_s", "imbalance_work"]


def parse_args(argv):
    ap = argparse.ArgumentParser(prog="bench/speedup.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--pvrt", default=os.path.join(ROOT, "build", "pvrt"), help="pvrt binary (default build/pvrt)")
    ap.add_argument("--mpirun", default="mpirun", help="mpirun command (default mpirun; '' leaves MPI out)")
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "paper1.xml"))
    ap.add_argument("--max-p", type=int, help="largest P (default: the CPUs this process may use)")
    ap.add_argument("--runs", type=int, help="rounds of every configuration (default 5; quick 1)")
    ap.add_argument("--width", type=int, help="default 1280; quick 160")
    ap.add_argument("--height", type=int, help="default 800; quick 100")
    ap.add_argument("--spp", type=int, help="samples per pixel c (default 16; quick 4)")
    ap.add_argument("--only", default="ceiling,openmp,mpi,hybrid",
                    help="comma-separated groups: ceiling, openmp, mpi, hybrid, fig1 (c=256, mpirun's wall "
                         "against one process's; long)")
    ap.add_argument("--fig1-spp", type=int, default=256, help="c of the fig1 group (default 256)")
    ap.add_argument("--fig1-runs", type=int, default=2, help="rounds of the fig1 group (default 2)")
    ap.add_argument("--fig1-base-runs", type=int, help="rounds of fig1's one-thread run (default: --fig1-runs)")
    ap.add_argument("--select", help="only the configurations whose name matches this regular expression")
    ap.add_argument("--quick", action="store_true", help="tiny sizes and one round (a smoke test)")
    ap.add_argument("--summarise", action="store_true",
                    help="run nothing: write the tables again from OUT/scaling_runs.csv (a run cut short, or one "
                         "brought back from another machine; give the --max-p it ran with)")
    a = ap.parse_args(argv)
    a.runs = a.runs or (1 if a.quick else 5)
    a.width = a.width or (160 if a.quick else 1280)
    a.height = a.height or (100 if a.quick else 800)
    a.spp = a.spp or (4 if a.quick else 16)
    a.max_p = a.max_p or len(os.sched_getaffinity(0))
    if os.sep in a.pvrt:
        a.pvrt = os.path.abspath(a.pvrt)
    a.only = set(a.only.split(","))
    if a.only - {"ceiling", "openmp", "mpi", "hybrid", "fig1"}:
        ap.error("unknown group in --only")
    return a


def counts(n):
    """1..n when n <= 8, else 1, powers of two below n, and n."""
    return list(range(1, n + 1)) if n <= 8 else sorted({1, n} | {2 ** k for k in range(1, 12) if 2 ** k < n})


def configurations(a):
    """(group, config, kind, schedule, gather, ranks, threads) of every configuration."""
    n = a.max_p
    out = []
    if "openmp" in a.only:
        for p in counts(n):
            out.append(("openmp", "openmp tiles P=%d" % p, "openmp", "tiles", "", 1, p))
        for sched in ("dynamic", "cyclic", "block", "static", "guided"):
            for p in sorted({2, n // 2, n} - {0, 1}) if n >= 2 else []:
                out.append(("openmp", "openmp %s P=%d" % (sched, p), "openmp", sched, "", 1, p))
    if "mpi" in a.only and a.mpirun:
        for p in counts(n):
            for sched in ("cyclic", "tiles", "dynamic", "block"):
                out.append(("mpi", "mpi %s gather P=%d" % (sched, p), "mpi", sched, "gather", p, 1))
            if p > 1:
                out.append(("mpi", "mpi cyclic recursive-doubling P=%d" % p, "mpi", "cyclic", "recursive-doubling",
                            p, 1))
        if n > 1:  # the ranks left to the kernel: the figures behind unequal rank times
            out.append(("mpi", "mpi cyclic gather P=%d unpinned" % n, "mpi-unpinned", "cyclic", "gather", n, 1))
    if "hybrid" in a.only and a.mpirun:
        r = 2
        while r < n:
            if n % r == 0:
                for sched in ("tiles", "dynamic"):
                    out.append(("hybrid", "hybrid %s %dx%d" % (sched, r, n // r), "mpi", sched, "gather", r, n // r))
            r *= 2
    return out


def run(cmd, log, env=None):
    """Runs cmd; returns (wall seconds, peak RSS KiB of the largest child, exit code, stdout)."""
    start = time.perf_counter()
    with open(log + ".out", "w") as out, open(log + ".err", "w") as err:
        p = subprocess.Popen(cmd, stdout=out, stderr=err, env=env)
        _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - start
    with open(log + ".out", errors="replace") as f:
        text = f.read()
    return wall, usage.ru_maxrss, os.waitstatus_to_exitcode(status), text


def parse_stats(json_path_or_text):
    """The figures of `pvrt render --stats-json` (bench/pvrt_stats.py) that the tables use."""
    r = pvrt_stats.figures(pvrt_stats.read(json_path_or_text))
    return {k: v for k, v in r.items() if k not in ("worker_work", "worker_seconds")}


class Runner:
    def __init__(self, a):
        self.a = a
        self.rows = []
        self.logs = os.path.join(a.out, "logs")
        os.makedirs(self.logs, exist_ok=True)
        self.png = os.path.join(a.out, "speedup-image.png")

    def render_cmd(self, spp, threads, schedule, extra=()):
        a = self.a
        return [a.pvrt, "render", a.scene, "-o", self.png, "-W", str(a.width), "-H", str(a.height), "--sampler",
                "pov", "--spp", str(spp), "--threads", str(threads), "--schedule", schedule, "--stats", "--quiet",
                *extra]

    def command(self, kind, schedule, gather, ranks, threads, spp):
        if kind == "openmp":
            return self.render_cmd(spp, threads, schedule), None
        env = dict(os.environ)
        if kind == "mpi-unpinned":
            env["PVRT_PIN_THREADS"] = "0"
        mpirun = self.a.mpirun.split() + ["--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np",
                                          str(ranks)]
        if kind == "mpi-unpinned":
            mpirun += ["-x", "PVRT_PIN_THREADS"]
        return mpirun + self.render_cmd(spp, threads, schedule, ["--backend", "mpi", "--gather", gather]), env

    def measure(self, conf, rnd, spp):
        group, config, kind, schedule, gather, ranks, threads = conf
        cmd, env = self.command(kind, schedule, gather, ranks, threads, spp)
        tag = re.sub(r"[^A-Za-z0-9_.-]+", "_", "%s.c%d.r%s" % (config, spp, rnd))
        log = os.path.join(self.logs, tag)
        wall, rss, rc, text = run(cmd + ["--stats-json", log + ".json"], log, env)
        row = dict(group=group, config=config, kind=kind, schedule=schedule, gather=gather, ranks=ranks,
                   threads=threads, p=ranks * threads, run=rnd, spp=spp, width=self.a.width, height=self.a.height,
                   status="ok" if rc == 0 else "failed (exit %d, logs/%s.err)" % (rc, tag), wall_s=wall,
                   peak_rss_kib=rss)
        row.update(parse_stats(log + ".json"))
        self.rows.append(row)
        # Kept current after every run, so a measurement cut short (a borrowed machine's time limit) keeps its rows.
        write_csv(os.path.join(self.a.out, "scaling_runs.csv"), self.rows, FIELDS)
        print("  %-40s c=%-3d run %-3s wall %7.3f s  render %s  %s" % (
            config, spp, rnd, wall, "%7.4f s" % row["render_s"] if "render_s" in row else "    n/a", row["status"]),
            flush=True)
        return row

    def together(self, rnd):
        """N single-thread renders at once (independent processes): the machine's own slow-down with N busy CPUs."""
        n = self.a.max_p
        procs = []
        start = time.perf_counter()
        for k in range(n):
            log = os.path.join(self.logs, "ceiling.together.r%d.%d" % (rnd, k))
            out = open(log + ".out", "w")
            cmd = self.render_cmd(self.a.spp, 1, "tiles") + ["--stats-json", log + ".json"]
            cmd[cmd.index("-o") + 1] = os.path.join(self.a.out, "ceiling-%d.png" % k)
            procs.append((subprocess.Popen(cmd, stdout=out, stderr=subprocess.DEVNULL), out, log))
        for p, out, log in procs:
            rc = p.wait()
            out.close()
            stats = parse_stats(log + ".json")
            self.rows.append(dict(group="ceiling", config="together x%d" % n, kind="openmp", schedule="tiles",
                                  ranks=1, threads=1, p=1, run=rnd, spp=self.a.spp, width=self.a.width,
                                  height=self.a.height, status="ok" if rc == 0 else "failed (exit %d)" % rc,
                                  wall_s=time.perf_counter() - start, **stats))
        for k in range(n):
            try:
                os.remove(os.path.join(self.a.out, "ceiling-%d.png" % k))
            except OSError:
                pass
        write_csv(os.path.join(self.a.out, "scaling_runs.csv"), self.rows, FIELDS)
        together = [r["render_s"] for r in self.rows if r["config"].startswith("together") and r["run"] == rnd
                    and "render_s" in r]
        if together:
            print("  %-40s c=%-3d run %-3s render median %.4f s, max %.4f s" % (
                "together x%d" % n, self.a.spp, rnd, statistics.median(together), max(together)), flush=True)

    def rounds(self, confs, rounds, spp, only_first=None):
        """Every configuration once a round, forward then backward; `only_first` maps a configuration's
        name to the number of rounds it takes part in (from the first)."""
        for rnd in range(rounds):
            for conf in (confs if rnd % 2 == 0 else confs[::-1]):
                if rnd >= (only_first or {}).get(conf[1], rounds):
                    continue
                if conf[2] == "together":
                    self.together(rnd)
                else:
                    self.measure(conf, rnd, spp)


def median(rows, field):
    v = [r[field] for r in rows if r.get("status") == "ok" and r.get(field) is not None]
    return (statistics.median(v), min(v), max(v), len(v)) if v else None


def summarise(rows, max_p):
    """One entry per (config, spp) with medians, speedup and efficiencies."""
    out = []
    keys = []
    for r in rows:
        if (r["config"], r["spp"]) not in keys:
            keys.append((r["config"], r["spp"]))
    # "alone" (the ceiling's) and "openmp tiles P=1" are the same command in the same rounds: on a noisy machine
    # their medians differed by 9% (3.50 and 3.18 s, 10 rounds each), which moved every efficiency as much, so
    # both the speedups and the ceiling take the median of the two together.
    single = [r for r in rows if r["config"] in ("alone", "openmp tiles P=1")]
    alone = median(single, "render_s")
    together = median([r for r in rows if r["config"].startswith("together")], "render_s")
    # The slow-down is the machine's throughput with N busy CPUs against one alone: N renders that each take t_i
    # do N / sum(alone / t_i) renders' worth of time apiece, which is what an on-demand schedule can reach (a
    # median ratio would hide that some CPUs run at 60% of the others while the rest run at full speed).
    together_times = [r["render_s"] for r in rows if r["config"].startswith("together") and r.get("status") == "ok"
                      and r.get("render_s")]
    slowdown = (1 / statistics.mean(alone[0] / t for t in together_times)) if alone and together_times else None
    for config, spp in keys:
        group = [r for r in rows if r["config"] == config and r["spp"] == spp]
        s = {k: group[0].get(k) for k in ("group", "config", "kind", "schedule", "gather", "ranks", "threads", "p",
                                           "spp")}
        for field in ("render_s", "wall_s", "write_s", "load_s", "build_s", "rank_compute_min_s",
                      "rank_compute_max_s", "rank_compute_mean_s", "imbalance_work", "peak_rss_kib"):
            m = median(group, field)
            if m:
                s[field], s[field + "_min"], s[field + "_max"], s["runs"] = m
        out.append(s)
    for s in out:
        if s["group"] == "ceiling" or "render_s" not in s:
            continue
        base = next((b for b in out if b["config"] == "openmp tiles P=1" and b["spp"] == s["spp"]), None)
        if base and "render_s" in base:
            base_render = alone[0] if alone and base["spp"] == single[0]["spp"] else base["render_s"]
            s["speedup"] = base_render / s["render_s"]
            s["efficiency"] = s["speedup"] / s["p"]
            if slowdown and s["p"] > 1:
                # Against what P independent single-thread renders reach on this machine
                # (interpolated linearly in P between 1 and the ceiling's N).
                sd = 1 + (slowdown - 1) * (s["p"] - 1) / max(1, max_p - 1)
                s["efficiency_vs_ceiling"] = s["efficiency"] * sd
            # Whole commands: mpirun (or the process) against one single-thread process.
            if "wall_s" in base:
                s["wall_speedup"] = base["wall_s"] / s["wall_s"]
                s["wall_efficiency"] = s["wall_speedup"] / s["p"]
    return out, slowdown, alone, together


def pct(v):
    return "–" if v is None else "%.0f%%" % (100 * v)


def num(v, pattern="{:.4f}"):
    return "–" if v is None else pattern.format(v)


def markdown(a, summary, slowdown, alone, together, meta):
    L = ["## Parallel scaling (%s, %d x %d, c = %d)" % (os.path.basename(a.scene), a.width, a.height, a.spp), ""]
    L += ["| | |", "|---|---|"] + ["| %s | %s |" % kv for kv in meta.items()] + [""]
    L += ["Render: the render stage from `--stats` (MPI: rank 0's, to the gathered image), median [min–max] of %d "
          "interleaved rounds. Speedup: the median of every single-thread render of those rounds "
          "(`openmp tiles P=1` and the ceiling's `alone`, the same command) over this one. E: speedup / P. "
          "E/ceiling: E times the machine's own slow-down with P busy CPUs (below). Wall: the whole command "
          "(`mpirun` included) against one single-thread process's." % a.runs, ""]
    if alone and together:
        L += ["**Ceiling**: one single-thread render alone %.4f s [%.4f–%.4f]; %d at once %.4f s median, %.4f s "
              "worst: their throughput is **1/%.3f** of %d renders alone (worst render %.3fx slower). Measured in "
              "the same rounds as the configurations." % (alone[0], alone[1], alone[2], a.max_p, together[0],
                                                          together[2], slowdown, a.max_p, together[2] / alone[0]),
              ""]
    for group, title in (("openmp", "OpenMP threads"), ("mpi", "MPI ranks (1 thread each)"),
                         ("hybrid", "Hybrid MPI x OpenMP"), ("fig1", "Fig. 1 setting")):
        rows = [s for s in summary if s["group"] == group]
        if not rows:
            continue
        L += ["### " + title, "",
              "| configuration | P | c | render s | speedup | E | E/ceiling | wall s | wall E | rank compute "
              "min–max s | work imbalance |", "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"]
        for s in rows:
            rc = ("%.4f–%.4f" % (s["rank_compute_min_s"], s["rank_compute_max_s"])
                  if s.get("rank_compute_min_s") is not None else "–")
            L.append("| %s | %d | %d | %s [%s–%s] | %s | %s | %s | %s | %s | %s | %s |" % (
                s["config"], s["p"], s["spp"], num(s.get("render_s")), num(s.get("render_s_min")),
                num(s.get("render_s_max")), num(s.get("speedup"), "{:.2f}"), pct(s.get("efficiency")),
                pct(s.get("efficiency_vs_ceiling")), num(s.get("wall_s"), "{:.3f}"), pct(s.get("wall_efficiency")),
                rc, num(s.get("imbalance_work"), "{:.3f}")))
        L.append("")
    return "\n".join(L)


def plot(a, summary):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    series = {}
    for s in summary:
        if s["group"] in ("openmp", "mpi") and "speedup" in s and "unpinned" not in s["config"]:
            label = re.sub(r" P=\d+", "", s["config"])
            series.setdefault(label, []).append(s)
    for label, rows in sorted(series.items()):
        if len(rows) < 2:
            continue
        rows.sort(key=lambda s: s["p"])
        style = "o-" if label.startswith("openmp") else "s--"
        ax.plot([s["p"] for s in rows], [s["speedup"] for s in rows], style, label=label)
        ax2.plot([s["p"] for s in rows], [100 * s["efficiency"] for s in rows], style, label=label)
    p = [1, a.max_p]
    ax.plot(p, p, "k:", label="ideal")
    ax.set_ylabel("speedup (render stage)")
    ax2.set_ylabel("efficiency %")
    ax2.set_ylim(0, 110)
    for x in (ax, ax2):
        x.set_xlabel("P (threads or ranks)")
        x.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.suptitle("pvrt parallel scaling, %s %dx%d c=%d" % (os.path.basename(a.scene), a.width, a.height, a.spp))
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "scaling.png"), dpi=110)
    plt.close(fig)
    return ["scaling.png"]


def read_runs(path):
    """The rows of a scaling_runs.csv, numbers as numbers, empty fields left out."""
    rows = []
    with open(path, newline="") as f:
        for raw in csv.DictReader(f):
            row = {}
            for k, v in raw.items():
                if v in ("", None):
                    continue
                try:
                    row[k] = int(v)
                except ValueError:
                    try:
                        row[k] = float(v)
                    except ValueError:
                        row[k] = v
            rows.append(row)
    return rows


def main(argv, meta=None):
    a = parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    r = Runner(a)
    started = time.perf_counter()
    if a.summarise:
        r.rows = read_runs(os.path.join(a.out, "scaling_runs.csv"))
        a.runs = max((x["run"] for x in r.rows if x.get("group") != "fig1"), default=0) + 1
        a.width, a.height, a.spp = r.rows[0]["width"], r.rows[0]["height"], r.rows[0]["spp"]
        a.only = set()
    else:
        run_all(a, r)
    return report(a, r, meta, started)


def run_all(a, r):
    confs = configurations(a)
    if a.select:
        confs = [c for c in confs if re.search(a.select, c[1])]
    if "ceiling" in a.only and a.max_p > 1:
        # In the same rounds as the configurations, so that a slow phase of a shared machine weighs on the ceiling
        # as on the runs it is set against (measured first, on its own, it once came out 1.06x where the same
        # rounds gave 1.37x).
        confs = [("ceiling", "alone", "openmp", "tiles", "", 1, 1),
                 ("ceiling", "together x%d" % a.max_p, "together", "tiles", "", 1, 1)] + confs
    r.rounds(confs, a.runs, a.spp)
    if "fig1" in a.only:
        fig1 = [("fig1", "fig1 openmp P=1", "openmp", "tiles", "", 1, 1),
                ("fig1", "fig1 openmp P=%d" % a.max_p, "openmp", "tiles", "", 1, a.max_p)]
        if a.mpirun:
            fig1 += [("fig1", "fig1 mpi %s P=%d" % (s, a.max_p), "mpi", s, "gather", a.max_p, 1)
                     for s in ("cyclic", "dynamic")]
        if a.select:
            fig1 = [c for c in fig1 if re.search(a.select, c[1])]
        base_runs = a.fig1_base_runs if a.fig1_base_runs is not None else a.fig1_runs
        r.rounds(fig1, a.fig1_runs, a.fig1_spp, {"fig1 openmp P=1": base_runs})


def report(a, r, meta, started):
    summary, slowdown, alone, together = summarise(r.rows, a.max_p)
    # fig1's baseline is its own one-thread run at its c.
    for s in summary:
        if s["group"] == "fig1" and s["config"] != "fig1 openmp P=1":
            base = next((b for b in summary if b["config"] == "fig1 openmp P=1"), None)
            if base and "render_s" in base and "render_s" in s:
                s["speedup"] = base["render_s"] / s["render_s"]
                s["efficiency"] = s["speedup"] / s["p"]
                s["wall_speedup"] = base["wall_s"] / s["wall_s"]
                s["wall_efficiency"] = s["wall_speedup"] / s["p"]
    meta = dict(meta or {})
    meta.setdefault("CPUs used", str(a.max_p))
    if not a.summarise:
        meta["scaling time"] = "%.0f s" % (time.perf_counter() - started)
        write_csv(os.path.join(a.out, "scaling_runs.csv"), r.rows, FIELDS)
    write_csv(os.path.join(a.out, "scaling_summary.csv"), summary)
    plots = plot(a, summary)
    md = markdown(a, summary, slowdown, alone, together, meta)
    if plots:
        md += "\n" + "\n".join("![%s](%s)" % (p, p) for p in plots) + "\n"
    with open(os.path.join(a.out, "scaling.md"), "w") as f:
        f.write(md)
    print("speedup: wrote %s/scaling.md, scaling_runs.csv, scaling_summary.csv%s" % (
        a.out, "".join(", " + p for p in plots)))
    failed = [x for x in r.rows if str(x.get("status", "")).startswith("failed")]
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
