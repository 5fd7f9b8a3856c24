#!/usr/bin/env bash
# How far pvrt's renders are from POV-Ray's references, over the whole golden corpus, in
# one command (docs/fidelity.md quotes its totals):
#   tools/golden-census.sh [BUILD] [SCENE-REGEX]
# Renders every reference of reference/manifest.tsv as the golden tests do (same size,
# samples and sampler), compares it with the reference, and prints for each image the
# channels that differ by 1 level, by more than 1, and the largest difference; then the
# totals for the corpus that predates issue 26 (every scene but fidelity_*) and for the
# fidelity_* scenes apart. Images are the same whatever the backend, so one is enough.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
only=${2:-.}
pvrt=$build/pvrt
[ -x "$pvrt" ] || { echo "golden-census.sh: no $pvrt; build the pvrt target first" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

printf '%-28s %-5s %9s %6s %6s %4s\n' scene variant channels off1 over1 max
while IFS=$'\t' read -r scene variant width height depth _; do
  [ "$scene" = scene ] && continue
  [[ $scene =~ $only ]] || continue
  ref=$root/reference/$scene.png
  [ "$variant" = noaa ] && ref=$root/reference/$scene.noaa.png
  spp=$((depth > 0 ? depth * depth : 1))
  out=$work/$scene.$variant.png
  "$pvrt" render "$root/scenes/$scene.xml" -o "$out" -W "$width" -H "$height" --spp "$spp" --sampler pov \
    --quiet || { echo "golden-census.sh: $scene did not render" >&2; exit 1; }
  # "  N channels: A differ, B by more than 1 level (...%), C by more than 2"
  stats=$("$pvrt" compare "$out" "$ref" --max-levels 255 --max-fraction-over-1 1)
  read -r channels differ over1 < <(sed -n 's/^ *\([0-9]*\) channels: \([0-9]*\) differ, \([0-9]*\) by more.*/\1 \2 \3/p' <<<"$stats")
  max=$(sed -n 's/^ *Max error = \([0-9]*\) levels.*/\1/p' <<<"$stats")
  printf '%-28s %-5s %9d %6d %6d %4d\n' "$scene" "$variant" "$channels" $((differ - over1)) "$over1" "$max"
done <"$root/reference/manifest.tsv" | tee "$work/table"

awk '
  { g = ($1 ~ /^fidelity_/) ? "fidelity" : "corpus"; n[g]++; ch[g] += $3; o1[g] += $4; om[g] += $5; if ($6 > mx[g]) mx[g] = $6 }
  END {
    for (g in n) printf "%s: %d images, %d channels, %d off by 1 level, %d by more, largest %d\n", g, n[g], ch[g], o1[g], om[g], mx[g]
  }' "$work/table" | sort
