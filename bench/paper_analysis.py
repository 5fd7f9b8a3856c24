"""The measurements bench/paper.py takes besides renders (the machine's ceiling, gathers, memory) and what it makes
of all of them: medians, the figures' quantities, the performance model against every timed run, the simulator."""
import csv
import math
import os
import re
import statistics
import subprocess
import sys
import time


import lbsim
import loadmap
import model
from speedup import parse_stats
import pvrt_stats

HERE = os.path.dirname(os.path.abspath(__file__))


def ceiling(a, r):
    """One single-thread render alone against max_p of them at once (independent processes): how much slower each
    CPU is when all are busy (shared caches, memory, clock, neighbours). Returns (alone s, together s) medians."""
    alone, together = [], []
    for rep in range(a.reps):
        row = r.render("ceiling", "scene1", 16, 1, strategy="tiles", rep=rep)
        if "render_s" in row:
            alone.append(row["render_s"])
        if a.max_p < 2:
            continue
        procs = []
        for k in range(a.max_p):
            cmd = [a.pvrt, "render", os.path.join(HERE, "..", "scenes", "paper1.xml"), "-o",
                   os.path.join(a.out, "logs", "ceiling-%d.png" % k), "-W", str(a.width), "-H", str(a.height),
                   "--sampler", "jitter", "--spp", "16", "--threads", "1", "--stats-json", "-", "--quiet"]
            procs.append(subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True))
        for p in procs:
            st = parse_stats(p.communicate()[0])
            if "render_s" in st:
                together.append(st["render_s"])
    med = lambda v: statistics.median(v) if v else None  # noqa: E731
    return med(alone), med(together)


def gathers(a, r):
    """Fig. 11: `pvrt mpi-bench` on P = 2.. ranks; its rows (with P) and the ping-pong's tau_s, tau_b."""
    rows = []
    for p in a.fig11_p:
        path = os.path.join(a.out, "logs", "mpibench-P%d.csv" % p)
        cmd = a.mpirun.split() + ["--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np", str(p),
                                  a.pvrt, "mpi-bench", "--reps", str(a.bench_reps), "--no-8k", "--csv", path]
        with open(os.path.join(a.out, "logs", "mpibench-P%d.out" % p), "w") as out:
            rc = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT).returncode
        r.rows.append(dict(figure="fig11", backend="mpi", p=p, status="ok" if rc == 0 else "failed (exit %d)" % rc,
                           note="more ranks than cores" if p > a.max_p else ""))
        if rc == 0:
            for x in csv.DictReader(open(path)):
                x["oversubscribed"] = "yes" if p > a.max_p else ""
                rows.append(x)
        print("  fig11 mpi-bench P=%d %s" % (p, "ok" if rc == 0 else "failed"), flush=True)
    two = [x for x in rows if int(x["ranks"]) == 2]
    tau_s, tau_b = model.ping_pong_costs(two) if two else (float("nan"), float("nan"))
    return dict(rows=rows, tau_s=tau_s, tau_b=tau_b)


def rss_run(a, r, cmd, ranks, tag):
    """Peak resident set of every rank (KiB) of cmd, run under mpirun when ranks > 0."""
    prefix = os.path.join(a.out, "logs", "rss-" + tag)
    wrapped = [sys.executable, os.path.join(HERE, "rss_wrap.py"), prefix] + cmd
    if ranks:
        wrapped = a.mpirun.split() + ["--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np",
                                      str(ranks), "-x", "PVRT_HUGE_PAGES"] + wrapped
    env = dict(os.environ, PVRT_HUGE_PAGES="0")
    with open(prefix + ".log", "w") as log:
        rc = subprocess.run(wrapped, stdout=log, stderr=subprocess.STDOUT, env=env).returncode
    out = []
    for k in range(max(1, ranks)):
        try:
            out.append(int(open("%s.%d" % (prefix, k)).read()))
        except (OSError, ValueError):
            out.append(None)
    return rc, out


