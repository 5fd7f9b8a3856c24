#!/usr/bin/env bash
# The parallel-scaling measurements on a borrowed many-core machine where nothing of ours
# is installed: pvrt, mpirun and their libraries travel as a bundle
# (../shared/tools/bundle.sh BUILD BUNDLE, or any folder with pvrt.sh and mpirun.sh that
# start them), python3 is the only other need (matplotlib for the plot, if there).
#   bench/many_core.sh BUNDLE OUT [--quick|--full] [PARTS]
# PARTS, run in the order given: big, mpibench, ceilingcurve, scaling (default scaling,mpibench,big,ceilingcurve).
# DEADLINE=S stops the scaling part S seconds after the start, keeping the rounds it finished (the runs' CSV is
# rewritten after every run), so a borrowed machine's time limit loses no finished measurement.
# SCALING_ARGS replaces the arguments given to bench/speedup.py (e.g. a --select of a few
# configurations); MPIBENCH_RANKS lists the rank counts of mpi-bench (default 2 4 8 .. N).
# Writes to OUT (8 files, as many as a borrowed machine's return may hold): machine.txt (CPUs, topology),
# scaling.md / scaling_runs.csv / scaling_summary.csv (bench/speedup.py: OpenMP schedules, MPI strategies and
# gathers, hybrid splits, the machine's ceiling, the c=256 setting), mpibench.csv (pvrt
# mpi-bench at 2..N ranks), big.csv (the 10^6-sphere scene's stages and peak memory on 1 and
# N threads), ceilingcurve.csv (1, 2, 4, .. N independent single-thread renders at once: where the machine's own
# slow-down sets in) and logs.tgz (every run's output).
set -uo pipefail
bundle=$(cd "${1:?BUNDLE}" && pwd)
out=${2:?OUT}
quick=${3:-}
parts=${4:-scaling,mpibench,big,ceilingcurve}
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

# k independent single-thread renders at once for k = 1, 2, 4 .. N, `reps` rounds: each one's render stage. If the
# slow-down appears only past N/2, busy CPUs share physical cores; if it grows steadily, clock or memory.
part_ceilingcurve() {
  say "ceiling curve: 1..$n independent single-thread renders at once"
  local ks="" k r j
  for ((k = 1; k < n; k *= 2)); do ks="$ks $k"; done
  ks="$ks $n"
  echo "round,together,index,render_s" >"$out/ceilingcurve.csv"
  for ((r = 0; r < 3; r++)); do
    for k in $ks; do
      for ((j = 0; j < k; j++)); do
        "$pvrt" render "$root/scenes/paper1.xml" -o "$work/cc-$j.png" -W 640 -H 400 --sampler pov --spp 16 \
          --threads 1 --stats --quiet >"$work/cc-$r-$k-$j.log" 2>&1 &
      done
      wait
      for ((j = 0; j < k; j++)); do
        t=$(sed -nE 's/.*render ([0-9.]+) s.*/\1/p' "$work/cc-$r-$k-$j.log" | head -1)
        echo "$r,$k,$j,$t" >>"$out/ceilingcurve.csv"
      done
    done
  done
  rm -f "$work"/cc-*.png
}

part_big() {
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
}

for part in ${parts//,/ }; do
  case $part in
    scaling | mpibench | big | ceilingcurve) "part_$part" ;;
    *) echo "many_core.sh: unknown part '$part' (scaling, mpibench, big, ceilingcurve)" >&2; exit 2 ;;
  esac
done
rm -f "$work/scaling/speedup-image.png"
tar czf "$out/logs.tgz" -C "$work" . 2>/dev/null
say "done"
