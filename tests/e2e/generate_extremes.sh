#!/usr/bin/env bash
# `pvrt generate` at the edges of what it accepts writes scenes its own loader reads: boxes
# and radii up to 1e15 in magnitude, and tiny radii. Each scene must render (8 x 8).
# Usage: generate_extremes.sh PVRT WORKDIR
set -u
pvrt=$1 work=$2
rm -rf "$work" && mkdir -p "$work" || exit 1
fail=0
one() {  # one NAME generate-options...
  local name=$1
  shift
  "$pvrt" generate --spheres 20 --lights 2 -o "$work/$name.xml" "$@" || { echo "$name: generate refused it"; fail=1; return; }
  if "$pvrt" render "$work/$name.xml" -o "$work/$name.png" -W 8 -H 8 --quiet; then
    echo "$name: generated and rendered"
  else
    echo "$name: the loader refused what generate wrote"; fail=1
  fi
}
one huge_radii --radius-min 1e14 --radius-max 1e15
one huge_boxes --sphere-box -1e15 -1e15 -1e15 1e15 1e15 1e15 --light-box -1e15 -1e15 -1e15 1e15 1e15 1e15
one tiny_radii --radius-min 1e-300 --radius-max 1e-299
one flat_box --sphere-box 0 0 0 0 0 0 --light-box 1 1 1 1 1 1
exit $fail