def memory(a, r):
    """Peak RSS per rank against image size (c = 1, one thread per rank) for P = 1 and for both gathers at P = 2
    and 4, and against the number of spheres; huge pages off (PVRT_HUGE_PAGES=0) so pages are 4 KiB."""
    rows = []
    scene = os.path.join(HERE, "..", "scenes", "paper1.xml")
    ranks = [2] if a.mode == "quick" else [2, 4]
    for w, h in a.mem_sizes:
        base = [a.pvrt, "render", scene, "-o", os.path.join(a.out, "logs", "mem.png"), "-W", str(w), "-H", str(h),
                "--quiet", "--threads", "1"]
        runs = [("none", 0, base)] + [(g, p, base + ["--backend", "mpi", "--schedule", "block", "--gather", g])
                                      for g in ("gather", "recursive-doubling") for p in ranks]
        for gather, p, cmd in runs:
            rc, rss = rss_run(a, r, cmd, p, "%dx%d-%s-%d" % (w, h, gather, p))
            for k, v in enumerate(rss):
                rows.append(dict(kind="pixels", width=w, height=h, pixels=w * h, spheres=100, lights=5,
                                 gather=gather, ranks=max(p, 1), rank=k, peak_rss_kib=v,
                                 status="ok" if rc == 0 and v else "failed (exit %d)" % rc))
    for n in a.mem_objects:
        path = os.path.join(a.out, "logs", "spheres-%d.xml" % n)
        subprocess.run([a.pvrt, "generate", "--spheres", str(n), "--lights", "5", "--seed", "1", "-o", path],
                       check=True, stdout=subprocess.DEVNULL)
        rc, rss = rss_run(a, r, [a.pvrt, "render", path, "-o", os.path.join(a.out, "logs", "mem.png"), "-W", "32",
                                 "-H", "20", "--quiet", "--threads", "1", "--stats-json", "-"], 0, "spheres-%d" % n)
        text = open(os.path.join(a.out, "logs", "rss-spheres-%d.log" % n)).read()
        kib = [pvrt_stats.figures(pvrt_stats.read(text[text.find("{"):])).get("structures_kib", 0.0)]
        rows.append(dict(kind="objects", width=32, height=20, pixels=640, spheres=n, lights=5, gather="none",
                         ranks=1, rank=0, peak_rss_kib=rss[0], structures_kib=sum(kib),
                         status="ok" if rc == 0 and rss[0] else "failed"))
        os.remove(path)
    print("  memory: %d readings" % len(rows), flush=True)
    return rows


def medians(rows):
    """One entry per configuration: the median render time over its repetitions, and its other fields."""
    groups = {}
    for x in rows:
        if x.get("status") != "ok" or "render_s" not in x:
            continue
        key = tuple(x.get(k) for k in ("figure", "scene", "backend", "strategy", "chunk", "tile", "gather", "p",
                                       "spp", "width", "height"))
        groups.setdefault(key, []).append(x)
    out = []
    for key, xs in groups.items():
        t = [x["render_s"] for x in xs]
        m = dict(xs[0])
        m.update(render_s=statistics.median(t), render_min_s=min(t), render_max_s=max(t), reps=len(t))
        for f in ("rank_compute_max_s", "rank_comm_max_s"):
            v = [x[f] for x in xs if x.get(f) is not None]
            m[f] = statistics.median(v) if v else None
        out.append(m)
    return out


def share(work_map, backend, strategy, p, tile=32):
    return model.rank_work(work_map, strategy if strategy in ("block", "cyclic") else "tiles", p, tile)


def why(m, pred, ceil_factor, tau_f):
    """The measured figures that explain a miss of more than 10%."""
    notes = []
    if ceil_factor and ceil_factor > 1.05:
        notes.append("%d busy CPUs run %.0f%% slower each (ceiling)" % (m["p"], 100 * (ceil_factor - 1)))
    secs = [float(s) for s in str(m.get("worker_s") or "").split()]
    work = [int(w) for w in str(m.get("worker_work") or "").split()]
    if secs and work and sum(work):
        per = max(secs) / work[secs.index(max(secs))] if work[secs.index(max(secs))] else 0
        if per and abs(per / tau_f - 1) > 0.1:
            notes.append("busiest worker %.0f%% %s per work unit than the serial run (caches, clock, neighbours)"
                         % (100 * abs(per / tau_f - 1), "slower" if per > tau_f else "faster"))
        overhead = m["render_s"] - max(secs)
        if overhead > 0.1 * m["render_s"]:
            notes.append("%.0f%% of the render stage outside the workers' compute (start-up, gather, waits)"
                         % (100 * overhead / m["render_s"]))
    if m.get("rank_comm_max_s") and m["rank_comm_max_s"] > 2 * max(pred["pred_comm_s"], 1e-6):
        notes.append("communication %.4f s measured against %.4f s modelled" % (m["rank_comm_max_s"],
                                                                               pred["pred_comm_s"]))
    return "; ".join(notes) or "not explained by the ceiling, per-work cost or communication measured"


