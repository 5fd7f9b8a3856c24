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
      --threads "$threads" --stats --quiet >>"$work/stats$n.txt"
  done
done
echo "${width}x${height}, --spp $spp, $threads threads, seed $seed, $rounds round(s)${level:+, max_trace_level $level}"
printf '%10s %12s %26s %10s %22s %10s %9s %10s %9s\n' spheres "load+build s" "render s: median [min-max]" \
  "vs first" "paired: median [min-max]" "tests/ray" "Mrays/s" "2nd/px" "shade/px"
first=""
for n in "${counts[@]}"; do
  row=$(awk -v n="$n" '
    /^  Time/ { startup += $3 + $6; render[++k] = $9 }
    /^  Image/ { pixels = $2 * $4 }
    /^  Total rays/ { rays = $3 }
    /^  (Reflected|Refracted|Transmitted) rays/ { secondary[$1] = $3 }
    /^  Shading operations/ { shading = $3 }
    /^  Intersection tests/ { tests = $3 }
    END {
      for (i = 1; i <= k; ++i)  # insertion sort of the render times
        for (j = i; j > 1 && render[j - 1] > render[j]; --j) { t = render[j]; render[j] = render[j - 1]; render[j - 1] = t }
      median = render[int((k + 1) / 2)]
      second = secondary["Reflected"] + secondary["Refracted"] + secondary["Transmitted"]
      printf "%.4f %.4f %.4f %.4f %.2f %.2f %.3f %.3f\n", startup / k, median, render[1], render[k], tests / rays,
        rays / median / 1e6, second / pixels, shading / pixels
    }' "$work/stats$n.txt")
  read -r startup median lo hi perRay mrays second shading <<<"$row"
  first=${first:-$median}
  firstStats=${firstStats:-$work/stats$n.txt}
  # Each round's render against the first scene's in the same round (rendered just before
  # it, so the machine's drift cancels): the median and range of those ratios.
  paired=$(awk '
    FNR == 1 { file++ }
    /^  Time/ { t[file, ++k[file]] = $9 }
    END {
      for (i = 1; i <= k[2]; ++i) r[i] = t[2, i] / t[1, i]
      for (i = 1; i <= k[2]; ++i)
        for (j = i; j > 1 && r[j - 1] > r[j]; --j) { x = r[j]; r[j] = r[j - 1]; r[j - 1] = x }
      printf "%.2fx [%.2f-%.2f]", r[int((k[2] + 1) / 2)], r[1], r[k[2]]
    }' "$firstStats" "$work/stats$n.txt")
  printf '%10d %12.4f %26s %9.2fx %22s %10.2f %9.2f %10.3f %9.3f\n' "$n" "$startup" "$median [$lo-$hi]" \
    "$(awk -v a="$median" -v b="$first" 'BEGIN { print a / b }')" "$paired" "$perRay" "$mrays" "$second" "$shading"
done
