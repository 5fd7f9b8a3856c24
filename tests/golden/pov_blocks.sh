#!/bin/sh
# --pov-blocks against POV-Ray's own render: the same image whatever the threads and schedule
# (bit for bit), and within BOUND of the reference's channels over 1 level, a bound that the
# default per-pixel kernel exceeds (docs/fidelity.md, the shadow cache).
# usage: pov_blocks.sh PVRT SCENE REFERENCE OUTDIR MAX_LEVELS BOUND [SPP]
# SPP 9 (the default) is POV-Ray's +A0.0 +AM1 +R3 -J, SPP 1 its -A.
set -eu
pvrt=$1 scene=$2 ref=$3 out=$4 levels=$5 bound=$6 spp=${7:-9}
mkdir -p "$out"
render() { "$pvrt" render "$scene" -W 160 -H 100 --spp "$spp" --sampler pov --quiet "$@"; }
render -o "$out/serial.png" --pov-blocks --backend serial
render -o "$out/t2.png" --pov-blocks --threads 2 --schedule cyclic
render -o "$out/tiles.png" --pov-blocks --threads 2 --schedule dynamic --tile-size 16
cmp "$out/serial.png" "$out/t2.png"
cmp "$out/serial.png" "$out/tiles.png"
"$pvrt" compare "$out/serial.png" "$ref" --max-levels "$levels" --max-fraction-over-1 "$bound"
render -o "$out/plain.png" --threads 2
if "$pvrt" compare "$out/plain.png" "$ref" --max-levels "$levels" --max-fraction-over-1 "$bound" >/dev/null; then
  echo "the plain kernel is within the bound too: the test shows nothing"; exit 1
fi
echo "pov_blocks: PASS"
