#!/usr/bin/env bash
# Real `mpirun` checks of the MPI backend.
#   mpi_check.sh identical BUILD SCENE NP SCHEDULE GATHER [THREADS]
#       the MPI render is bit-identical to the serial render
#   mpi_check.sh adaptive BUILD SCENE NP SCHEDULE METHOD [THREADS]
#       the same with POV-Ray's adaptive antialiasing (+A0.3 +AMmethod +R3, 16-pixel blocks)
#   mpi_check.sh failure BUILD SCENE
#       a failure injected on one rank ends the whole job quickly, non-zero, with the
#       message once and no output file
#   mpi_check.sh slow BUILD SCENE
#       dynamic balancing gives a rank that sleeps per tile less work than the others
#   mpi_check.sh loadmap BUILD SCENE NP SCHEDULE
#       the load map (work per pixel, EXR) gathered from NP ranks is the serial one exactly
#   mpi_check.sh interrupt BUILD SCENE SIGNAL
#       SIGNAL (INT, TERM or USR1) to mpirun mid-render ends the job within 3 s; an existing
#       output is left as it was, no saved scene and no temporary appear; USR1, which mpirun
#       forwards, ends it with 130 (on INT and TERM Open MPI's mpirun exits 1 itself)
#   mpi_check.sh interrupt BUILD SCENE SIGNAL wrapper
#       the same through tools/pvrt-mpirun, the signal sent to its process group as Ctrl-C
#       would: 130 for INT, 143 for TERM
#   mpi_check.sh stopped BUILD SCENE [remote]
#       a rank stopped with SIGSTOP ends the job (exit 75, one message) once --mpi-timeout
#       (2 s here) has passed, instead of hanging; `remote`: 3 ranks, each as if on a node of
#       its own (PVRT_WATCHDOG_HEARTBEATS_ONLY=1), so that only the heartbeats can see it
#   mpi_check.sh formats BUILD SCENE NP GATHER
#       an 8-bit output (PNG, TGA) travels as sRGB bytes, an EXR as floats: each is the
#       serial render's exactly, and the 8-bit gather sends at most a third of the float one's bytes
#   mpi_check.sh transports BUILD SCENE
#       ranks all on this node ask Open MPI for shared memory (ob1 over vader), unless the user
#       chose a transport (--mca) or set PVRT_MPI_SHARED_MEMORY=0; the image is the same each way
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
adaptive)
  np=$1 schedule=$2 method=$3 threads=${4:-1}
  aa=(-W 96 -H 60 --spp 9 --aa-threshold 0.3 --aa-method "$method" --aa-block 16 --quiet)
  "$pvrt" render "$scene" -o "$work/serial.png" --backend serial "${aa[@]}" || exit 1
  "${mpirun[@]}" -np "$np" "$pvrt" render "$scene" -o "$work/mpi.png" --backend mpi --schedule "$schedule" \
    --threads "$threads" "${aa[@]}" || exit 1
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
  # A saved scene is committed with the image or not at all (before: written by rank 0 even
  # when another rank then failed).
  PVRT_FAIL_RANK=1 timeout 60 "${mpirun[@]}" -x PVRT_FAIL_RANK -np 2 "$pvrt" render "$scene" -o "$work/out.png" \
    --save-scene "$work/saved.xml" --backend mpi "${size[@]}" 2>/dev/null
  [ -z "$(ls -A "$work" | grep -v '^err$')" ] || { echo "left behind: $(ls -A "$work")"; exit 1; }
  ;;
interrupt)
  sig=$1 via=${2:-mpirun}
  mkdir "$work/out" && echo "existing" >"$work/out/out.png"
  launcher=("${mpirun[@]}")
  # tools/pvrt-mpirun, started as a shell starts a command in the foreground (job control: it
  # gets its own process group and SIGINT is not ignored); the signal goes to that whole
  # group, as Ctrl-C at a terminal would send it.
  [ "$via" = wrapper ] && launcher=("$(dirname "$0")/../../tools/pvrt-mpirun" "${mpirun[@]:1}") && set -m
  "${launcher[@]}" -np 2 "$pvrt" render "$scene" -o "$work/out/out.png" --save-scene "$work/out/saved.xml" \
    --backend mpi --threads 1 -W 4000 -H 2500 --spp 16 --quiet 2>"$work/err" &
  pid=$!
  set +m
  target=$pid
  [ "$via" = wrapper ] && target=-$pid
  sleep 4  # started and rendering
  t0=$(date +%s%N)
  kill -"$sig" -- $target
  wait $pid
  rc=$? ms=$((($(date +%s%N) - t0) / 1000000))
  echo "SIG$sig to $via: exit $rc after $ms ms"
  cat "$work/err"
  fail=0
  [ $ms -le 3000 ] || { echo "took $ms ms to end"; fail=1; }
  want=1
  [ "$sig" = USR1 ] && want=130
  [ "$via" = wrapper ] && want=$((128 + $(kill -l "$sig")))
  [ $rc -eq $want ] || { echo "exit $rc, expected $want"; fail=1; }
  [ "$(cat "$work/out/out.png")" = existing ] || { echo "the existing output was changed"; fail=1; }
  [ "$(ls -A "$work/out")" = out.png ] || { echo "left behind: $(ls -A "$work/out")"; fail=1; }
  exit $fail
  ;;
