#!/usr/bin/env bash
# Usage: unreadable.sh EXPECT_ERROR PVRT DIR
# A scene without read permission must give `FILE: error: cannot read scene: Permission denied`.
# Root reads any file whatever its mode, so as root the render runs as user nobody (setpriv);
# without setpriv the test is skipped (exit 77).
set -u
expect=$1 pvrt=$2 dir=$3
scene_dir=$dir-scene
rm -rf "$scene_dir" && mkdir -p "$scene_dir" || exit 1
scene=$scene_dir/unreadable.xml
echo '<scene><sphere center="0 0 0" radius="1"/></scene>' >"$scene"
chmod 000 "$scene"
run=()
if [ "$(id -u)" -eq 0 ]; then
  if ! command -v setpriv >/dev/null; then
    echo "skipped: running as root (which reads any file) and setpriv is missing to drop to nobody"
    exit 77
  fi
  run=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
fi
"$expect" 3 "^.*/unreadable\.xml: error: cannot read scene: Permission denied$" "$dir" --absent "$dir/out.png" -- \
  "${run[@]}" "$pvrt" render "$scene" -o "$dir/out.png"
rc=$?
rm -rf "$scene_dir"
exit $rc
