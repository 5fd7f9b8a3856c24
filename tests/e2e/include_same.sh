#!/usr/bin/env bash
# Usage: include_same.sh PVRT SCENES_DIR OUT_DIR
# A scene split over files with <include file="..."/> (nested, paths relative to the
# including file) renders bit for bit as the same scene written in one file, from whatever
# folder pvrt is started; its saved scene is the flat one.
set -euo pipefail
pvrt=$1 scenes=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$pvrt" render "$scenes/flat.xml" -o "$out/flat.png" --spp 4 --quiet
(cd / && "$pvrt" render "$scenes/main.xml" -o "$out/main.png" --spp 4 --quiet --save-scene "$out/saved.xml")
(cd "$scenes/.." && "$pvrt" render include/main.xml -o "$out/main_relative.png" --spp 4 --quiet)
cmp "$out/flat.png" "$out/main.png" || fail "the included scene's image differs from the flat scene's"
cmp "$out/flat.png" "$out/main_relative.png" || fail "started elsewhere, the included scene's image differs"
grep -q '<include' "$out/saved.xml" && fail "the saved scene still includes files"
grep -q 'name="glass"' "$out/saved.xml" || fail "the saved scene lacks the included material"
"$pvrt" render "$out/saved.xml" -o "$out/saved.png" --spp 4 --quiet
cmp "$out/flat.png" "$out/saved.png" || fail "the saved scene renders differently"
echo PASS
