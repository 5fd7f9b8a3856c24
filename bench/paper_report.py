"""bench/paper.py's report: the machine, then for each of the paper's figures pvrt's result beside the paper's
claim (bench/paper_claims.csv), its plot and its CSV."""
import csv
import datetime
import os
import platform
import subprocess

import numpy as np

from bench import write_csv
import paper_plots

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def first_line(*cmd):
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=30)
        return ((out.stdout or out.stderr).strip().splitlines() or ["?"])[0]
    except (OSError, subprocess.SubprocessError):
        return "not found"


def machine(a):
    cpu = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
               platform.processor())
    mem = next((line.split(":", 1)[1].strip() for line in open("/proc/meminfo") if line.startswith("MemTotal")), "?")
    commit = first_line("git", "-C", ROOT, "rev-parse", "--short", "HEAD")
    if subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"], capture_output=True,
                      text=True).stdout.strip():
        commit += " (with uncommitted changes)"
    return {
        "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
        "CPU": "%s, %d cores usable (%d online)" % (cpu, a.max_p, os.cpu_count()),
        "memory": mem,
        "system": platform.platform(),
        "MPI": first_line(a.mpirun.split()[0], "--version"),
        "compilers": "%s; %s" % (first_line("g++", "--version"), first_line("clang++", "--version")),
        "commit": commit,
        "pvrt": a.pvrt,
        "load average at start": " ".join("%.2f" % v for v in os.getloadavg()),
        "settings": "%s: %d x %d (table 1: 1280 x 800), %d repetitions (median [min-max]), P = 1..%d, "
                    "`--sampler jitter` everywhere (any c)" % (a.mode, a.width, a.height, a.reps, a.max_p),
    }


def claims():
    with open(os.path.join(HERE, "paper_claims.csv")) as f:
        return list(csv.DictReader(f))


def claim_lines(figure):
    out = ["*Paper*: %s (%s)." % (c["paper_claim"], c["source"]) for c in claims() if c["figure"] == figure]
    return out + [""]


def pct(v):
    return "–" if v is None else "%+.1f%%" % (100 * v)


def num(v, f="%.4f"):
    return "–" if v is None else f % v


def section_scaling(res, L, a):
    meds = res["medians"]
    serial = {m["scene"]: m["render_s"] for m in meds if m["figure"] == "serial"}
    L += ["## Fig. 6: speedup and efficiency, scene 1, c = 16", ""] + claim_lines("fig. 6")
    L += ["Speedup = the serial backend's median render (`--backend serial`) over the run's; E = speedup / P.", "",
          "| backend | strategy | P | render s [min–max] | speedup | E |", "|---|---|--:|--:|--:|--:|"]
    for m in sorted(meds, key=lambda m: (m["backend"], m["strategy"], m["p"])):
        if m["figure"] == "fig9" and m["scene"] == "scene1" and m["strategy"] == "cyclic" and "scene1" in serial:
            s = serial["scene1"] / m["render_s"]
            L.append("| %s | %s | %d | %.4f [%.4f–%.4f] | %.2f | %.0f%% |" % (
                m["backend"], m["strategy"], m["p"], m["render_s"], m["render_min_s"], m["render_max_s"], s,
                100 * s / m["p"]))
    L += ["", "![fig. 6](fig6_speedup.png)", ""]
    L += ["## Fig. 9: r_S = S_cyclic / S_block (= T_block / T_cyclic)", ""] + claim_lines("fig. 9")
    L += ["| scene | backend | P | T block s | T cyclic s | r_S |", "|---|---|--:|--:|--:|--:|"]
    for scene, backend, p, tb, tc in paper_plots.ratios(meds):
        L.append("| %s | %s | %d | %.4f | %.4f | %.3f |" % (scene, backend, p, tb, tc, tb / tc))
    L += ["", "![fig. 9](fig9_ratio.png)", ""]