stopped)
  np=2 message='has been stopped for 2 s; ending the job'
  if [ "${1:-}" = remote ]; then
    export PVRT_WATCHDOG_HEARTBEATS_ONLY=1
    mpirun+=(-x PVRT_WATCHDOG_HEARTBEATS_ONLY)
    np=3 message='rank 1 (pid [0-9]* on .*) has sent no heartbeat for 2 s'
  fi
  "${mpirun[@]}" -np $np "$pvrt" render "$scene" -o "$work/out.png" --backend mpi --threads 1 --mpi-timeout 2 \
    -W 4000 -H 2500 --spp 16 --quiet 2>"$work/err" &
  pid=$!
  sleep 4
  rank1=
  for p in $(pgrep -P $pid); do  # mpirun's children are the ranks: rank 1 by its environment
    grep -qz '^OMPI_COMM_WORLD_RANK=1$' /proc/"$p"/environ 2>/dev/null && rank1=$p
  done
  [ -n "$rank1" ] || { echo "rank 1 not found among mpirun's children"; kill $pid; exit 1; }
  t0=$(date +%s%N)
  kill -STOP "$rank1"
  wait $pid
  rc=$? ms=$((($(date +%s%N) - t0) / 1000000))
  kill -CONT "$rank1" 2>/dev/null
  echo "rank pid $rank1 stopped: mpirun exit $rc after $ms ms"
  cat "$work/err"
  fail=0
  [ $rc -eq 75 ] || { echo "exit $rc, expected 75"; fail=1; }
  [ $ms -ge 2000 ] && [ $ms -le 6000 ] || { echo "ended after $ms ms, expected 2-6 s (--mpi-timeout 2)"; fail=1; }
  [ "$(grep -c "$message" "$work/err")" -eq 1 ] || { echo "expected the message once: $message"; fail=1; }
  [ -z "$(ls -A "$work" | grep -v '^err$')" ] || { echo "left behind: $(ls -A "$work")"; fail=1; }
  exit $fail
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
  # (The maps had the images' names before, `--load-map serial` beside `-o serial.png`: the map's
  # PNG silently replaced the render. Two outputs on one file are now refused.)
  "$pvrt" render "$scene" -o "$work/serial.png" --backend serial --load-map "$work/serial-map" "${size[@]}" || exit 1
  "${mpirun[@]}" -np "$np" "$pvrt" render "$scene" -o "$work/mpi.png" --backend mpi --schedule "$schedule" \
    --threads 2 --load-map "$work/mpi-map" "${size[@]}" || exit 1
  "$pvrt" compare "$work/serial.png" "$work/mpi.png" --max-levels 0 --max-fraction-over-1 0 || exit 1
  "$pvrt" compare "$work/serial-map.png" "$work/mpi-map.png" --max-levels 0 --max-fraction-over-1 0 || exit 1
  idiff -fail 0 -warn 0 "$work/serial-map.exr" "$work/mpi-map.exr"
  ;;
formats)
  np=$1 gather=$2
  sent() {  # the KiB every rank sent, summed, from --stats
    awk '/Rank +items/{on=1; next} on && /^  [0-9]/{s+=$NF} END{print s+0}' "$1"
  }
  for ext in png tga exr; do
    "$pvrt" render "$scene" -o "$work/serial.$ext" --backend serial "${size[@]}" || exit 1
    "${mpirun[@]}" -np "$np" "$pvrt" render "$scene" -o "$work/mpi.$ext" --backend mpi --schedule cyclic \
      --gather "$gather" --threads 1 "${size[@]}" --stats >"$work/stats.$ext" || exit 1
  done
  cmp "$work/serial.png" "$work/mpi.png" || exit 1
  cmp "$work/serial.tga" "$work/mpi.tga" || exit 1
  idiff -fail 0 -warn 0 "$work/serial.exr" "$work/mpi.exr" || exit 1
  float=$(sent "$work/stats.exr") bytes=$(sent "$work/stats.png")
  echo "sent: $float KiB as floats, $bytes KiB as sRGB bytes"
  awk -v f="$float" -v b="$bytes" 'BEGIN{exit !(f > 0 && b > 0 && 3 * b <= f)}' || { echo "the 8-bit gather is not smaller"; exit 1; }
  ;;
transports)
  "$pvrt" render "$scene" -o "$work/serial.png" --backend serial "${size[@]}" || exit 1
  check() {  # expected-transports-line, then mpirun's own arguments
    local expect=$1
    shift
    "${mpirun[@]}" "$@" -np 2 "$pvrt" render "$scene" -o "$work/mpi.png" --backend mpi --threads 1 "${size[@]}" \
      --stats >"$work/stats" || exit 1
    grep 'MPI transports' "$work/stats"
    grep -qF "MPI transports        $expect" "$work/stats" || { echo "expected: $expect"; exit 1; }
    cmp "$work/serial.png" "$work/mpi.png" || exit 1
  }
  check "one node: pml ob1, btl self,vader, osc ^ucx"
  check "one node: pml ob1, btl self,tcp, osc ^ucx" --mca btl self,tcp
  PVRT_MPI_SHARED_MEMORY=0 check "Open MPI's own choice" -x PVRT_MPI_SHARED_MEMORY
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
