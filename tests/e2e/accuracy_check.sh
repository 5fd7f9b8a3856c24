#!/usr/bin/env bash
# Usage: accuracy_check.sh PVRT SCENE GOLDEN_PNG WORKDIR
# `pvrt accuracy` on a tiny image: the table's rows are the settings asked for, and the
# readings that have an exact answer have it (deterministic, no timing checks):
#   * c = 1 traces the pixel centre whatever the pattern, so pov, grid, jitter and the
#     adaptive patterns (POV-Ray's -A then) agree;
#   * jitter at the reference's own settings reproduces the reference: RMSE 0, PSNR inf;
#   * the pov pattern at POV-Ray's +R3 (c = 9) is within a level of POV-Ray's image;
#   * the quality variant's c is the square nearest c0 x P.
set -euo pipefail
pvrt=$1 scene=$2 golden=$3 work=$4
mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
csv=$work/accuracy.csv
"$pvrt" accuracy "$scene" --reference "$golden" --spp-list 1,9,16 --reference-spp 16 --reference-sampler jitter \
  --max-depth 2 --depth-spp 4 --threads 2 --csv "$csv" >"$work/accuracy.txt"
cat "$work/accuracy.txt"
head -1 "$csv" | grep -q '^mode,sampler,spp,depth,threads,rays_per_pixel,seconds,' || fail "CSV header"
[ "$(grep -c '^samples,' "$csv")" -eq 15 ] || fail "expected 15 samples rows (5 patterns x 3 c)"
[ "$(grep -c '^depth,' "$csv")" -eq 2 ] || fail "expected 2 depth rows"
grep -q '^depth,pov,4,1,' "$csv" && grep -q '^depth,pov,4,2,' "$csv" || fail "depth rows 1 and 2 at pov c=4"
col() { awk -F, -v m="$1" -v s="$2" -v c="$3" -v k="$4" '$1==m && $2==s && $3==c { print $k }' "$csv"; }
# columns: 14 rmse, 15 psnr, 16 share_over1, 17 golden_rmse
[ "$(col samples pov 1 14)" = "$(col samples grid 1 14)" ] || fail "pov and grid differ at c=1"
[ "$(col samples pov 1 14)" = "$(col samples jitter 1 14)" ] || fail "pov and jitter differ at c=1"
[ "$(col samples pov 1 14)" = "$(col samples adaptive1 1 14)" ] || fail "pov and adaptive1 differ at c=1"
[ "$(col samples pov 1 14)" = "$(col samples adaptive2 1 14)" ] || fail "pov and adaptive2 differ at c=1"
# +A0.3 traces fewer camera rays than +A0.0 at the same c (column 8: primary rays).
awk -v a="$(col samples adaptive1 9 8)" -v p="$(col samples pov 9 8)" 'BEGIN { exit !(a < p) }' ||
  fail "adaptive1 c=9 traced no fewer camera rays than pov"
[ "$(col samples jitter 16 14)" = "0.000000" ] || fail "jitter c=16 does not reproduce the reference"
[ "$(col samples jitter 16 15)" = "inf" ] || fail "PSNR of an exact match is not inf"
awk -v e="$(col samples pov 9 17)" 'BEGIN { exit !(e != "" && e < 1) }' || fail "pov c=9 is not POV-Ray's +R3 image"
[ -z "$(col samples grid 9 17)" ] || fail "golden error given for a non-pov row"
grep -q '^Equal time' "$work/accuracy.txt" && grep -q '^Equal error' "$work/accuracy.txt" || fail "readings"

"$pvrt" accuracy "$scene" -W 32 -H 20 --quality-variant --c0 4 --max-threads 3 --reference-spp 4 \
  --csv "$work/quality.csv" >/dev/null
[ "$(cut -d, -f1,3,5 "$work/quality.csv" | tail -n +2 | tr '\n' ' ')" = "quality,4,1 quality,9,2 quality,9,3 " ] ||
  fail "quality variant rows: $(cut -d, -f1,3,5 "$work/quality.csv" | tr '\n' ' ')"
echo PASS
