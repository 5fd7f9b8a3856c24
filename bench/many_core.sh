#!/usr/bin/env bash
# The parallel-scaling measurements on a borrowed many-core machine where nothing of ours
# is installed: pvrt, mpirun and their libraries travel as a bundle
# (../shared/tools/bundle.sh BUILD BUNDLE, or any folder with pvrt.sh and mpirun.sh that
# start them), python3 is the only other need (matplotlib for the plot, if there).
#   bench/many_core.sh BUNDLE OUT [--quick|--full] [PARTS]
# PARTS, run in the order given: big, mpibench, ceilingcurve, mpistart, scaling (default
# scaling,mpibench,big,ceilingcurve,mpistart). BIG_THREADS, BIG_ROUNDS: the big part's thread counts and rounds.
# DEADLINE=S stops the scaling part S seconds after the start, keeping the rounds it finished (the runs' CSV is
# rewritten after every run), so a borrowed machine's time limit loses no finished measurement.
# SCALING_ARGS replaces the arguments given to bench/speedup.py (e.g. a --select of a few
# configurations); MPIBENCH_RANKS lists the rank counts of mpi-bench (default 2 4 8 .. N).
# Writes to OUT (8 files, as many as a borrowed machine's return may hold): machine.txt (CPUs, topology),
# scaling.md / scaling_runs.csv / scaling_summary.csv (bench/speedup.py: OpenMP schedules, MPI strategies and
# gathers, hybrid splits, the machine's ceiling, the c=256 setting), mpibench.csv (pvrt
# mpi-bench at 2..N ranks), big.csv (the 10^6-sphere scene's stages and peak memory on 1 and
# N threads; with BUNDLE/pvrt-base.sh, that build's too), ceilingcurve.csv (bench/ceiling_curve.py: each CPU
# alone, then 2, 4 .. N at once, pinned), mpirun's own start cost (appended to machine.txt) and logs.tgz.
set -uo pipefail
bundle=$(cd "${1:?BUNDLE}" && pwd)
out=${2:?OUT}
quick=${3:-}
parts=${4:-scaling,mpibench,big,ceilingcurve,mpistart}
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
part_scaling() {
  say "scaling (bench/speedup.py ${scaling[*]})"
  local limit=()
  [ -n "${DEADLINE:-}" ] && limit=(timeout --signal=INT "$((DEADLINE - ($(date +%s) - started)))")
  "${limit[@]}" python3 "$root/bench/speedup.py" --pvrt "$pvrt" --mpirun "$mpirun" --out "$work/scaling" \
    "${scaling[@]}" | { grep -vE '^  (openmp|mpi|hybrid|alone|fig1)' || true; }
  [ "${PIPESTATUS[0]}" = 0 ] || say "scaling stopped early or failed: the runs' CSV holds what finished"
  for f in scaling.md scaling_runs.csv scaling_summary.csv; do  # scaling.png travels in logs.tgz
    cp "$work/scaling/$f" "$out/" 2>/dev/null
  done
}

part_mpibench() {
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
}

# Independent single-thread renders pinned to CPUs: each CPU alone, then 2, 4 .. N at once (bench/ceiling_curve.py).
part_ceilingcurve() {
  say "ceiling curve: each CPU alone, then 2..$n at once"
  python3 "$root/bench/ceiling_curve.py" --pvrt "$pvrt" --scene "$root/scenes/paper1.xml" --csv "$out/ceilingcurve.csv" \
    --rounds "${CEILING_ROUNDS:-6}"
}

