#!/usr/bin/env bash
# Usage: expect_error.sh EXIT_CODE STDERR_REGEX DIR [--absent FILE]... [--existing FILE]... -- command...
# Runs the command once (in a fresh DIR, which belongs to this test alone) and passes when
#   * it exits with EXIT_CODE; a status of 128 or more (killed by a signal: a crash, an
#     abort, a sanitizer) always fails,
#   * stderr is exactly one line, ending in a newline, that matches STDERR_REGEX,
#   * nothing was written: every --absent FILE is still absent, every --existing FILE (filled
#     with bytes no writer of pvrt would produce before the run) is byte-identical, and no
#     other file (a temporary) appeared in DIR.
set -u
want_rc=$1 pattern=$2 dir=$3
shift 3
absent=() existing=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  case $1 in
    --absent) absent+=("$2") ;;
    --existing) existing+=("$2") ;;
    *) echo "expect_error.sh: unknown option $1"; exit 2 ;;
  esac
  shift 2
done
shift
rm -rf "$dir" && mkdir -p "$dir" || exit 1
err=$(mktemp) sentinel=$(mktemp)
trap 'rm -f "$err" "$sentinel"' EXIT
{ echo "pvrt e2e sentinel $$ $RANDOM"; head -c 256 /dev/urandom; } >"$sentinel"
for f in "${existing[@]}"; do cp "$sentinel" "$f" || exit 1; done
before=$(ls -A "$dir")

"$@" 2>"$err" >/dev/null
rc=$?
fail=0
if [ "$rc" -ge 128 ]; then
  echo "killed by signal $((rc - 128)) (exit status $rc): a crash, not an error message"
  fail=1
elif [ "$rc" -ne "$want_rc" ]; then
  echo "exit code $rc, expected $want_rc"
  fail=1
fi
lines=$(wc -l <"$err")
if [ "$lines" -ne 1 ] || [ "$(wc -c <"$err")" -ne "$(head -n 1 "$err" | wc -c)" ]; then
  echo "expected exactly one line on stderr, got $lines:"
  head -c 4000 "$err" | cat -A
  fail=1
elif ! grep -Eq -- "$pattern" "$err"; then
  echo "stderr does not match /$pattern/:"
  cat "$err"
  fail=1
fi
for f in "${absent[@]}"; do
  if [ -e "$f" ]; then echo "$f was written"; fail=1; fi
done
for f in "${existing[@]}"; do
  if ! cmp -s "$sentinel" "$f"; then echo "the existing file $f was changed or removed"; fail=1; fi
done
if [ "$(ls -A "$dir")" != "$before" ]; then echo "left behind in $dir:"; ls -la "$dir"; fail=1; fi
exit $fail