def section_loads(res, L):
    L += ["## Figs. 7, 8: load per processor, 8 ranks, block against cyclic, c = 8", ""]
    L += claim_lines("fig. 7") + claim_lines("fig. 8")
    L += ["Each rank's work as pvrt counted it (`--stats`, with `--load-map`, so every pixel's own work) and as the "
          "model splits the measured load map; max/mean is the imbalance.", "",
          "| scene | strategy | rank work (pvrt) | max/mean | the map's split agrees |", "|---|---|---|--:|---|"]
    for x in res["fig78"]:
        meas = x["measured"]
        agree = "–" if x["predicted"] is None else (
            "exactly" if [round(v) for v in x["predicted"]] == meas else "max error %.2g%%" % (
                100 * max(abs(p - m) / max(m, 1) for p, m in zip(x["predicted"], meas))))
        L.append("| %s | %s | %s | %.3f | %s |" % (x["scene"], x["strategy"], " ".join(map(str, meas)),
                                                     max(meas) / np.mean(meas), agree))
    L += ["", "![figs. 7, 8](fig7_8_loads.png)", ""]


def section_openmp(res, L, a):
    L += ["## Fig. 12: OpenMP schedules and chunk sizes, c = 8, %d threads" % a.max_p, ""] + claim_lines("fig. 12")
    L += ["| scene | schedule | chunk | render s [min–max] |", "|---|---|--:|--:|"]
    for m in sorted((m for m in res["medians"] if m["figure"] == "fig12"),
                    key=lambda m: (m["scene"], m["strategy"], int(m["chunk"] or 0))):
        L.append("| %s | %s | %s | %.4f [%.4f–%.4f] |" % (m["scene"], m["strategy"], m["chunk"], m["render_s"],
                                                          m["render_min_s"], m["render_max_s"]))
    L += ["", "![fig. 12](fig12_schedules.png)", ""]
    L += ["## Fig. 13: constant c/P = 8 (c = 8P), scene 1", ""] + claim_lines("fig. 13")
    L += ["| backend | P | c | render s [min–max] |", "|---|--:|--:|--:|"]
    for m in sorted((m for m in res["medians"] if m["figure"] == "fig13"), key=lambda m: (m["backend"], m["p"])):
        L.append("| %s | %d | %d | %.4f [%.4f–%.4f] |" % (m["backend"], m["p"], m["spp"], m["render_s"],
                                                          m["render_min_s"], m["render_max_s"]))
    for backend, (k, c) in paper_plots.fig13_slopes(res["medians"]).items():
        L.append("")
        L.append("Trend line, %s: T = %.4f s + %.4f s x P (slope %s of T(1) per added P; flat = perfect scaling)."
                 % (backend, c, k, "%.1f%%" % (100 * k / (k + c)) if k + c else "–"))
    L += ["", "![fig. 13](fig13_constant.png)", ""]


def section_gathers(ctx, L):
    L += ["## Fig. 11: MPI_Gatherv against recursive doubling", ""] + claim_lines("fig. 11")
    L += ["`pvrt mpi-bench`: rank 0 collects a 1280x800 image of B bytes a pixel (3: the paper's 8-bit RGB; 12: "
          "pvrt's float payload), median [min–max] microseconds over the repetitions.", "",
          "| P | B/px | MPI_Gatherv us | recursive doubling us | note |", "|--:|--:|--:|--:|---|"]
    for p, bpp, g, rd, note in paper_plots.gather_table(ctx["bench"]["rows"]):
        L.append("| %d | %d | %s | %s | %s |" % (p, bpp, g, rd, note))
    L += ["", "tau_s = %.2f us, tau_b = %.3g s/byte (%.2f GB/s), from the 2-rank ping-pong (fastest repetition)." % (
        1e6 * ctx["bench"]["tau_s"], ctx["bench"]["tau_b"], 1e-9 / ctx["bench"]["tau_b"]), "",
        "![fig. 11](fig11_gather.png)", ""]


def section_table1(ctx, L, a):
    size, c = ("1280 x 800", 16) if a.mode != "quick" else ("%d x %d" % (a.width, a.height), 4)
    L += ["## Table 1: compilers (scene 1, %s, c = %d, OpenMP on %d cores)" % (size, c, a.max_p), ""]
    L += claim_lines("table 1")
    L += ["| build | build s | render s [min–max] |", "|---|--:|--:|"]
    for x in ctx["table1"]:
        L.append("| %s | %s | %s |" % (x["build"], num(x["build_s"], "%.0f"), "%.4f [%.4f–%.4f]" % (
            x["render_s"], x["render_min_s"], x["render_max_s"]) if x["render_s"] else x["status"]))
    L.append("")


