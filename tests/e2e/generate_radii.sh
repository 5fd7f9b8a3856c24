#!/usr/bin/env bash
# `pvrt generate` keeps the spheres' share of the box as N grows: default radii 0.2-0.8 up
# to 100 spheres, times (100/N)^(1/3) beyond; a radius given on the command line is kept.
# Usage: generate_radii.sh PVRT WORKDIR
set -euo pipefail
pvrt=$1 work=$2
mkdir -p "$work"
# radii FILE: "min max" of the spheres' radii
radii() { grep -o 'radius="[^"]*"' "$1" | sed 's/radius="\(.*\)"/\1/' | sort -g | sed -n '1p;$p' | paste -sd' '; }
# check NAME LO HI FILE: every radius in [LO, HI], and the extremes within 10% of them
check() {
  read -r min max <<<"$(radii "$4")"
  awk -v n="$1" -v lo="$2" -v hi="$3" -v min="$min" -v max="$max" 'BEGIN {
    ok = min >= lo && max <= hi && min < 1.1 * lo && max > 0.9 * hi
    printf "%s: radii %s-%s, expected within %s-%s: %s\n", n, min, max, lo, hi, ok ? "ok" : "WRONG"
    exit !ok }'
}
"$pvrt" generate --spheres 100 --seed 2 -o "$work/g100.xml"
check "100 spheres" 0.2 0.8 "$work/g100.xml"
"$pvrt" generate --spheres 1000 --seed 2 -o "$work/g1000.xml"
s=$(awk 'BEGIN { printf "%.9g", 0.1 ^ (1 / 3) }')
check "1000 spheres" "$(awk -v s="$s" 'BEGIN { print 0.2 * s }')" "$(awk -v s="$s" 'BEGIN { print 0.8 * s }')" "$work/g1000.xml"
"$pvrt" generate --spheres 1000 --seed 2 --radius-max 0.5 -o "$work/g1000max.xml"
check "1000 spheres, --radius-max 0.5" "$(awk -v s="$s" 'BEGIN { print 0.2 * s }')" 0.5 "$work/g1000max.xml"
