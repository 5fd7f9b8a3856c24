#!/usr/bin/env bash
# Usage: region_check.sh PVRT SCENE OUT_DIR [MPIRUN]
# A render region (--start-col ... --end-row) holds exactly the pixels of the whole image it
# covers: the same float bits (EXR) on the serial and OpenMP backends, every schedule, and
# under MPI (when MPIRUN is given) with each strategy; and the load map is cut alike.
set -euo pipefail
pvrt=$1 scene=$2 out=$3 mpirun=${4:-}
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
size=(-W 72 -H 45 --spp 4)
"$pvrt" render "$scene" "${size[@]}" -o "$out/full.exr" --load-map "$out/fullmap" --backend serial --quiet
# Columns 10-49 and rows 0.2-0.8 of 45 (9 to 35 counted from 0): 40 x 27 pixels.
region=(--start-col 10 --end-col 49 --start-row 0.2 --end-row 0.8)
oiiotool "$out/full.exr" --cut 40x27+9+9 -o "$out/cut.exr"
oiiotool "$out/fullmap.exr" --cut 40x27+9+9 -o "$out/cutmap.exr"
same() {  # same pixels, bit for bit
  oiiotool "$1" "$2" --diff --fail 0 --failpercent 0 --warn 0 >"$out/diff.txt" 2>&1 || { cat "$out/diff.txt"; fail "$3"; }
}
runs=("--backend serial" "--threads 3 --schedule tiles --tile-size 8" "--threads 2 --schedule cyclic"
      "--threads 3 --schedule dynamic --chunk 2" "--threads 2 --schedule block")
for i in "${!runs[@]}"; do
  # shellcheck disable=SC2086
  "$pvrt" render "$scene" "${size[@]}" "${region[@]}" ${runs[$i]} -o "$out/r$i.exr" --quiet
  same "$out/cut.exr" "$out/r$i.exr" "region with ${runs[$i]} differs from the whole image's pixels"
done
"$pvrt" render "$scene" "${size[@]}" "${region[@]}" --threads 2 -o "$out/rimg.exr" --load-map "$out/rmap" --quiet
same "$out/cutmap.exr" "$out/rmap.exr" "the region's load map differs from the whole map's"
if [ -n "$mpirun" ]; then
  for schedule in block cyclic tiles dynamic; do
    $mpirun --allow-run-as-root --oversubscribe --bind-to none -np 3 "$pvrt" render "$scene" "${size[@]}" \
      "${region[@]}" --backend mpi --threads 1 --schedule "$schedule" --tile-size 8 -o "$out/mpi-$schedule.exr" --quiet
    same "$out/cut.exr" "$out/mpi-$schedule.exr" "MPI region with $schedule differs from the whole image's pixels"
  done
fi
# As a PNG, the region's size; its pixels are the whole PNG's (the 8-bit conversion is per pixel).
"$pvrt" render "$scene" "${size[@]}" "${region[@]}" -o "$out/r.png" --quiet
"$pvrt" render "$scene" "${size[@]}" -o "$out/full.png" --quiet
oiiotool "$out/full.png" --cut 40x27+9+9 -o "$out/cut.png"
same "$out/cut.png" "$out/r.png" "the region's PNG differs from the whole PNG cut"
info=$(oiiotool --info "$out/r.png")
case $info in *"40 x   27"*|*"40 x 27"*) ;; *) fail "region PNG is not 40 x 27: $info" ;; esac
echo PASS
