#!/usr/bin/env bash
# pvrt's BVH against Intel Embree 3 on the object-scaling scenes (bench/object_scaling.sh's:
# N spheres in one box, radii shrinking as N^(-1/3)), one thread, one ray workload
# (bench/embree/traversal_vs_embree.cpp). Needs libembree-dev:
#   apt-get install libembree-dev && cmake -S . -B build && cmake --build build --target bench_embree
# Usage: bench/embree_compare.sh [build dir] [counts...]
set -euo pipefail
build=${1:-build}
shift || true
counts=("$@")
((${#counts[@]})) || counts=(100 10000 1000000)
[[ -x $build/bench_embree ]] || { echo "no $build/bench_embree: see the comment at the top of $0" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for n in "${counts[@]}"; do
  scale=$(awk -v n="$n" 'BEGIN { printf "%.6g", (100 / n) ^ (1 / 3) }')
  "$build/pvrt" generate --spheres "$n" --lights 5 --seed 1 --radius-min "$(awk -v s="$scale" 'BEGIN { print 0.2 * s }')" \
    --radius-max "$(awk -v s="$scale" 'BEGIN { print 0.8 * s }')" -o "$work/s$n.xml"
  echo "== $n spheres, 640x400, 1 thread, median of 5"
  # Huge pages, as pvrt render asks for them (src/cli/huge_pages.h).
  GLIBC_TUNABLES=glibc.malloc.hugetlb=1 "$build/bench_embree" "$work/s$n.xml" 640 400 5
done
