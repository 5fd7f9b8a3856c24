#!/usr/bin/env bash
# How render time grows with the number of objects: random sphere scenes of N spheres in
# the same box, radii shrunk as N^(-1/3) so that the spheres' total volume stays the same.
# With the BVH, time per ray should grow like log(N), not N.
# Usage: bench/object_scaling.sh [pvrt binary] [counts...]
set -euo pipefail
pvrt=${1:-build/pvrt}
shift || true
counts=("$@")
((${#counts[@]})) || counts=(100 1000 10000 100000)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '%10s %12s %12s %14s %16s\n' spheres "load+build s" "render s" "tests/ray" "Mrays/s"
for n in "${counts[@]}"; do
  scale=$(awk -v n="$n" 'BEGIN { printf "%.6g", (100 / n) ^ (1 / 3) }')
  rmin=$(awk -v s="$scale" 'BEGIN { printf "%.6g", 0.2 * s }')
  rmax=$(awk -v s="$scale" 'BEGIN { printf "%.6g", 0.8 * s }')
  "$pvrt" generate --spheres "$n" --lights 5 --seed 1 --radius-min "$rmin" --radius-max "$rmax" -o "$work/s$n.xml"
  "$pvrt" render "$work/s$n.xml" -o "$work/s$n.png" -W 640 -H 400 --spp 4 --stats --quiet >"$work/stats$n.txt"
  awk -v n="$n" '
    /^  Time/ { load = $3; build = $6; render = $9 }
    /^  Total rays/ { rays = $3 }
    /^  Intersection tests/ { tests = $3 }
    END { printf "%10d %12.4f %12.4f %14.2f %16.2f\n", n, load + build, render, tests / rays, rays / render / 1e6 }
  ' "$work/stats$n.txt"
done
