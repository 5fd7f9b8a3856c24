#!/usr/bin/env bash
# Usage: time_budget_passes.sh PVRT SCENE WORK_DIR
# --time-budget with the sequence sampler (its default) renders in passes and stops when the next
# would not fit: it prints the passes and the c reached, --stats-json lists each pass (the first of
# one sample, each starting where the last ended), and the image is bit for bit that of
# `--spp c --sampler sequence` in one go, on 1 thread and on 2 (and on 2 MPI ranks when mpirun is
# there). A budget the passes can fill goes past c = 1; and they end near it.
set -uo pipefail
pvrt=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
size=(-W 160 -H 100 --seed 3)
start=$(date +%s.%N)
out=$("$pvrt" render "$scene" -o "$work/budget.png" "${size[@]}" --time-budget 1.5 --threads 2 \
  --stats-json "$work/budget.json") || fail "budget render"
wall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')
echo "$out"
echo "$out" | grep -Eq '^time budget 1\.5 s: [0-9]+ passes of the sequence sampler reached --spp [0-9]+ \(render' \
  || fail "no passes line"
c=$(python3 - "$work/budget.json" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["time_budget"]
assert t["method"] == "passes" and t["budget_seconds"] == 1.5, t
p = t["passes"]
assert p[0]["first_sample"] == 0 and p[0]["end_sample"] == 1, p[0]
for a, b in zip(p, p[1:]):
    assert b["first_sample"] == a["end_sample"] and b["end_sample"] > b["first_sample"], (a, b)
assert t["chosen_spp"] == p[-1]["end_sample"]
print(t["chosen_spp"])
PY
) || fail "stats json"
echo "c = $c, wall $wall s"
[ "$c" -gt 1 ] || fail "a 1.5 s budget for 160 x 100 stopped at c = 1"
# Not a timing test: only a run that ignored the budget altogether (twice over) fails.
awk -v w="$wall" 'BEGIN { exit !(w < 3.0) }' || fail "took $wall s for a 1.5 s budget"
for threads in 1 2; do
  "$pvrt" render "$scene" -o "$work/once$threads.png" "${size[@]}" --spp "$c" --sampler sequence \
    --threads $threads -q || fail "--spp $c"
  cmp "$work/budget.png" "$work/once$threads.png" || fail "passes differ from --spp $c on $threads thread(s)"
done
if command -v mpirun >/dev/null; then
  mpirun --allow-run-as-root --oversubscribe --bind-to none -np 2 "$pvrt" render "$scene" -o "$work/mpi.png" \
    "${size[@]}" --spp "$c" --sampler sequence --backend mpi --threads 1 -q || fail "mpi"
  cmp "$work/budget.png" "$work/mpi.png" || fail "passes differ from --spp $c on 2 MPI ranks"
fi
echo PASS
