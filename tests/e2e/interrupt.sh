#!/usr/bin/env bash
# Usage: interrupt.sh SIGNAL PVRT SCENE DIR [STAGE]
# Starts pvrt, sends SIGNAL (INT, TERM or KILL) while it is in STAGE, and checks:
#   INT/TERM: pvrt exits with 130 (SIGINT) or 143 (SIGTERM) within 0.5 s of the signal,
#             printing one line; nothing is written and no temporary is left;
#   KILL:     the process dies by the signal (137); the output is not written. A temporary
#             may be left if the kill lands during the final write (docs/cli.md), but here it
#             lands mid-render, so none is expected either.
# Twice: with no output file before (none after), and with one (byte-identical after).
# STAGE (default render):
#   render   a 4000 x 2500 render of SCENE at 16 samples a pixel (minutes);
#   pipe     SCENE read from a pipe (/dev/stdin) whose writer sends half of it and then waits for ever;
#   load     the load of 10^6 generated spheres without lights (the signal is sent halfway
#            through it, as timed by a first run with --stats);
#   bvh      their BVH build (the signal is sent halfway through the build). For these two the
#            render after the build lasts seconds, so that a run some tenths faster than the
#            timing one is still there for the signal (which then lands in the build or the
#            render: either must stop within the limit);
#   buffers  the light-buffer build of `pvrt generate --spheres 100000 --lights 1000`
#            (tens of seconds);
#   trace    one deep trace: six clear spheres with reflection at max_trace_level 256, whose
#            ray trees never end (SCENE is ignored for these three, which make their own).
set -u
sig=$1 pvrt=$2 scene=$3 dir=$4 stage=${5:-render}
rm -rf "$dir" && mkdir -p "$dir" || exit 1
work=$dir.work
rm -rf "$work" && mkdir -p "$work" || exit 1
out=$dir/out.png err=$work/stderr sentinel=$work/sentinel
limit_ms=500
fail=0
args=(-W 4000 -H 2500 --spp 16 --threads 1)
settle=1  # seconds between the handler's installation and the signal

case $stage in
render)
  # --save-scene and --load-map are committed with the image or not at all.
  args+=(--save-scene "$dir/saved.xml" --load-map "$dir/map") ;;
pipe)
  args=(--threads 1)
  settle=0.5 ;;
load | bvh)
  "$pvrt" generate --spheres 1000000 --lights 0 --no-floor -o "$work/scene.xml" || exit 1
  # One thread: the build (about 1 s with two) then lasts long enough that the signal, timed
  # by a first run, still lands in it when the load of a later run is some tenths faster.
  scene=$work/scene.xml args=(-W 8 -H 8 --threads 1)
  times=$("$pvrt" render "$scene" -o "$work/first.png" "${args[@]}" --stats | sed -n 's/.*Time *load \([0-9.]*\) s, build \([0-9.]*\) s.*/\1 \2/p')
  # Halfway through the load, or through the build (which follows the load).
  half='a[1] / 2'
  [ "$stage" = bvh ] && half='a[1] + a[2] / 2'
  settle=$(awk -v t="$times" "BEGIN { split(t, a, \" \"); print $half }")
  # A render of several seconds after the build: a later run whose load is seconds faster than
  # the timing one's (on a machine whose other work comes and goes) is still there for the signal.
  args=(-W 640 -H 400 --spp 16 --threads 1)
  echo "first run: load and build $times s; signal $settle s after the handler" ;;
buffers)
  "$pvrt" generate --spheres 100000 --lights 1000 -o "$work/scene.xml" || exit 1
  scene=$work/scene.xml args=(-W 8 -H 8 --threads 2 --memory-limit 64G)
  settle=4 ;;
trace)
  scene=$work/scene.xml args=(-W 40 -H 25 --threads 2)
  {
    echo '<scene><global_settings max_trace_level="256"/><camera location="0 0 -6" look_at="0 0 0"/>'
    echo '<light_source location="-5 9 -6"/><material name="glass"><pigment color="1 1 1" filter="1"/>'
    echo '<finish ambient="0" diffuse="0" reflection="0.5"/><interior ior="1.5"/></material>'
    for c in "-1 0 0" "1 0 0" "0 1.732 0" "0 -1.732 0" "0 0.577 1.633" "0 0 -1.7"; do
      echo "<sphere center=\"$c\" radius=\"1\" material=\"glass\"/>"
    done
    echo '</scene>'
  } >"$scene" ;;