def analyse(a, rows, ctx):
    res = {}
    meds = medians(rows)
    res["medians"] = meds
    maps = {k: loadmap.read(v) for k, v in ctx["maps"].items() if os.path.exists(v)}
    res["maps"] = maps
    tau_f = {}
    for m in meds:
        if m["figure"] == "serial" and m.get("work_total"):
            tau_f[m["scene"]] = m["render_s"] / m["work_total"]
    res["tau_f"] = tau_f
    tau_s, tau_b = ctx["bench"]["tau_s"], ctx["bench"]["tau_b"]
    alone, together = ctx["ceiling"]
    slow_n = together / alone if alone and together else 1.0
    res["ceiling"] = (alone, together, slow_n)
    # The model against figs. 6, 9 (block, cyclic), 13 and the simulator's MPI runs.
    model_rows = []
    for m in meds:
        if m["figure"] not in ("fig9", "fig13", "sim") or m["scene"] not in tau_f or not m.get("work_total"):
            continue
        wmap = maps.get((m["scene"], 16 if m["spp"] >= 16 else 8))
        if wmap is None:
            continue
        p = m["p"]
        ceil_factor = 1 + (slow_n - 1) * (p - 1) / max(1, a.max_p - 1) if p <= a.max_p else slow_n * p / a.max_p
        tf = tau_f[m["scene"]]
        if m["strategy"] == "dynamic":
            sim = lbsim.simulate(wmap * (m["work_total"] / wmap.sum()), "dynamic", p, tf, tau_s, tau_b,
                                 tile=int(m["tile"] or 32))
            t = sim["time_s"]
            pred = dict(pred_s=t, pred_compute_s=tf * m["work_total"] / p, pred_comm_s=model.gather_seconds(
                m["gather"], p, wmap.size, tau_s, tau_b))
            pred["pred_idle_s"] = t - pred["pred_compute_s"] - pred["pred_comm_s"]
        else:
            comm = model.gather_seconds(m["gather"], p, m["width"] * m["height"], tau_s, tau_b) \
                if m["backend"] == "mpi" else 0.0
            pred = model.predict(share(wmap, m["backend"], m["strategy"], p, int(m["tile"] or 32)),
                                 m["work_total"], p, tf, comm)
        err = pred["pred_s"] / m["render_s"] - 1
        corrected = (pred["pred_s"] - pred["pred_comm_s"]) * ceil_factor + pred["pred_comm_s"]
        row = dict((k, m[k]) for k in ("figure", "scene", "backend", "strategy", "tile", "gather", "p", "spp"))
        row.update(pred, measured_s=m["render_s"], error=err, pred_ceiling_s=corrected,
                   error_ceiling=corrected / m["render_s"] - 1,
                   why=why(m, pred, ceil_factor, tf) if abs(err) > 0.1 else "")
        model_rows.append(row)
    res["model"] = model_rows
    # Figs. 7, 8: the load per rank pvrt counted against the map's split.
    res["fig78"] = []
    for m in meds:
        if m["figure"] == "fig78" and m.get("worker_work"):
            wmap = maps.get((m["scene"], 8))
            measured = [int(w) for w in m["worker_work"].split()]
            predicted = model.rank_work(wmap, m["strategy"], 8) if wmap is not None else None
            res["fig78"].append(dict(scene=m["scene"], strategy=m["strategy"], measured=measured,
                                     predicted=None if predicted is None else [float(v) for v in predicted]))
    res["sim"] = simulate(a, maps, tau_f, tau_s, tau_b, res["model"], slow_n)
    res["memory"] = memory_model(ctx["memory"])
    return res


