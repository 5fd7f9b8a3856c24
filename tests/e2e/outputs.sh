#!/usr/bin/env bash
# Usage: outputs.sh CASE PVRT SCENE DIR
# How pvrt writes its outputs (core/output_files.h); each case its own CTest test:
#   planted_links   symbolic links planted at the temporary names older pvrt used
#                   (`.NAME.tmp-PID-N.EXT`) are not followed: their target is untouched
#                   (render, --save-scene, --load-map and generate)
#   symlink         -o through a symbolic link replaces the link's target, and the link stays
#   fifo            -o a FIFO writes the PNG into the pipe; the FIFO stays a FIFO
#   dev_stdout      -o /dev/stdout writes the PNG to standard output; /dev/stdout stays a link
#   dash            -o - writes the PNG to standard output; pvrt's own lines go to standard error
#   not_committed   a run that fails at its output (a directory) leaves no saved scene, no
#                   load map and no temporary
#   stream_fails    a stream that cannot be written (/dev/full) fails the run before any file
#                   is replaced: out.png and saved.xml keep what they held, no temporary left
#   permissions     a replaced file keeps its permissions
#   unwritable      an output folder that cannot be written fails before the render (as
#                   user nobody: root writes anywhere; skipped without setpriv)
#   newline_name    a scene whose name holds a newline gets a one-line message, the newline
#                   written \n
# Every image written is compared with a plain render to a regular file: the same bytes.
set -u
case_=$1 pvrt=$2 scene=$3 dir=$4
rm -rf "$dir" && mkdir -p "$dir" || exit 1
cd "$dir" || exit 1
size=(-W 48 -H 30 --spp 1 --quiet)
fail=0
bad() { echo "FAIL: $*"; fail=1; }
sentinel() { printf 'pvrt outputs sentinel %s\n' "$RANDOM$RANDOM" >"$1"; }
"$pvrt" render "$scene" -o plain.png "${size[@]}" || exit 1

case $case_ in
planted_links)
  mkdir victims && sentinel victims/v
  cp victims/v victims/expected
  # `exec` keeps the shell's PID, so $$ is pvrt's: plant links at its first temporary names.
  sh -c 'for n in 0 1 2 3 4 5; do
           for f in out.png saved.xml map.exr map.png gen.xml; do
             ln -s victims/v ".${f%.*}.tmp-$$-$n.${f##*.}"
           done
         done
         exec "$0" render "$1" -o out.png --save-scene saved.xml --load-map map '"${size[*]}" "$pvrt" "$scene" ||
    bad "render exited $?"
  sh -c 'for n in 0 1 2; do ln -s victims/v ".gen.tmp-$$-$n.xml"; done
         exec "$0" generate --spheres 3 -o gen.xml' "$pvrt" || bad "generate exited $?"
  cmp -s victims/v victims/expected || bad "a planted link was followed: its target changed"
  cmp -s out.png plain.png || bad "out.png is not the plain render"
  for f in saved.xml map.exr map.png gen.xml; do [ -s "$f" ] || bad "$f was not written"; done
  links=$(find . -maxdepth 1 -type l | wc -l)
  [ "$links" -eq 33 ] || bad "expected the 33 planted links untouched, found $links"
  ;;
symlink)
  mkdir real && sentinel real/target.png && ln -s real/target.png link.png
  "$pvrt" render "$scene" -o link.png "${size[@]}" || bad "render exited $?"
  [ -L link.png ] || bad "link.png is no longer a symbolic link"
  cmp -s real/target.png plain.png || bad "the link's target is not the render"
  [ "$(ls -A real)" = target.png ] || bad "left in real/: $(ls -A real)"
  ;;
fifo)
  mkfifo pipe.png
  timeout 60 cat pipe.png >got.png &
  reader=$!
  timeout 60 "$pvrt" render "$scene" -o pipe.png "${size[@]}" || bad "render exited $?"
  wait $reader
  [ -p pipe.png ] || bad "pipe.png is no longer a FIFO"
  cmp -s got.png plain.png || bad "what came through the FIFO is not the render"
  ;;
dev_stdout)
  "$pvrt" render "$scene" -o /dev/stdout "${size[@]}" >got.png || bad "render exited $?"
  [ -L /dev/stdout ] || [ -c /dev/stdout ] || bad "/dev/stdout was replaced"
  cmp -s got.png plain.png || bad "standard output is not the render"
  ;;