def section_model(res, L, a):
    L += ["## The performance model", ""] + claim_lines("model")
    L += ["tau_f (s per work unit, serial runs): " + ", ".join("%s %.3g" % kv for kv in sorted(res["tau_f"].items()))]
    alone, together, slow = res["ceiling"]
    if alone and together:
        L += ["", "Ceiling: one single-thread render alone %.4f s, %d at once %.4f s each: %.2fx." % (
            alone, a.max_p, together, slow)]
    L += ["", "Predicted T = tau_f W / P + T_idle + T_comm; error = predicted / measured - 1; *with ceiling*: the "
          "compute scaled by the machine's measured slow-down with P busy CPUs.", "",
          "| figure | scene | backend | strategy | P | c | measured s | predicted s | error | with ceiling | why "
          "(when over 10%) |", "|---|---|---|---|--:|--:|--:|--:|--:|--:|---|"]
    for x in res["model"]:
        L.append("| %s | %s | %s | %s | %d | %d | %.4f | %.4f | %s | %s | %s |" % (
            x["figure"], x["scene"], x["backend"], x["strategy"], x["p"], x["spp"], x["measured_s"], x["pred_s"],
            pct(x["error"]), pct(x["error_ceiling"]), x["why"]))
    if res["model"]:
        worst = max(res["model"], key=lambda x: abs(x["error"]))
        L += ["", "Worst error: %s (%s %s %s P=%d c=%d); median |error| %.1f%%." % (
            pct(worst["error"]), worst["figure"], worst["backend"], worst["strategy"], worst["p"], worst["spp"],
            100 * float(np.median([abs(x["error"]) for x in res["model"]])))]
    L += ["", "![model](model_error.png)", ""]


def section_sim(res, L):
    sim = res["sim"]
    L += ["## Load-balance simulator (P = 1..4096)", ""]
    if not sim:
        L += ["Not run (no load map, serial run or ping-pong).", ""]
        return
    L += ["Scene 1's measured c = 16 work map (stretched to 1280 x 800 and to 8K by nearest pixel), tau_f, tau_s "
          "and tau_b as measured; heterogeneous: a quarter of the ranks twice as slow (bench/lbsim.py).", "",
          "Against the measured MPI runs of scene 1 (same P):", "",
          "| strategy | P | simulated s | measured s | error | with ceiling |", "|---|--:|--:|--:|--:|--:|"]
    for x in sim["check"]:
        L.append("| %s | %d | %.4f | %.4f | %s | %s |" % (x["strategy"], x["p"], x["simulated_s"], x["measured_s"],
                                                          pct(x["error"]), pct(x["error_ceiling"])))
    L += ["", "Largest P whose efficiency is still >= 50% (where each strategy stops scaling):", "",
          "| image | slow ranks | strategy | tile | P |", "|---|---|---|--:|--:|"]
    for (image, f, k, strategy, tile), p in sorted(sim["stops"].items(), key=lambda kv: tuple(map(str, kv[0]))):
        L.append("| %s | %s | %s | %s | %d |" % (image, "none" if f == 0 else "%g x%g" % (f, k), strategy, tile, p))
    L += ["", "Best strategy by simulated time:", "", "| ranks | image | slow ranks | best | tile | efficiency |",
          "|--:|---|---|---|--:|--:|"]
    for p, by in sorted(sim["best"].items()):
        for (image, f, k), r in sorted(by.items(), key=lambda kv: tuple(map(str, kv[0]))):
            L.append("| %d | %s | %s | %s | %s | %.0f%% |" % (p, image, "none" if f == 0 else "%g x%g" % (f, k),
                                                              r["strategy"], r["tile"], 100 * r["efficiency"]))
    L += ["", "![simulator](sim_efficiency.png)", ""]


