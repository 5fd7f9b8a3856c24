#!/usr/bin/env bash
# `pvrt compare`'s exit code agrees with the verdict it prints, and usage errors have their own:
#   0 PASS (identical, or within the thresholds)   1 FAILURE (over them, or sizes differ)
#   2 bad command line                              4 an image cannot be read
set -uo pipefail
build=$1 root=$2
pvrt=$build/pvrt
ref=$root/reference
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
# check CODE VERDICT-REGEX ARGS...
check() {
  local want=$1 verdict=$2
  shift 2
  "$pvrt" compare "$@" >"$work/out" 2>&1
  local rc=$?
  if [ "$rc" -ne "$want" ] || ! grep -Eq -- "$verdict" "$work/out"; then
    echo "compare $*: exit $rc (want $want), output:"
    cat "$work/out"
    failed=1
  fi
}
# A reference made brighter by about a third of a level: nearly every channel 1 level off,
# none more, within the default thresholds (pvrt's own renders of the corpus are now too
# close to POV-Ray's to serve: reference/README.md).
oiiotool "$ref/prim_triangle.png" --addc 0.003 -o "$work/tri.png" || exit 1
check 0 '^PASS \(identical\)$' "$ref/paper1.png" "$ref/paper1.png"
check 0 '^PASS \(within 2 levels' "$work/tri.png" "$ref/prim_triangle.png"
check 1 '^FAILURE$' "$work/tri.png" "$ref/prim_triangle.png" --max-levels 0
check 1 '^FAILURE$' "$ref/paper1.png" "$ref/paper1.noaa.png"
check 1 '^FAILURE: the images differ in size: ".*paper1.png" is 160 x 100, ".*camera_square.png" 160 x 160$' "$ref/paper1.png" "$ref/camera_square.png"
check 2 'required|Expected' "$ref/paper1.png"
check 2 'pvrt: ' "$ref/paper1.png" "$ref/paper1.png" --max-levels x
check 4 'cannot read' "$work/nothing.png" "$ref/paper1.png"
exit $failed
