#!/usr/bin/env bash
# How render time grows with the number of objects: random sphere scenes of N spheres in
# the same box, radii shrunk as N^(-1/3) so that the spheres' total volume stays the same.
# With the BVH, time per ray should grow like log(N), not N.
# Usage: bench/object_scaling.sh [pvrt binary] [counts...]
# Environment: SPP (samples per pixel, default 4), THREADS (default 2), SEED (default 1),
# WIDTH and HEIGHT (default 640x400), ROUNDS (default 1): each round renders every scene
# once, in turn, so that the machine's drift falls on all of them alike; the table gives
# medians [min-max] of the render stage, each scene's median against the first one's, and
# the median [min-max] of the round-by-round ratios to the first scene ("paired").
# TRACE_LEVEL=n sets the scenes' max_trace_level (default: the generator's, 5); 1 leaves
# out every reflected and refracted ray, so that what remains is the camera rays, their
# shadows and their shading. The columns "2nd/px" and "shade/px" (reflected, refracted and
# transmitted rays, and shading operations, per pixel) show how much more of that work a
# scene has than the first: bigger scenes of these spheres cover more of the image.
set -euo pipefail
pvrt=${1:-build/pvrt}
shift || true
counts=("$@")
((${#counts[@]})) || counts=(100 1000 10000 100000)
spp=${SPP:-4} threads=${THREADS:-2} seed=${SEED:-1} rounds=${ROUNDS:-1}
width=${WIDTH:-640} height=${HEIGHT:-400} level=${TRACE_LEVEL:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for n in "${counts[@]}"; do  # pvrt generate's default radii shrink as N^(-1/3)
  "$pvrt" generate --spheres "$n" --lights 5 --seed "$seed" -o "$work/s$n.xml"
  if [[ -n $level ]]; then
    sed -i "0,/<scene>/s//<scene>\n  <global_settings max_trace_level=\"$level\"\/>/" "$work/s$n.xml"
  fi
done
for ((r = 0; r < rounds; ++r)); do
  for n in "${counts[@]}"; do
    "$pvrt" render "$work/s$n.xml" -o "$work/s$n.png" -W "$width" -H "$height" --spp "$spp" \
      --threads "$threads" --quiet --stats-json "$work/stats$n.r$r.json"
  done
done
echo "${width}x${height}, --spp $spp, $threads threads, seed $seed, $rounds round(s)${level:+, max_trace_level $level}"
printf '%10s %12s %26s %10s %22s %10s %9s %10s %9s\n' spheres "load+build s" "render s: median [min-max]" \
  "vs first" "paired: median [min-max]" "tests/ray" "Mrays/s" "2nd/px" "shade/px"
first=""
for n in "${counts[@]}"; do
  # The figures of --stats-json; each round of this scene paired with the first scene's same round.
  read -r startup median lo hi perRay mrays second shading paired < <(python3 - "$n" "${counts[0]}" "$rounds" "$work" <<'PY'
import json, statistics, sys
n, first, rounds, work = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
load = lambda m, r: json.load(open("%s/stats%s.r%d.json" % (work, m, r)))
runs, firsts = [load(n, r) for r in range(rounds)], [load(first, r) for r in range(rounds)]
render = sorted(j["seconds"]["render"] for j in runs)
median = render[(len(render) - 1) // 2]
c = runs[-1]["counts"]
pixels = runs[-1]["image"]["width"] * runs[-1]["image"]["height"]
ratios = sorted(a["seconds"]["render"] / b["seconds"]["render"] for a, b in zip(runs, firsts))
print("%.4f %.4f %.4f %.4f %.2f %.2f %.3f %.3f %.2fx [%.2f-%.2f]" % (
    statistics.mean(j["seconds"]["load"] + j["seconds"]["build"] for j in runs), median, render[0], render[-1],
    c["intersection_tests"] / c["total_rays"], c["total_rays"] / median / 1e6,
    (c["reflected_rays"] + c["refracted_rays"] + c["transmitted_rays"]) / pixels, c["shading_operations"] / pixels,
    ratios[(len(ratios) - 1) // 2], ratios[0], ratios[-1]))
PY
)
  first=${first:-$median}
  printf '%10d %12.4f %26s %9.2fx %22s %10.2f %9.2f %10.3f %9.3f\n' "$n" "$startup" "$median [$lo-$hi]" \
    "$(awk -v a="$median" -v b="$first" 'BEGIN { print a / b }')" "$paired" "$perRay" "$mrays" "$second" "$shading"
done