def simulate(a, maps, tau_f, tau_s, tau_b, model_rows, slow_n=1.0):
    """The simulator over P = 1..4096 for 1280x800 (or this run's size) and an 8K stretch of the same map, with
    and without slow ranks; its agreement with the measured MPI runs of scene 1 at c = 16."""
    wmap = maps.get(("scene1", 16))
    if wmap is None or "scene1" not in tau_f or not all(map(math.isfinite, (tau_s, tau_b))):
        return None
    tf = tau_f["scene1"]
    started = time.time()
    small = loadmap.resample(wmap, 1280, 800) if a.mode != "quick" else wmap
    big = loadmap.resample(wmap, *a.big)
    # A pixel of the stretched maps costs what the measured pixel does: the total grows with the pixels.
    hetero = ((0.0, 1.0), (0.25, 2.0))
    rows = lbsim.sweep(small, "%dx%d" % small.shape[::-1], a.sim_p, tf, tau_s, tau_b, a.sim_tiles[0], hetero)
    rows += lbsim.sweep(big, "%dx%d" % big.shape[::-1], a.sim_p, tf, tau_s, tau_b, a.sim_tiles[1], hetero)
    check = []
    for m in model_rows:
        if m["backend"] == "mpi" and m["scene"] == "scene1" and m["figure"] in ("fig9", "sim"):
            s = lbsim.simulate(wmap, m["strategy"], m["p"], tf, tau_s, tau_b, tile=int(m["tile"] or 32))
            # The same correction as the model's: compute slowed by the machine's ceiling at P busy CPUs.
            cf = 1 + (slow_n - 1) * (m["p"] - 1) / max(1, a.max_p - 1)
            check.append(dict(strategy=m["strategy"], p=m["p"], simulated_s=s["time_s"], measured_s=m["measured_s"],
                              error=s["time_s"] / m["measured_s"] - 1,
                              error_ceiling=s["time_s"] * cf / m["measured_s"] - 1))
    print("  simulator: %d configurations in %.0f s" % (len(rows), time.time() - started), flush=True)
    return dict(rows=rows, check=check, stops=lbsim.stops_scaling(rows),
                best={p: lbsim.best(rows, p) for p in (64, 256, 4096) if p in a.sim_p})


def memory_model(rows):
    """Slopes of peak RSS against pixels (per rank: rank 0 and the others, each gather) and against spheres, and
    the paper's formulas beside the measured totals above the smallest image's."""
    ok = [x for x in rows if str(x["status"]) == "ok"]
    out = dict(rows=rows, slopes=[], table=[])
    for gather in ("none", "gather", "recursive-doubling"):
        for ranks in sorted({x["ranks"] for x in ok if x["gather"] == gather and x["kind"] == "pixels"}):
            for who in ("rank 0", "other ranks"):
                xs = [x for x in ok if x["kind"] == "pixels" and x["gather"] == gather and x["ranks"] == ranks
                      and ((x["rank"] == 0) == (who == "rank 0"))]
                if not xs:
                    continue
                k, c = model.slope([x["pixels"] for x in xs], [1024 * x["peak_rss_kib"] for x in xs])
                out["slopes"].append(dict(gather=gather, ranks=ranks, who=who, bytes_per_pixel=k, intercept_b=c))
    objs = [x for x in ok if x["kind"] == "objects"]
    k, c = model.slope([x["spheres"] for x in objs], [1024 * x["peak_rss_kib"] for x in objs])
    out["bytes_per_sphere"] = k
    k2, _ = model.slope([x["spheres"] for x in objs], [1024 * x.get("structures_kib", 0) for x in objs])
    out["structure_bytes_per_sphere"] = k2
    smallest = min((x["pixels"] for x in ok if x["kind"] == "pixels"), default=None)
    for gather in ("gather", "recursive-doubling"):
        for ranks in sorted({x["ranks"] for x in ok if x["gather"] == gather}):
            for pixels in sorted({x["pixels"] for x in ok if x["gather"] == gather and x["ranks"] == ranks}):
                xs = [x for x in ok if x["gather"] == gather and x["ranks"] == ranks and x["pixels"] == pixels]
                base = [x for x in ok if x["gather"] == gather and x["ranks"] == ranks and x["pixels"] == smallest]
                if len(xs) != ranks or len(base) != ranks:
                    continue
                w, h = xs[0]["width"], xs[0]["height"]
                total = 1024 * sum(x["peak_rss_kib"] for x in xs)
                above = total - 1024 * sum(x["peak_rss_kib"] for x in base)
                bw, bh = base[0]["width"], base[0]["height"]
                paper = model.paper_memory(5, 100, ranks, w, h, gather)
                paper_above = paper - model.paper_memory(5, 100, ranks, bw, bh, gather)
                out["table"].append(dict(gather=gather, ranks=ranks, width=w, height=h, measured_total_b=total,
                                         paper_b=paper, measured_above_smallest_b=above,
                                         paper_above_smallest_b=paper_above,
                                         ratio=above / paper_above if paper_above else None))
    return out
