#!/usr/bin/env bash
# Usage: expect_error.sh EXIT_CODE STDERR_REGEX OUTPUT_FILE -- command...
# Passes when the command exits with EXIT_CODE, prints exactly one line on stderr that
# matches STDERR_REGEX, and leaves OUTPUT_FILE absent (and no temporary beside it).
set -u
want_rc=$1 pattern=$2 out=$3
shift 4
rm -f "$out"
err=$(mktemp)
"$@" 2>"$err" >/dev/null
rc=$?
fail=0
if [ "$rc" -ne "$want_rc" ]; then echo "exit code $rc, expected $want_rc"; fail=1; fi
lines=$(wc -l <"$err")
if [ "$lines" -ne 1 ]; then echo "expected exactly one line on stderr, got $lines:"; cat "$err"; fail=1; fi
if ! grep -Eq -- "$pattern" "$err"; then echo "stderr does not match /$pattern/:"; cat "$err"; fail=1; fi
if [ -e "$out" ]; then echo "output file $out was written"; fail=1; fi
if ls "$(dirname "$out")"/.*tmp-* >/dev/null 2>&1; then echo "a temporary file was left behind"; fail=1; fi
rm -f "$err"
exit $fail
