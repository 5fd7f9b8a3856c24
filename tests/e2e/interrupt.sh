#!/usr/bin/env bash
# Usage: interrupt.sh SIGNAL PVRT SCENE DIR
# Starts a long render, sends SIGNAL (INT, TERM or KILL) once it is rendering, and checks:
#   INT/TERM: pvrt exits with 130 within 2 s, printing one line; nothing is written and no
#             temporary is left;
#   KILL:     the process dies by the signal (137); the output is not written. A temporary
#             may be left if the kill lands during the final write (docs/cli.md), but here it
#             lands mid-render, so none is expected either.
# Twice: with no output file before (none after), and with one (byte-identical after).
set -u
sig=$1 pvrt=$2 scene=$3 dir=$4
rm -rf "$dir" && mkdir -p "$dir" || exit 1
out=$dir/out.png err=$dir/../$(basename "$dir").stderr sentinel=$dir/../$(basename "$dir").sentinel
fail=0

# Whether process $1 has a handler installed for SIGINT (bit 2 of SigCgt in /proc).
catches_sigint() { [ $((0x$(awk '/^SigCgt/ {print $2}' /proc/"$1"/status 2>/dev/null || echo 0) & 2)) -ne 0 ]; }

one_run() {  # one_run WHAT: render, signal, check
  local what=$1
  # 4000 x 2500 at 16 samples a pixel takes minutes: the signal always lands mid-render.
  # --save-scene and --load-map are committed with the image or not at all.
  "$pvrt" render "$scene" -o "$out" --save-scene "$dir/saved.xml" --load-map "$dir/map" -W 4000 -H 2500 --spp 16 \
    --threads 1 --quiet 2>"$err" &
  local pid=$! waited=0
  # Wait until pvrt has started (its libraries load slowly) and installed its handler,
  # then a little more so that it is rendering.
  while ! catches_sigint $pid && [ $waited -lt 600 ]; do sleep 0.05; waited=$((waited + 1)); done
  if ! kill -0 $pid 2>/dev/null; then echo "$what: pvrt ended before it could be signalled:"; cat "$err"; fail=1; return; fi
  # (Killed by SIGINT, a shell also reports 130: the handler and the message tell them apart.)
  if ! catches_sigint $pid; then echo "$what: pvrt installed no SIGINT handler within 30 s"; fail=1; fi
  sleep 1
  local t0=$(date +%s%N)
  kill -"$sig" $pid
  wait $pid
  local rc=$? ms=$((($(date +%s%N) - t0) / 1000000))
  if [ "$sig" = KILL ]; then
    if [ $rc -ne 137 ]; then echo "$what: exit status $rc, expected 137 (killed)"; fail=1; fi
  else
    if [ $rc -ne 130 ]; then echo "$what: exit code $rc, expected 130"; fail=1; fi
    if [ $ms -gt 2000 ]; then echo "$what: took $ms ms to stop, more than 2 s"; fail=1; fi
    if [ "$(wc -l <"$err")" -ne 1 ] || ! grep -q "^pvrt: interrupted; nothing was written$" "$err"; then
      echo "$what: expected the one line 'pvrt: interrupted; nothing was written' on stderr, got:"; cat "$err"; fail=1
    fi
  fi
  echo "$what: exit status $rc, $ms ms after SIG$sig"
}

one_run "no output file before"
if [ -e "$out" ]; then echo "an output file was written"; fail=1; fi
if [ -n "$(ls -A "$dir")" ]; then echo "left behind:"; ls -la "$dir"; fail=1; fi

{ echo "pvrt interrupt sentinel $$"; head -c 256 /dev/urandom; } >"$sentinel"
cp "$sentinel" "$out"
one_run "an output file before"
if ! cmp -s "$sentinel" "$out"; then echo "the existing output file was changed or removed"; fail=1; fi
if [ "$(ls -A "$dir")" != out.png ]; then echo "left behind:"; ls -la "$dir"; fail=1; fi
rm -f "$err" "$sentinel"
exit $fail
