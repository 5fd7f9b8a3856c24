#!/usr/bin/env bash
# The parallel-scaling measurements on a borrowed many-core machine where nothing of ours
# is installed: pvrt, mpirun and their libraries travel as a bundle
# (../shared/tools/bundle.sh BUILD BUNDLE, or any folder with pvrt.sh and mpirun.sh that
# start them), python3 is the only other need (matplotlib for the plot, if there).
#   bench/many_core.sh BUNDLE OUT [--quick|--full] [PARTS]   (PARTS: scaling,mpibench,big; default all)
# SCALING_ARGS replaces the arguments given to bench/speedup.py (e.g. a --select of a few
# configurations); MPIBENCH_RANKS lists the rank counts of mpi-bench (default 2 4 8 .. N).
# Writes to OUT (8 files): machine.txt (CPUs, topology), scaling.md / scaling_runs.csv /
# scaling_summary.csv / scaling.png (bench/speedup.py: OpenMP schedules, MPI strategies and
# gathers, hybrid splits, the machine's ceiling, the c=256 setting), mpibench.csv (pvrt
# mpi-bench at 2..N ranks), big.csv (the 10^6-sphere scene's stages and peak memory on 1 and
# N threads) and logs.tgz (every run's output).
set -uo pipefail
bundle=$(cd "${1:?BUNDLE}" && pwd)
out=${2:?OUT}
quick=${3:-}
parts=${4:-scaling,mpibench,big}
has() { [[ ",$parts," == *",$1,"* ]]; }
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pvrt=$bundle/pvrt.sh mpirun=$bundle/mpirun.sh
n=$(nproc)
started=$(date +%s)
say() { echo "[$(($(date +%s) - started)) s] $*"; }

{
  echo "nproc $n"; grep -m1 'model name' /proc/cpuinfo; uname -a; grep -E 'MemTotal' /proc/meminfo
  command -v lscpu >/dev/null && lscpu
  for c in /sys/devices/system/cpu/cpu[0-9]*; do
    echo "$(basename "$c") core $(cat "$c/topology/core_id" 2>/dev/null) package $(cat "$c/topology/physical_package_id" 2>/dev/null) siblings $(cat "$c/topology/thread_siblings_list" 2>/dev/null) MHz $(cat "$c/cpufreq/scaling_cur_freq" 2>/dev/null)"
  done
  grep -m1 -i 'cpu MHz' /proc/cpuinfo
} >"$out/machine.txt" 2>&1

say "smoke: one process, then 2 MPI ranks"
"$pvrt" render "$root/scenes/paper1.xml" -o "$work/smoke.png" -W 64 -H 40 --stats | grep -E 'Backend|Time'
"$mpirun" --bind-to none -np 2 "$pvrt" render "$root/scenes/paper1.xml" -o "$work/smoke2.png" -W 64 -H 40 \
  --backend mpi --stats | grep -E 'Backend|Time'

if [ "$quick" = --quick ]; then
  scaling=(--quick --max-p "$n" --only ceiling,openmp,mpi,hybrid,fig1 --fig1-spp 9 --fig1-runs 1)
  spheres=20000 reps=3 bench8k=--no-8k
else
  scaling=(--runs 5 --max-p "$n" --only ceiling,openmp,mpi,hybrid,fig1)
  spheres=1000000 reps=20 bench8k=${MPIBENCH_8K-}
fi
[ -n "${SCALING_ARGS:-}" ] && eval "scaling=($SCALING_ARGS)"
mkdir -p "$work/scaling"
if has scaling; then
  say "scaling (bench/speedup.py ${scaling[*]})"
  python3 "$root/bench/speedup.py" --pvrt "$pvrt" --mpirun "$mpirun" --out "$work/scaling" "${scaling[@]}" |
    grep -vE '^  (openmp|mpi|hybrid|alone|fig1)' || true
  cp "$work/scaling/"scaling.md "$work/scaling/"scaling_runs.csv "$work/scaling/"scaling_summary.csv "$out/"
  cp "$work/scaling/scaling.png" "$out/" 2>/dev/null
fi

if has mpibench; then
  say "mpi-bench at 2..$n ranks"
  ranks=${MPIBENCH_RANKS:-}
  if [ -z "$ranks" ]; then
    for ((p = 2; p <= n; p *= 2)); do ranks="$ranks $p"; done
  fi
  for p in $ranks; do
    "$mpirun" --bind-to none -np "$p" "$pvrt" mpi-bench --reps "$reps" $bench8k --csv "$work/mpibench-$p.csv" \
      >"$work/mpibench-$p.log" 2>&1 || say "mpi-bench at $p ranks failed"
  done
  first=1
  for f in "$work"/mpibench-*.csv; do
    if [ "$first" = 1 ]; then cat "$f" >"$out/mpibench.csv"; first=0; else tail -n +2 "$f" >>"$out/mpibench.csv"; fi
  done
fi

has big || { tar czf "$out/logs.tgz" -C "$work" . 2>/dev/null; say "done"; exit 0; }
say "$spheres spheres: load, build, render, write, peak memory on 1 and $n threads"
"$pvrt" generate --spheres "$spheres" --lights 5 --seed 3 -o "$work/big.xml" >/dev/null
python3 - "$pvrt" "$work" "$n" "$out/big.csv" <<'PY'
import os, re, subprocess, sys
pvrt, work, n, csv = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
rows = []
for rnd in range(2):
    for t in ([1, n] if rnd % 2 == 0 else [n, 1]):
        log = open(os.path.join(work, "big-t%d-r%d.log" % (t, rnd)), "w+")
        p = subprocess.Popen([pvrt, "render", os.path.join(work, "big.xml"), "-o", os.path.join(work, "big.png"),
                              "-W", "1280", "-H", "800", "--spp", "1", "--threads", str(t), "--stats", "--quiet"],
                             stdout=log, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(p.pid, 0)
        log.seek(0)
        text = log.read()
        m = re.search(r"load ([\d.]+) s, build ([\d.]+) s, render ([\d.]+) s, write ([\d.]+) s", text)
        bvh = re.search(r"BVH .* built in ([\d.]+) s", text)
        lb = re.search(r"Light buffers .* built in ([\d.]+) s", text)
        row = dict(threads=t, run=rnd, rc=os.waitstatus_to_exitcode(status), peak_rss_mib=usage.ru_maxrss / 1024,
                   load_s=m and m[1], build_s=m and m[2], render_s=m and m[3], write_s=m and m[4],
                   bvh_s=bvh and bvh[1], light_buffers_s=lb and lb[1])
        print(row, flush=True)
        rows.append(row)
with open(csv, "w") as f:
    f.write(",".join(rows[0]) + "\n")
    for r in rows:
        f.write(",".join(str(v) for v in r.values()) + "\n")
PY
rm -f "$work/big.xml"
tar czf "$out/logs.tgz" -C "$work" . 2>/dev/null
say "done"