*) echo "unknown stage $stage"; exit 2 ;;
esac

# Whether process $1 has a handler installed for SIGINT (bit 2 of SigCgt in /proc).
catches_sigint() { [ $((0x$(awk '/^SigCgt/ {print $2}' /proc/"$1"/status 2>/dev/null || echo 0) & 2)) -ne 0 ]; }

one_run() {  # one_run WHAT: run, signal, check
  local what=$1
  if [ "$stage" = pipe ]; then
    # Half the scene, then the writer keeps the pipe open without writing.
    { head -c $(($(wc -c <"$scene") / 2)) "$scene"; sleep 600 & echo $! >"$work/writer.pid"; wait; } 2>/dev/null | "$pvrt" render /dev/stdin -o "$out" "${args[@]}" --quiet 2>"$err" &
  else
    "$pvrt" render "$scene" -o "$out" "${args[@]}" --quiet 2>"$err" &
  fi
  local pid=$! waited=0
  # Wait until pvrt has started (its libraries load slowly) and installed its handler.
  while ! catches_sigint $pid && [ $waited -lt 600 ]; do sleep 0.05; waited=$((waited + 1)); done
  if ! kill -0 $pid 2>/dev/null; then echo "$what: pvrt ended before it could be signalled:"; cat "$err"; fail=1; return; fi
  # (Killed by SIGINT, a shell also reports 130: the handler and the message tell them apart.)
  if ! catches_sigint $pid; then echo "$what: pvrt installed no SIGINT handler within 30 s"; fail=1; fi
  sleep "$settle"
  if ! kill -0 $pid 2>/dev/null; then echo "$what: pvrt ended before the signal:"; cat "$err"; fail=1; return; fi
  local t0=$(date +%s%N)
  kill -"$sig" $pid
  # Until pvrt is gone (`wait` would also wait for the pipe's writer), then its status.
  local n=0
  while kill -0 $pid 2>/dev/null && [ $n -lt 3000 ]; do sleep 0.005; n=$((n + 1)); done
  local ms=$((($(date +%s%N) - t0) / 1000000))
  [ -f "$work/writer.pid" ] && kill "$(cat "$work/writer.pid")" 2>/dev/null && rm -f "$work/writer.pid"
  wait $pid
  local rc=$?
  local want=130
  [ "$sig" = TERM ] && want=143
  if [ "$sig" = KILL ]; then
    if [ $rc -ne 137 ]; then echo "$what: exit status $rc, expected 137 (killed)"; fail=1; fi
  else
    if [ $rc -ne $want ]; then echo "$what: exit code $rc, expected $want"; fail=1; fi
    if [ $ms -gt $limit_ms ]; then echo "$what: took $ms ms to stop, more than $limit_ms ms"; fail=1; fi
    if [ "$(wc -l <"$err")" -ne 1 ] || ! grep -q "^pvrt: interrupted; nothing was written$" "$err"; then
      echo "$what: expected the one line 'pvrt: interrupted; nothing was written' on stderr, got:"; cat "$err"; fail=1
    fi
  fi
  echo "$stage, $what: exit status $rc, $ms ms after SIG$sig"
}

one_run "no output file before"
if [ -e "$out" ]; then echo "an output file was written"; fail=1; fi
if [ -n "$(ls -A "$dir")" ]; then echo "left behind:"; ls -la "$dir"; fail=1; fi

{ echo "pvrt interrupt sentinel $$"; head -c 256 /dev/urandom; } >"$sentinel"
cp "$sentinel" "$out"
one_run "an output file before"
if ! cmp -s "$sentinel" "$out"; then echo "the existing output file was changed or removed"; fail=1; fi
if [ "$(ls -A "$dir")" != out.png ]; then echo "left behind:"; ls -la "$dir"; fail=1; fi
rm -rf "$work"
exit $fail