def section_memory(res, L):
    mem = res["memory"]
    L += ["## Memory model", ""] + claim_lines("memory")
    L += ["Peak resident set of every rank (`getrusage`, bench/rss_wrap.py; `PVRT_HUGE_PAGES=0`), c = 1, one "
          "thread a rank, scene 1 (L = 5, B = 100).", "",
          "Slopes (bytes of peak RSS per pixel, least squares over the image sizes):", "",
          "| gather | ranks | who | bytes / pixel |", "|---|--:|---|--:|"]
    for x in mem["slopes"]:
        L.append("| %s | %d | %s | %s |" % (x["gather"], x["ranks"], x["who"], num(x["bytes_per_pixel"], "%.1f")))
    L += ["", "Per sphere (10^3..10^5 generated spheres, one rank, slopes): peak RSS %s bytes (loading the XML "
          "included), of which the BVH and light buffers `--stats` reports %s bytes; the paper: 96." % (
              num(mem.get("bytes_per_sphere"), "%.0f"), num(mem.get("structure_bytes_per_sphere"), "%.0f")), "",
          "All ranks together, above the smallest image's (the paper's image terms against pvrt's):", "",
          "| gather | ranks | image | measured B | paper B | ratio |", "|---|--:|---|--:|--:|--:|"]
    for x in mem["table"]:
        L.append("| %s | %d | %dx%d | %d | %d | %s |" % (x["gather"], x["ranks"], x["width"], x["height"],
                                                         x["measured_above_smallest_b"], x["paper_above_smallest_b"],
                                                         num(x["ratio"], "%.2f")))
    L += ["", "![memory](memory.png)", ""]


def busy_machine_warning(meta):
    """A warning when other work ran beside the runs: their times (not their counts) then mean little."""
    loads = [float(meta[k].split()[0]) for k in ("load average at start", "load average at end") if k in meta]
    if max(loads, default=0.0) <= 0.5:
        return []
    return ["**Warning: the machine was busy** (1-minute load average %s at the start and end): other work ran "
            "beside these runs, so their times, speedups and the model's errors are not this machine's; work counts, "
            "loads per rank, images and memory are unaffected. Run again on an idle machine." %
            " and ".join("%.2f" % v for v in loads), ""]


def write(a, meta, rows, ctx, res):
    L = ["# The paper's experiments, reproduced by pvrt", "",
         "Kadir & Khan, \"Parallel Ray Tracing using MPI and OpenMP\" (KTH). The paper's claims and their sources: "
         "bench/paper_claims.csv. Every run: runs.csv (logs in logs/).", "", "| | |", "|---|---|"]
    L += ["| %s | %s |" % kv for kv in meta.items()] + [""]
    L += busy_machine_warning(meta)
    L += ["## Figs. 4, 5: pixel load maps, c = 8 (log scale)", ""] + claim_lines("fig. 4") + claim_lines("fig. 5")
    L += ["![fig. 4](fig4_loadmap_scene1.png) ![fig. 5](fig5_loadmap_scene2.png)", ""]
    section_scaling(res, L, a)
    section_loads(res, L)
    L += ["## Fig. 10: scene 1 at c = %s, with a zoomed crop" % ", ".join(str(c) for c, _ in ctx["fig10"]), ""]
    L += claim_lines("fig. 10") + ["![fig. 10](fig10_images.png)", ""]
    section_gathers(ctx, L)
    section_openmp(res, L, a)
    section_table1(ctx, L, a)
    section_model(res, L, a)
    section_sim(res, L)
    section_memory(res, L)
    out = a.out
    write_csv(os.path.join(out, "model.csv"), res["model"])
    write_csv(os.path.join(out, "fig11_gather.csv"), ctx["bench"]["rows"])
    write_csv(os.path.join(out, "table1.csv"), ctx["table1"])
    write_csv(os.path.join(out, "memory.csv"), ctx["memory"])
    write_csv(os.path.join(out, "memory_model.csv"), res["memory"]["table"])
    write_csv(os.path.join(out, "medians.csv"), res["medians"])
    if res["sim"]:
        write_csv(os.path.join(out, "simulator.csv"), res["sim"]["rows"])
        write_csv(os.path.join(out, "simulator_check.csv"), res["sim"]["check"])
    paper_plots.all_plots(a, ctx, res)
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(L) + "\n")
