#!/usr/bin/env bash
# Usage: many_core_smoke.sh PVRT OUT_DIR
# bench/many_core.sh, the script that measures scaling on a borrowed many-core machine, runs end to end in
# --quick mode on this one, through a bundle folder of wrappers as ../shared/tools/bundle.sh makes them, and writes
# its 8 files. It runs where no test can reach it otherwise (CI never has such a machine), so a broken part
# would only be found there, at the cost of the machine's time. No timing is checked.
set -euo pipefail
pvrt=$(cd "$(dirname "$1")" && pwd)/$(basename "$1") out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$out"
mkdir -p "$out/bundle"
printf '#!/bin/sh\nexec %s "$@"\n' "$pvrt" >"$out/bundle/pvrt.sh"
cp "$out/bundle/pvrt.sh" "$out/bundle/pvrt-base.sh"
printf '#!/bin/sh\nexec mpirun --allow-run-as-root --oversubscribe "$@"\n' >"$out/bundle/mpirun.sh"
chmod +x "$out/bundle/"*.sh
CEILING_ROUNDS=1 BIG_ROUNDS=1 "$root/bench/many_core.sh" "$out/bundle" "$out/result" --quick \
  big,ceilingcurve,mpistart,mpibench,scaling
fail() { echo "FAIL: $*"; exit 1; }
r=$out/result
for f in machine.txt big.csv ceilingcurve.csv mpibench.csv scaling.md scaling_runs.csv scaling_summary.csv logs.tgz; do
  [ -s "$r/$f" ] || fail "$f not written"
done
[ "$(find "$r" -type f | wc -l)" -le 8 ] || fail "more than the 8 files a borrowed machine's return may hold"
grep -q '^new,[0-9]*,0,0,' "$r/big.csv" || fail "no run of the new build in big.csv"
grep -q '^base,[0-9]*,0,0,' "$r/big.csv" || fail "no run of the base build in big.csv"
grep -q '^0,alone,1,[0-9]*,[0-9.]*$' "$r/ceilingcurve.csv" || fail "no CPU alone in ceilingcurve.csv"
grep -q '^0,together,[0-9]*,[0-9]*,[0-9.]*$' "$r/ceilingcurve.csv" || fail "no CPUs together in ceilingcurve.csv"
grep -q 'mpirun -np [0-9]* pvrt render 16x10 mpi,[0-9.]*$' "$r/machine.txt" || fail "no mpirun start cost"
grep -q '^pingpong-one-way,' "$r/mpibench.csv" || fail "no ping-pong in mpibench.csv"
grep -q '^ceiling,alone,' "$r/scaling_runs.csv" || fail "no ceiling in the scaling rounds"
grep -q '^\*\*Ceiling\*\*' "$r/scaling.md" || fail "scaling.md lacks the ceiling"
echo PASS
