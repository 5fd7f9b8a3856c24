#!/usr/bin/env bash
# Usage: bench_smoke.sh PVRT OUT_DIR (OUT_DIR absolute)
# The benchmark suite runs end to end in --quick mode and writes its tables. No timing is
# checked: the numbers of a quick run on a busy machine mean nothing.
set -euo pipefail
pvrt=$1 out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$out"
# --pvrt as a user types it from the folder above the build: a relative path (build/pvrt).
bindir=$(cd "$(dirname "$pvrt")" && pwd)
cd "$(dirname "$bindir")"
"$root/bench/run.sh" --quick --pvrt "$(basename "$bindir")/$(basename "$pvrt")" --out "$out"
fail() { echo "FAIL: $*"; exit 1; }
for f in results.csv summary.csv results.md; do [ -s "$out/$f" ] || fail "$f not written"; done
head -1 "$out/results.csv" | grep -q '^experiment,scene,objects,renderer,run,threads,' || fail "results.csv header"
for scene in paper1 paper2 paper1_noreflection glass100 spheres_100 spheres_1000; do
  grep -q "^[a-z]*,$scene,[0-9]*,pvrt,0,[0-9]*,160,100,4,ok," "$out/results.csv" || fail "no pvrt run of $scene"
  if command -v povray >/dev/null; then
    grep -q "^[a-z]*,$scene,[0-9]*,povray,0,.*,ok," "$out/results.csv" || fail "no POV-Ray run of $scene"
  fi
done
for f in scaling_runs.csv scaling_summary.csv scaling.md; do [ -s "$out/$f" ] || fail "$f not written"; done
grep -q '^openmp,openmp tiles P=1,openmp,tiles,,1,1,1,0,' "$out/scaling_runs.csv" || fail "no one-thread scaling run"
if command -v mpirun >/dev/null; then
  grep -q '^mpi,mpi dynamic gather P=1,mpi,dynamic,gather,1,1,1,0,.*,ok,' "$out/scaling_runs.csv" || fail "no MPI scaling run"
fi
for heading in '## Scenes' '## Random scenes' '## pvrt: rays by kind' '## Parallel scaling' '### OpenMP threads'; do
  grep -q "^$heading" "$out/results.md" || fail "results.md lacks \"$heading\""
done
echo PASS
