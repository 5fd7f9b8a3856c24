#!/usr/bin/env bash
# Real `mpirun` checks of the MPI backend.
#   mpi_check.sh identical BUILD SCENE NP SCHEDULE GATHER [THREADS]
#       the MPI render is bit-identical to the serial render
#   mpi_check.sh failure BUILD SCENE
#       a failure injected on one rank ends the whole job quickly, non-zero, with the
#       message once and no output file
#   mpi_check.sh slow BUILD SCENE
#       dynamic balancing gives a rank that sleeps per tile less work than the others
#   mpi_check.sh loadmap BUILD SCENE NP SCHEDULE
#       the load map (work per pixel, EXR) gathered from NP ranks is the serial one exactly
#   mpi_check.sh defaults BUILD SCENE NP
#       without --threads or OMP_NUM_THREADS, NP ranks on this node divide its CPUs: each
#       has max(1, CPUs / NP) threads, never a thread per CPU each
set -uo pipefail
mode=$1 build=$2 scene=$3
shift 3
pvrt=$build/pvrt
mpirun=(mpirun --allow-run-as-root --oversubscribe --bind-to none)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
size=(-W 96 -H 60 --spp 4 --quiet)

case $mode in
identical)
  np=$1 schedule=$2 gather=$3 threads=${4:-1}
  "$pvrt" render "$scene" -o "$work/serial.png" --backend serial "${size[@]}" || exit 1
  OMP_NUM_THREADS=$threads "${mpirun[@]}" -x OMP_NUM_THREADS -np "$np" "$pvrt" render "$scene" -o "$work/mpi.png" \
    --backend mpi --schedule "$schedule" --gather "$gather" --threads "$threads" "${size[@]}" || exit 1
  "$pvrt" compare "$work/serial.png" "$work/mpi.png" --max-levels 0 --max-fraction-over-1 0
  ;;
failure)
  start=$(date +%s)
  PVRT_FAIL_RANK=1 timeout 60 "${mpirun[@]}" -x PVRT_FAIL_RANK -np 3 "$pvrt" render "$scene" -o "$work/out.png" \
    --backend mpi "${size[@]}" 2>"$work/err"
  rc=$?
  elapsed=$(($(date +%s) - start))
  cat "$work/err"
  [ "$rc" -ne 0 ] && [ "$rc" -ne 124 ] || { echo "expected a non-zero exit (not a timeout), got $rc"; exit 1; }
  [ "$(grep -c 'injected failure' "$work/err")" -eq 1 ] || { echo "expected the message exactly once"; exit 1; }
  [ ! -e "$work/out.png" ] || { echo "an output file was written"; exit 1; }
  [ "$elapsed" -le 20 ] || { echo "took ${elapsed}s to stop"; exit 1; }
  ;;
slow)
  PVRT_SLOW_RANK=1:30 "${mpirun[@]}" -x PVRT_SLOW_RANK -np 3 "$pvrt" render "$scene" -o "$work/out.png" \
    --backend mpi --schedule dynamic --tile-size 8 --threads 1 -W 96 -H 60 --spp 4 --stats >"$work/stats" || exit 1
  cat "$work/stats"
  # Rank table rows: rank items pixels ... (rank 0, the master, renders between answers).
  slow=$(awk '$1 == "1" && NF == 9 { print $2 }' "$work/stats")
  fast=$(awk '$1 == "2" && NF == 9 { print $2 }' "$work/stats")
  echo "slow rank rendered $slow tiles, fast rank $fast"
  [ -n "$slow" ] && [ -n "$fast" ] && [ "$slow" -lt "$fast" ] || exit 1
  ;;
loadmap)
  np=$1 schedule=$2
  "$pvrt" render "$scene" -o "$work/serial.png" --backend serial --load-map "$work/serial" "${size[@]}" || exit 1
  "${mpirun[@]}" -np "$np" "$pvrt" render "$scene" -o "$work/mpi.png" --backend mpi --schedule "$schedule" \
    --threads 2 --load-map "$work/mpi" "${size[@]}" || exit 1
  "$pvrt" compare "$work/serial.png" "$work/mpi.png" --max-levels 0 --max-fraction-over-1 0 || exit 1
  idiff -fail 0 -warn 0 "$work/serial.exr" "$work/mpi.exr"
  ;;
defaults)
  np=$1
  cpus=$(nproc)
  expect=$((cpus / np))
  [ "$expect" -ge 1 ] || expect=1
  # Unbound ranks all may use every CPU, so they share them. (Bound by Open MPI's default,
  # to a core each for 2 ranks or fewer, each would have that core's CPUs alone.)
  env -u OMP_NUM_THREADS "${mpirun[@]}" -np "$np" "$pvrt" render "$scene" \
    -o "$work/out.png" --backend mpi --schedule dynamic "${size[@]}" --stats >"$work/stats" || exit 1
  grep -E 'Backend|^  [0-9]' "$work/stats"
  grep -q "mpi, $np rank(s) x $expect thread(s)" "$work/stats" || { echo "expected $expect thread(s) per rank on $cpus CPUs"; exit 1; }
  "$pvrt" render "$scene" -o "$work/serial.png" --backend serial "${size[@]}" || exit 1
  "$pvrt" compare "$work/serial.png" "$work/out.png" --max-levels 0 --max-fraction-over-1 0
  ;;
*) echo "unknown mode $mode"; exit 2 ;;
esac