# What mpirun costs before and after the ranks' work: N ranks that only print their version (no MPI_Init), N ranks
# rendering a 16 x 10 image (MPI_Init, the scene, the gather, MPI_Finalize), and one process rendering it.
part_mpistart() {
  say "mpirun's own cost at $n ranks"
  local r t0
  since() { awk -v a="$1" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.4f", b - a }'; }
  echo "round,what,wall_s" >"$work/mpistart.csv"
  for ((r = 0; r < 5; r++)); do
    t0=$EPOCHREALTIME; "$mpirun" --bind-to none -np "$n" "$pvrt" --version >/dev/null 2>&1
    echo "$r,mpirun -np $n pvrt --version,$(since "$t0")" >>"$work/mpistart.csv"
    t0=$EPOCHREALTIME; "$mpirun" --bind-to none -np "$n" "$pvrt" render "$root/scenes/paper1.xml" -o "$work/ms.png" \
      -W 16 -H 10 --backend mpi --quiet >/dev/null 2>&1
    echo "$r,mpirun -np $n pvrt render 16x10 mpi,$(since "$t0")" >>"$work/mpistart.csv"
    t0=$EPOCHREALTIME; "$pvrt" render "$root/scenes/paper1.xml" -o "$work/ms.png" -W 16 -H 10 --quiet >/dev/null 2>&1
    echo "$r,pvrt render 16x10 one process,$(since "$t0")" >>"$work/mpistart.csv"
  done
  cat "$work/mpistart.csv" >>"$out/machine.txt"
}

part_big() {
say "$spheres spheres: load, build, render, write, peak memory on 1 and $n threads"
"$pvrt" generate --spheres "$spheres" --lights 5 --seed 3 -o "$work/big.xml" >/dev/null
# With BUNDLE/pvrt-base.sh (an earlier build), N-thread runs of both alternate, to set a change against its base.
python3 - "$pvrt" "$work" "$n" "$out/big.csv" "${BIG_THREADS:-1 $n}" <<'PY'
import os, re, subprocess, sys
pvrt, work, n, csv, threads = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5].split()
base = os.path.join(os.path.dirname(pvrt), "pvrt-base.sh")
binaries = [("new", pvrt)] + ([("base", base)] if os.path.exists(base) else [])
plan = []
for rnd in range(int(os.environ.get("BIG_ROUNDS", "2"))):
    for t in (threads if rnd % 2 == 0 else threads[::-1]):
        for name, exe in (binaries if rnd % 2 == 0 else binaries[::-1]):
            plan.append((rnd, int(t), name, exe))
rows = []
for rnd, t, name, exe in plan:
    log = open(os.path.join(work, "big-%s-t%d-r%d.log" % (name, t, rnd)), "w+")
    p = subprocess.Popen([exe, "render", os.path.join(work, "big.xml"), "-o", os.path.join(work, "big.png"),
                          "-W", "1280", "-H", "800", "--spp", "1", "--threads", str(t), "--stats", "--quiet"],
                         stdout=log, stderr=subprocess.STDOUT)
    _, status, usage = os.wait4(p.pid, 0)
    log.seek(0)
    text = log.read()
    m = re.search(r"load ([\d.]+) s, build ([\d.]+) s, render ([\d.]+) s, write ([\d.]+) s", text)
    bvh = re.search(r"BVH .* built in ([\d.]+) s", text)
    lb = re.search(r"Light buffers .* built in ([\d.]+) s", text)
    # Each stage's CPU time and the cores it kept busy (builds before ed28ef9 do not print it).
    cpu = re.search(r"CPU time\s+load ([\d.]+) s \(([\d.]+) cores\), build ([\d.]+) s \(([\d.]+)\)", text)
    row = dict(binary=name, threads=t, run=rnd, rc=os.waitstatus_to_exitcode(status),
               peak_rss_mib=usage.ru_maxrss / 1024,
               load_s=m and m[1], build_s=m and m[2], render_s=m and m[3], write_s=m and m[4],
               bvh_s=bvh and bvh[1], light_buffers_s=lb and lb[1],
               load_cpu_s=cpu and cpu[1], load_cores=cpu and cpu[2], build_cpu_s=cpu and cpu[3],
               build_cores=cpu and cpu[4])
    print(row, flush=True)
    rows.append(row)
with open(csv, "w") as f:
    f.write(",".join(rows[0]) + "\n")
    for r in rows:
        f.write(",".join(str(v) for v in r.values()) + "\n")
PY
rm -f "$work/big.xml"
}

for part in ${parts//,/ }; do
  case $part in
    scaling | mpibench | big | ceilingcurve | mpistart) "part_$part" ;;
    *) echo "many_core.sh: unknown part '$part' (scaling, mpibench, big, ceilingcurve, mpistart)" >&2; exit 2 ;;
  esac
done
rm -f "$work/scaling/speedup-image.png"
tar czf "$out/logs.tgz" -C "$work" . 2>/dev/null
say "done"
