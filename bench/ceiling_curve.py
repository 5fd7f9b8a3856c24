#!/usr/bin/env python3
"""The machine's own parallel ceiling, CPU by CPU: independent single-thread renders, each pinned to a CPU.

Each round renders once on every CPU alone (one after the other), then on CPUs 0..k-1 at once for k = 2, 4, .. N.
If a CPU is slow alone, something outside the program (a neighbour on the host) takes it; if CPUs are fast alone and
slow together, they share something (a physical core, the memory bus, the clock); if which CPUs are slow changes from
round to round, the host moves its virtual CPUs about. No MPI and no threads of ours are involved.

    bench/ceiling_curve.py --pvrt PVRT --scene scenes/paper1.xml --csv OUT.csv [--rounds 6] [-W 320 -H 200 --spp 16]
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile


def main(argv):
    ap = argparse.ArgumentParser(prog="bench/ceiling_curve.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("--pvrt", required=True, help="pvrt (a binary or a wrapper script)")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("-W", type=int, default=320)
    ap.add_argument("-H", type=int, default=200)
    ap.add_argument("--spp", type=int, default=16)
    a = ap.parse_args(argv)
    cpus = sorted(os.sched_getaffinity(0))
    ks = sorted({k for k in (2 ** e for e in range(1, 12)) if k < len(cpus)} | {len(cpus)})
    rows = []
    with tempfile.TemporaryDirectory() as work:
        def start(cpu, tag):
            log = open(os.path.join(work, tag + ".log"), "w+")
            cmd = [a.pvrt, "render", a.scene, "-o", os.path.join(work, tag + ".png"), "-W", str(a.W), "-H", str(a.H),
                   "--sampler", "pov", "--spp", str(a.spp), "--threads", "1", "--stats", "--quiet"]
            return subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT,
                                    preexec_fn=lambda: os.sched_setaffinity(0, {cpu})), log

        def finish(proc, log):
            proc.wait()
            log.seek(0)
            m = re.search(r"render ([\d.]+) s", log.read())
            log.close()
            return float(m[1]) if m else None

        for rnd in range(a.rounds):
            for cpu in cpus:
                rows.append(dict(round=rnd, mode="alone", together=1, cpu=cpu,
                                 render_s=finish(*start(cpu, "alone%d" % cpu))))
            for k in ks:
                procs = [(cpu, start(cpu, "k%d_%d" % (k, cpu))) for cpu in cpus[:k]]
                for cpu, (p, log) in procs:
                    rows.append(dict(round=rnd, mode="together", together=k, cpu=cpu, render_s=finish(p, log)))
            with open(a.csv, "w", newline="") as f:
                w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
                w.writeheader()
                w.writerows(rows)
            alone = [r["render_s"] for r in rows if r["round"] == rnd and r["mode"] == "alone" and r["render_s"]]
            full = [r["render_s"] for r in rows if r["round"] == rnd and r["together"] == len(cpus) and r["render_s"]]
            print("ceiling curve round %d: alone %.3f-%.3f s, %d at once %.3f-%.3f s" % (
                rnd, min(alone), max(alone), len(cpus), min(full), max(full)), flush=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