dash)
  "$pvrt" render "$scene" -o - -W 48 -H 30 --spp 1 --stats >got.png 2>err.txt || bad "render exited $?"
  cmp -s got.png plain.png || bad "standard output is not the render"
  grep -q "Render statistics" err.txt || bad "--stats did not go to standard error"
  [ ! -e ./- ] || bad "a file named - was written"
  "$pvrt" generate --spheres 3 -o - >gen.xml || bad "generate -o - exited $?"
  "$pvrt" render gen.xml -o gen.png "${size[@]}" || bad "the generated scene from standard output does not load"
  ;;
not_committed)
  mkdir out.png
  "$pvrt" render "$scene" -o out.png --save-scene saved.xml --load-map map "${size[@]}" 2>err.txt
  rc=$?
  [ $rc -eq 4 ] || bad "exit code $rc, expected 4"
  grep -q 'cannot write "out.png": it is a directory' err.txt || bad "message: $(cat err.txt)"
  [ "$(ls -A)" = "$(printf 'err.txt\nout.png\nplain.png')" ] || bad "left behind: $(ls -A)"
  ;;
stream_fails)
  [ -c /dev/full ] || { echo "skipped: no /dev/full"; exit 77; }
  sentinel out.png && cp out.png out.expected && sentinel saved.xml && cp saved.xml saved.expected
  "$pvrt" render "$scene" -o out.png --save-scene saved.xml --stats-json /dev/full "${size[@]}" 2>err.txt
  rc=$?
  [ $rc -eq 4 ] || bad "exit code $rc, expected 4"
  grep -q 'cannot write "/dev/full"' err.txt || bad "message: $(cat err.txt)"
  cmp -s out.png out.expected || bad "out.png was replaced by a run that failed"
  cmp -s saved.xml saved.expected || bad "saved.xml was replaced by a run that failed"
  "$pvrt" render "$scene" -o /dev/full --save-scene saved.xml "${size[@]}" 2>err.txt
  rc=$?
  [ $rc -eq 4 ] || bad "-o /dev/full: exit code $rc, expected 4"
  cmp -s saved.xml saved.expected || bad "saved.xml was replaced when -o /dev/full failed"
  left=$(ls -A | grep -v -x -e err.txt -e out.png -e out.expected -e saved.xml -e saved.expected -e plain.png)
  [ -z "$left" ] || bad "left behind: $left"
  ;;
permissions)
  sentinel out.png && chmod 640 out.png
  "$pvrt" render "$scene" -o out.png "${size[@]}" || bad "render exited $?"
  [ "$(stat -c %a out.png)" = 640 ] || bad "mode $(stat -c %a out.png), expected 640"
  cmp -s out.png plain.png || bad "out.png is not the render"
  ;;
unwritable)
  run=()
  if [ "$(id -u)" -eq 0 ]; then
    command -v setpriv >/dev/null || { echo "skipped: root writes anywhere, and no setpriv"; exit 77; }
    run=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
  fi
  mkdir locked && chmod 555 locked && chmod 755 . && cp "$scene" scene.xml && chmod 644 scene.xml
  start=$(date +%s%N)
  # 4000 x 2500 at 16 samples takes minutes: only a check before the render is quick.
  "${run[@]}" "$pvrt" render scene.xml -o locked/out.png -W 4000 -H 2500 --spp 16 --quiet 2>err.txt
  rc=$? ms=$((($(date +%s%N) - start) / 1000000))
  [ $rc -eq 4 ] || bad "exit code $rc, expected 4"
  grep -q 'cannot write "locked/out.png": the directory "locked" is not writable' err.txt || bad "message: $(cat err.txt)"
  [ $ms -lt 5000 ] || bad "took $ms ms: the folder was not checked before the render"
  echo "refused after $ms ms"
  ;;
newline_name)
  name=$'bad\nname.xml'
  printf '<scene>\n<sphere center="0 0 0" radus="1"/>\n</scene>\n' >"$name"
  "$pvrt" render "$name" -o out.png "${size[@]}" 2>err.txt
  rc=$?
  [ $rc -eq 3 ] || bad "exit code $rc, expected 3"
  [ "$(wc -l <err.txt)" -eq 1 ] || bad "expected one line, got: $(cat -A err.txt)"
  grep -q '^bad\\nname\.xml:2: error: sphere: ' err.txt || bad "message: $(cat err.txt)"
  "$pvrt" render "missing$name" -o out.png 2>err.txt
  [ "$(wc -l <err.txt)" -eq 1 ] || bad "missing file: expected one line, got: $(cat -A err.txt)"
  ;;
*)
  echo "unknown case $case_"; exit 2 ;;
esac
exit $fail
