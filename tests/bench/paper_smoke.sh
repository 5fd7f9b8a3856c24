#!/usr/bin/env bash
# Usage: paper_smoke.sh PVRT OUT_DIR
# bench/paper.sh --quick writes every figure, CSV and the report, and the model's and the simulator's
# predictions are finite. Skips (77) without mpirun or a python3 with numpy and matplotlib.
set -euo pipefail
pvrt=$1 out=$2
root=$(cd "$(dirname "$0")/../.." && pwd)
command -v mpirun >/dev/null || { echo "SKIP: no mpirun"; exit 77; }
command -v oiiotool >/dev/null || { echo "SKIP: no oiiotool"; exit 77; }
py=${PVRT_PYTHON:-/usr/bin/python3}
"$py" -c 'import numpy, matplotlib' 2>/dev/null || { echo "SKIP: $py lacks numpy or matplotlib"; exit 77; }
rm -rf "$out"
PVRT_PYTHON=$py "$root/bench/paper.sh" --quick --max-p 2 --pvrt "$pvrt" --out "$out"
fail() { echo "FAIL: $*"; exit 1; }
for f in report.md runs.csv medians.csv model.csv fig11_gather.csv table1.csv memory.csv memory_model.csv \
         simulator.csv simulator_check.csv fig4_loadmap_scene1.png fig5_loadmap_scene2.png fig6_speedup.png \
         fig7_8_loads.png fig9_ratio.png fig10_images.png fig11_gather.png fig12_schedules.png fig13_constant.png \
         model_error.png sim_efficiency.png memory.png; do
  [ -s "$out/$f" ] || fail "$f not written"
done
for heading in '## Figs. 4, 5' '## Fig. 6' '## Fig. 9' '## Figs. 7, 8' '## Fig. 10' '## Fig. 11' '## Fig. 12' \
               '## Fig. 13' '## Table 1' '## The performance model' '## Load-balance simulator' '## Memory model'; do
  grep -q "^$heading" "$out/report.md" || fail "report.md lacks \"$heading\""
done
grep -q '^| commit | [0-9a-f]' "$out/report.md" || fail "report.md lacks the commit"
grep -q '^| CPU | ' "$out/report.md" || fail "report.md lacks the machine"
! grep -q ',failed' "$out/runs.csv" || fail "a run failed: $(grep ',failed' "$out/runs.csv" | head -3)"
# Figs. 7, 8: the per-rank work pvrt counts is the load map's split by pvrt's own cut, exactly (4 rows).
[ "$(grep -cE '^\| scene[12] \| (block|cyclic) \| .* \| exactly \|$' "$out/report.md")" -eq 4 ] \
  || fail "figs. 7, 8: the map's split does not match the ranks' work: $(grep -E '^\| scene[12] \| (block|cyclic) \|' "$out/report.md")"
"$py" - "$out" <<'PY'
import csv, math, sys
out = sys.argv[1]
def finite(path, fields, least):
    rows = list(csv.DictReader(open(f"{out}/{path}")))
    if len(rows) < least:
        sys.exit(f"FAIL: {path} has {len(rows)} rows, expected at least {least}")
    for r in rows:
        for f in fields:
            v = float(r[f])
            if not math.isfinite(v) or v < 0:
                sys.exit(f"FAIL: {path}: {f} = {r[f]} in {r}")
    return rows
# fig. 9 (2 scenes x 2 backends x 2 strategies x P 1..2), fig. 13 (2 x 2), the simulator's MPI runs (2 x 2).
model = finite("model.csv", ["pred_s", "measured_s", "pred_ceiling_s"], 24)
for r in model:
    if not math.isfinite(float(r["error"])):
        sys.exit(f"FAIL: model error {r}")
sim = finite("simulator.csv", ["time_s", "speedup", "efficiency"], 10)
ranks = {int(r["ranks"]) for r in sim}
if max(ranks) < 64 or {"block", "cyclic", "tiles", "dynamic"} - {r["strategy"] for r in sim}:
    sys.exit("FAIL: the simulator lacks a strategy or P = 64")
finite("simulator_check.csv", ["simulated_s", "measured_s"], 4)
for r in csv.DictReader(open(f"{out}/simulator_check.csv")):
    if not math.isfinite(float(r["error_ceiling"])):
        sys.exit(f"FAIL: simulator check {r}")
finite("memory_model.csv", ["paper_b", "measured_total_b"], 2)
print("model rows", len(model), "simulator rows", len(sim))
PY
echo PASS
