#!/usr/bin/env bash
# Usage: deep_trace.sh PVRT DIR
# max_trace_level 256 among six glass spheres (docs/robustness.md, "Deep traces"):
#  1. glass that keeps 90% of the light a crossing: adc_bailout (1/255) ends every path
#     within about 60 levels, as in POV-Ray, so level 256 renders within 60 s and gives
#     the image of level 100 bit for bit;
#  2. clear glass (filter 1) with reflection 0.5: no weight falls below the bailout, the
#     tree has about C(256, 8) paths a pixel (as in POV-Ray): pvrt announces the estimate on
#     stderr (threshold lowered by PVRT_ANNOUNCE_SECONDS) and stops within 0.5 s of Ctrl-C.
set -u
pvrt=$1 dir=$2
rm -rf "$dir" && mkdir -p "$dir" || exit 1
fail=0
scene() {  # scene FILTER LEVEL
  echo "<scene><global_settings max_trace_level=\"$2\"/><camera location=\"0 0 -6\" look_at=\"0 0 0\"/>"
  echo '<light_source location="-5 9 -6"/><material name="glass">'
  echo "<pigment color=\"1 1 1\" filter=\"$1\"/><finish ambient=\"0\" diffuse=\"0\" reflection=\"0.5\"/>"
  echo '<interior ior="1.5"/></material>'
  for c in "-1 0 0" "1 0 0" "0 1.732 0" "0 -1.732 0" "0 0.577 1.633" "0 0 -1.7"; do
    echo "<sphere center=\"$c\" radius=\"1\" material=\"glass\"/>"
  done
  echo '</scene>'
}

scene 0.9 256 >"$dir/deep256.xml"
scene 0.9 100 >"$dir/deep100.xml"
t0=$(date +%s%N)
timeout 60 "$pvrt" render "$dir/deep256.xml" -o "$dir/deep256.exr" -W 80 -H 50 --threads 2 --quiet || { echo "level 256 did not finish in 60 s"; fail=1; }
echo "level 256: $((($(date +%s%N) - t0) / 1000000)) ms"
"$pvrt" render "$dir/deep100.xml" -o "$dir/deep100.exr" -W 80 -H 50 --threads 2 --quiet || fail=1
# (The files' bytes differ by their metadata: the pixels are compared.)
if ! "$pvrt" compare "$dir/deep256.exr" "$dir/deep100.exr" | grep -q "PASS (identical)"; then
  "$pvrt" compare "$dir/deep256.exr" "$dir/deep100.exr"
  echo "levels 256 and 100 differ: the bailout should have ended every path before level 100"; fail=1
fi

scene 1 256 >"$dir/endless.xml"
PVRT_ANNOUNCE_SECONDS=30 "$pvrt" render "$dir/endless.xml" -o "$dir/endless.png" -W 40 -H 25 --threads 2 \
  --tile-size 4 --quiet 2>"$dir/stderr" &
pid=$! waited=0
while ! grep -q "this render will take" "$dir/stderr" && [ $waited -lt 300 ]; do sleep 0.1; waited=$((waited + 1)); done
if ! grep -Eq "^pvrt: this render will take (at least|about) [0-9.]+ (seconds|minutes|hours|days) \([0-9.]+% of the pixels done in [0-9]+ seconds\); Ctrl-C stops it$" "$dir/stderr"; then
  echo "no estimate announced within 30 s:"; cat "$dir/stderr"; fail=1
fi
t0=$(date +%s%N)
kill -INT $pid
wait $pid
rc=$? ms=$((($(date +%s%N) - t0) / 1000000))
echo "endless: announced after $((waited / 10)) s; exit $rc $ms ms after SIGINT"
[ $rc -eq 130 ] || { echo "exit code $rc, expected 130"; fail=1; }
[ $ms -le 500 ] || { echo "took $ms ms to stop, more than 500 ms"; fail=1; }
[ -e "$dir/endless.png" ] && { echo "an image was written"; fail=1; }
exit $fail
