#!/usr/bin/env bash
# Usage: bench_smoke.sh PVRT OUT_DIR
# The benchmark suite runs end to end in --quick mode and writes its tables. No timing is
# checked: the numbers of a quick run on a busy machine mean nothing.
set -euo pipefail
pvrt=$1 out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
rm -rf "$out"
"$root/bench/run.sh" --quick --pvrt "$pvrt" --out "$out"
fail() { echo "FAIL: $*"; exit 1; }
for f in results.csv summary.csv results.md; do [ -s "$out/$f" ] || fail "$f not written"; done
head -1 "$out/results.csv" | grep -q '^experiment,scene,objects,renderer,run,threads,' || fail "results.csv header"
for scene in paper1 paper2 paper1_noreflection glass100 spheres_100 spheres_1000; do
  grep -q "^[a-z]*,$scene,[0-9]*,pvrt,0,[0-9]*,160,100,4,ok," "$out/results.csv" || fail "no pvrt run of $scene"
  if command -v povray >/dev/null; then
    grep -q "^[a-z]*,$scene,[0-9]*,povray,0,.*,ok," "$out/results.csv" || fail "no POV-Ray run of $scene"
  fi
done
grep -q '^speedup,paper1,[0-9]*,pvrt,0,1,' "$out/results.csv" || fail "no one-thread speedup run"
for heading in '## Scenes' '## Random scenes' '## pvrt: rays by kind' '## pvrt parallel speedup'; do
  grep -q "^$heading" "$out/results.md" || fail "results.md lacks \"$heading\""
done
echo PASS
