#!/usr/bin/env bash
# Usage: accuracy_plot.sh PVRT SCENE WORKDIR
# `pvrt accuracy --plot` writes a PNG; skipped (exit 77) without python3 + matplotlib.
set -euo pipefail
pvrt=$1 scene=$2 work=$3
mkdir -p "$work"
/usr/bin/python3 -c 'import matplotlib' 2>/dev/null || python3 -c 'import matplotlib' 2>/dev/null || {
  echo "SKIP: no python3 with matplotlib"; exit 77; }
rm -f "$work/accuracy.png"
"$pvrt" accuracy "$scene" -W 32 -H 20 --spp-list 1,4 --reference-spp 16 --max-depth 2 --plot "$work/accuracy.png"
[ "$(head -c 4 "$work/accuracy.png" | od -An -c | tr -d ' ')" = '211PNG' ] || { echo "FAIL: no PNG written"; exit 1; }
ls "$work"/*.csv 2>/dev/null && { echo "FAIL: temporary CSV left behind"; exit 1; }
echo PASS
