#!/usr/bin/env python3
"""How close `pvrt render --time-budget B` comes to B: the table of docs/design.md (issue 27, item 2).

    bench/time_budget.py [--pvrt build/pvrt] [--out DIR] [--budgets 2,5,10,30,60] [--threads 1,2]
                         [--sampler sequence|jitter|pov|grid]

For each budget, scene (paper1, paper2, and 10^5 random spheres from `pvrt generate --spheres 100000
--lights 5 --seed 7`, all at 1280 x 800) and thread count, one run: the whole process's wall time (start to
exit, what the budget covers, writing the PNG included) and its user CPU time, the c chosen, the render time
predicted and taken (from --stats-json). With the sequence sampler (the default with a budget) the render
goes in passes (render/passes.h): the table gives their number (no prediction of the whole); with the
others, the pilots. Writes DIR/time_budget.csv and DIR/time_budget.md. The machine's
load average is recorded before each run: other programs on the machine take CPU time from pvrt's
threads, so the wall times hold for that load only.
"""
import argparse
import csv
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import pvrt_stats  # noqa: E402

FIELDS = ["budget_s", "scene", "threads", "sampler", "wall_s", "user_s", "wall_over_budget", "chosen_spp", "pilots",
          "pilot_s", "passes", "predicted_render_s", "render_s", "load_s", "build_s", "write_s", "load_average", "status"]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pvrt", default=os.path.join(ROOT, "build", "pvrt"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "time-budget-" + time.strftime("%Y%m%d-%H%M%S")))
    ap.add_argument("--budgets", default="2,5,10,30,60")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--sampler", default="", help="--sampler for pvrt (default: none, so sequence and passes)")
    a = ap.parse_args(argv)
    a.pvrt = os.path.abspath(a.pvrt)
    os.makedirs(a.out, exist_ok=True)
    spheres = os.path.join(a.out, "spheres_100000.xml")
    if not os.path.exists(spheres):
        subprocess.run([a.pvrt, "generate", "--spheres", "100000", "--lights", "5", "--seed", "7", "-o", spheres],
                       check=True, stdout=subprocess.DEVNULL)
    scenes = {"paper1": os.path.join(ROOT, "scenes", "paper1.xml"), "paper2": os.path.join(ROOT, "scenes", "paper2.xml"),
              "spheres_1e5": spheres}
    rows = []
    csv_path = os.path.join(a.out, "time_budget.csv")
    for budget in [float(b) for b in a.budgets.split(",")]:
        for scene, path in scenes.items():
            for threads in [int(t) for t in a.threads.split(",")]:
                json_path = os.path.join(a.out, "run.json")
                cmd = [a.pvrt, "render", path, "-o", os.path.join(a.out, "image.png"), "--time-budget", "%g" % budget,
                       "--threads", str(threads), "--quiet", "--stats-json", json_path]
                if a.sampler:
                    cmd += ["--sampler", a.sampler]
                load = os.getloadavg()[0]
                start = time.perf_counter()
                p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL)
                _, status, usage = os.wait4(p.pid, 0)
                wall = time.perf_counter() - start
                rc = os.waitstatus_to_exitcode(status)
                st = pvrt_stats.read(json_path) if rc == 0 else {}
                tb = st.get("time_budget", {})
                sec = st.get("seconds", {})
                row = dict(budget_s=budget, scene=scene, threads=threads, sampler=a.sampler or "sequence",
                           passes=len(tb.get("passes", [])), wall_s="%.3f" % wall,
                           user_s="%.3f" % usage.ru_utime, wall_over_budget="%.3f" % (wall / budget),
                           chosen_spp=tb.get("chosen_spp", ""), pilots=len(tb.get("pilots", [])),
                           pilot_s="%.3f" % tb.get("pilot_seconds", 0),
                           predicted_render_s="%.3f" % tb.get("predicted_render_seconds", 0),
                           render_s="%.3f" % sec.get("render", 0), load_s="%.3f" % sec.get("load", 0),
                           build_s="%.3f" % sec.get("build", 0), write_s="%.3f" % sec.get("write", 0),
                           load_average="%.2f" % load, status="ok" if rc == 0 else "exit %d" % rc)
                rows.append(row)
                print("budget %5.1f s  %-12s %d thread(s): wall %7.3f s (%.2f of the budget), user %7.3f s, c=%s" % (
                    budget, scene, threads, wall, wall / budget, usage.ru_utime, row["chosen_spp"]), flush=True)
                with open(csv_path, "w", newline="") as f:  # after every run: a partial table survives
                    w = csv.DictWriter(f, fieldnames=FIELDS)
                    w.writeheader()
                    w.writerows(rows)
    with open(os.path.join(a.out, "time_budget.md"), "w") as f:
        f.write("| budget s | scene | threads | c | wall s | wall / budget | user s | passes, or pilots (s) "
                "| predicted render s | render s | load avg |\n|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            how = "%s passes" % r["passes"] if r["passes"] else "%s (%s)" % (r["pilots"], r["pilot_s"])
            predicted = r["predicted_render_s"] if not r["passes"] else "-"
            f.write("| %g | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s |\n" % (
                r["budget_s"], r["scene"], r["threads"], r["chosen_spp"], r["wall_s"], r["wall_over_budget"],
                r["user_s"], how, predicted, r["render_s"], r["load_average"]))
    print("wrote %s and time_budget.md" % csv_path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
