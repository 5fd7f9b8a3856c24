#!/usr/bin/env bash
# Usage: jitter_any_c.sh PVRT SCENE WORK_DIR
# --sampler jitter takes a c that is not a square (the paper's c = 8, and a prime 7): the image is the
# same bits on the serial backend, on 2 threads with every schedule, and on 3 MPI ranks (when mpirun is
# there); it is not the c = 1 image; --sampler grid and pov refuse c = 8 and write nothing.
set -uo pipefail
pvrt=$1 scene=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
size=(-W 96 -H 60 --sampler jitter --seed 5 --quiet)
for c in 7 8; do
  "$pvrt" render "$scene" -o "$work/serial$c.png" --backend serial --spp $c "${size[@]}" || fail "serial c=$c"
  for schedule in block cyclic dynamic tiles; do
    "$pvrt" render "$scene" -o "$work/omp$c-$schedule.png" --threads 2 --schedule $schedule --spp $c "${size[@]}" \
      || fail "openmp $schedule c=$c"
    "$pvrt" compare "$work/serial$c.png" "$work/omp$c-$schedule.png" --max-levels 0 --max-fraction-over-1 0 \
      >/dev/null || fail "openmp $schedule c=$c differs from serial"
  done
  if command -v mpirun >/dev/null; then
    mpirun --allow-run-as-root --oversubscribe --bind-to none -np 3 "$pvrt" render "$scene" -o "$work/mpi$c.png" \
      --backend mpi --threads 1 --spp $c "${size[@]}" || fail "mpi c=$c"
    "$pvrt" compare "$work/serial$c.png" "$work/mpi$c.png" --max-levels 0 --max-fraction-over-1 0 >/dev/null \
      || fail "mpi c=$c differs from serial"
  fi
done
"$pvrt" render "$scene" -o "$work/serial1.png" --backend serial --spp 1 "${size[@]}" || fail "c=1"
if "$pvrt" compare "$work/serial1.png" "$work/serial8.png" --max-levels 0 --max-fraction-over-1 0 >/dev/null; then
  fail "c = 8 gave the c = 1 image"
fi
for sampler in grid pov; do
  "$pvrt" render "$scene" -o "$work/bad-$sampler.png" --sampler $sampler --spp 8 -W 8 -H 5 2>"$work/err"
  rc=$?
  [ $rc -eq 2 ] || fail "--sampler $sampler --spp 8 exited $rc, expected 2"
  grep -q "perfect square (1, 4, 9, 16, ...) for --sampler $sampler, got 8" "$work/err" || fail "message: $(cat "$work/err")"
  [ ! -e "$work/bad-$sampler.png" ] || fail "--sampler $sampler --spp 8 wrote an image"
done
echo PASS
