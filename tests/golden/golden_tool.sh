#!/usr/bin/env bash
# Tests of `pvrt golden` itself (label golden-tool) on a small suite of its own: three of the
# repository's scenes at 64 pixels wide, their references made with the real POV-Ray.
#   golden_tool.sh setup BUILD ROOT       makes the suite in BUILD/golden-tool/base
#   golden_tool.sh MODE  BUILD ROOT       one check on a copy of it (see the cases below)
set -uo pipefail
mode=$1 build=$2 root=$3
pvrt=$build/pvrt
top=$build/golden-tool
base=$top/base
scenes=(prim_sphere light_shadowless background_ambient)

fail() { echo "golden-tool $mode: $*"; exit 1; }
# expect CODE COMMAND...: runs it (output to $dir/out), demands the exit code.
expect() {
  local want=$1
  shift
  "$@" >"$dir/out" 2>&1
  local rc=$?
  cat "$dir/out"
  [ "$rc" -eq "$want" ] || fail "exit code $rc, expected $want: $*"
}
has() { grep -q -- "$1" "$2" || fail "\"$1\" not in $2"; }
lacks() { ! grep -q -- "$1" "$2" || fail "\"$1\" in $2"; }
# The SDL's hash as the manifest records it: the export less its two-line recipe comment.
sha() { "$pvrt" export-pov "$1" -o - | grep -v -e '^// Render as ' -e '^// (+A0.0 +AM1 +Rn -J' | sha256sum | cut -c1-64; }
# Breaks prim_sphere the way a renderer regression would show: its picture changes while the
# manifest still says the reference is of this scene (the hash is updated with it).
break_sphere() {
  sed -i 's/0.9 0.25 0.2/0.2 0.9 0.25/' "$dir/prim_sphere.xml"
  local new
  new=$(sha "$dir/prim_sphere.xml")
  awk -F'\t' -v OFS='\t' -v s="$new" '$1 == "prim_sphere" { $6 = s } { print }' "$dir/reference/manifest.tsv" \
    >"$dir/m" && mv "$dir/m" "$dir/reference/manifest.tsv"
}

if [ "$mode" = setup ]; then
  command -v povray >/dev/null || fail "povray not installed (tools/install-deps.sh)"
  rm -rf "$top" && mkdir -p "$base"
  for s in "${scenes[@]}"; do cp "$root/scenes/$s.xml" "$base/"; done
  dir=$top
  expect 0 "$pvrt" golden make "$base" --width 64
  exit 0
fi
[ -f "$base/reference/manifest.tsv" ] || fail "no suite: the golden-tool.setup fixture did not run"
dir=$top/$mode
rm -rf "$dir" && cp -r "$base" "$dir"
out=$dir/run

case $mode in
make)  # the manifest says what made each reference, and POV-Ray makes the same pixels again
  m=$dir/reference/manifest.tsv
  [ "$(tail -n +2 "$m" | wc -l)" -eq 3 ] || fail "expected 3 manifest lines"
  version=$(povray --version 2>&1 | sed -n 's/^POV-Ray \([0-9][^ ]*\).*/\1/p' | head -1)
  for s in "${scenes[@]}"; do
    line=$(awk -F'\t' -v s="$s" '$1 == s' "$m")
    [ "$(cut -f6 <<<"$line")" = "$(sha "$dir/$s.xml")" ] || fail "$s: the manifest's hash is not the export's"
    [ "$(cut -f7 <<<"$line")" = "$version" ] || fail "$s: POV-Ray version not recorded"
    [[ "$(cut -f8 <<<"$line")" == "povray +I$s.pov +O$s.png +W64 +H"*" -D +FN +A0.0 +AM1 +R3 -J" ]] || fail "$s: command"
    [ -f "$dir/reference/$s.png" ] || fail "$s: no image"
  done
  expect 0 "$pvrt" golden make "$dir" --verify
  before=$(md5sum "$dir"/reference/*)
  expect 1 "$pvrt" golden make "$dir" --povray false  # POV-Ray fails: nothing is stored
  has "3 of 3 references failed: nothing stored" "$dir/out"
  [ "$before" = "$(md5sum "$dir"/reference/*)" ] || fail "a failed make changed the references"
  expect 2 "$pvrt" golden make "$dir" --povray /no/such/povray
  cp "$dir/reference/light_shadowless.png" "$dir/reference/prim_sphere.png"
  expect 1 "$pvrt" golden make "$dir" prim_sphere --verify
  has "prim_sphere.aa: POV-Ray does NOT reproduce" "$dir/out"
  ;;
variant)  # other antialiasing: read from the manifest, never assumed
  expect 0 "$pvrt" golden make "$dir" prim_sphere --variant fast --antialiasing "-A"
  has "wrote 1 reference and" "$dir/out"
  has $'prim_sphere\tfast\t64\t40\t0\t' "$dir/reference/manifest.tsv"
  [ -f "$dir/reference/prim_sphere.fast.png" ] || fail "no prim_sphere.fast.png"
  expect 0 "$pvrt" golden run "$dir" --scene prim_sphere --backends serial --out "$out"
  has "PASS prim_sphere.fast.serial" "$dir/out"
  sed -i 's/+A0.0 +AM1 +R3 -J$/+A0.3 +AM2 +R3/' "$dir/reference/manifest.tsv"
  expect 1 "$pvrt" golden run "$dir" --scene prim_sphere --backends serial --out "$out"
  has 'no pvrt settings for POV-Ray.s "+A0.3 +AM2 +R3"' "$dir/out"
  ;;
run)  # every test passes: exit 0, both reports, the report's path printed last
  expect 0 "$pvrt" golden run "$dir" --backends serial,openmp --out "$out" --jobs 2
  [ "$(grep -c '^PASS ' "$dir/out")" -eq 6 ] || fail "expected 6 PASS lines"
  [ "$(tail -1 "$dir/out")" = "report: $out/report.html" ] || fail "the report's path is not the last line"
  has "6 tests: 0 failed, 6 passed" "$out/report.html"
  # 6 rows of new | reference | difference (identical: no zoom), each picture embedded once
  [ "$(grep -o '<img class=full data-i=' "$out/report.html" | wc -l)" -eq 18 ] || fail "not 18 pictures"
  [ "$(grep -c "^'data:image/png;base64," "$out/report.html")" -ge 4 ] || fail "pictures not embedded"
  lacks '<img[^>]* src=' "$out/report.html"
  has 'tests="6" failures="0"' "$out/junit.xml"
  ;;
broken)  # one scene's picture changed: exit 1, listed in both reports, the others pass
  break_sphere
  expect 1 "$pvrt" golden run "$dir" --backends serial,openmp --out "$out"
  has "FAIL prim_sphere.aa.serial: over tolerance" "$dir/out"
  has "FAIL prim_sphere.aa.openmp" "$dir/out"
  has "PASS light_shadowless.aa.serial" "$dir/out"
  has "6 tests: 2 failed, 4 passed" "$out/report.html"
  has "<tr class=fail><td>prim_sphere.aa.serial</td>" "$out/report.html"
  has 'tests="6" failures="2"' "$out/junit.xml"
  has 'name="prim_sphere.aa.serial" time="[0-9.]*"><failure message="over tolerance' "$out/junit.xml"
  cp "$out/report.html" "$top/broken-report.html"  # kept: the report of a run with one broken scene
  ;;
stale)  # a scene edited after its reference was made
  sed -i 's/0.9 0.25 0.2/0.2 0.9 0.25/' "$dir/prim_sphere.xml"
  expect 1 "$pvrt" golden run "$dir" --backends serial --out "$out"
  has "FAIL prim_sphere.aa.serial: reference is stale" "$dir/out"
  expect 1 "$pvrt" golden make "$dir" --verify  # POV-Ray is not blamed for the edit
  has "prim_sphere.aa: reference is stale: the scene's export no longer hashes" "$dir/out"
  lacks "does NOT reproduce" "$dir/out"
  has "light_shadowless.aa: POV-Ray reproduces the reference" "$dir/out"
  ;;
tolerance)  # a looser threshold with its reason passes and is shown; one without a reason is an error
  break_sphere
  printf 'scene\tmax_levels\tmax_fraction_over_1\treason\nprim_sphere\t255\t1\tthe test breaks it on purpose\n' \
    >"$dir/reference/tolerances.tsv"
  expect 0 "$pvrt" golden run "$dir" --backends serial --out "$out"
  has "PASS prim_sphere.aa.serial: within tolerance" "$dir/out"
  has "the test breaks it on purpose" "$out/report.html"
  printf 'scene\tmax_levels\tmax_fraction_over_1\treason\n*\t255\t1\n' >"$dir/reference/tolerances.tsv"
  expect 3 "$pvrt" golden run "$dir" --backends serial --out "$out"
  has "tolerances.tsv:2: error: \*: a tolerance needs its reason" "$dir/out"
  printf 'scene\tmax_levels\tmax_fraction_over_1\treason\n*\t255\t1\tthe whole suite, loosely\n' >"$dir/reference/tolerances.tsv"
  expect 0 "$pvrt" golden run "$dir" --backends serial --out "$out"
  ;;
bless)  # shows what would change, stores only with --yes; a new scene gets its first reference
  break_sphere
  before=$(md5sum "$dir/reference/manifest.tsv" "$dir/reference/prim_sphere.png")
  expect 0 "$pvrt" golden bless "$dir" prim_sphere --out "$out"
  has "prim_sphere.aa: changes: [0-9]* of 7680 channels differ" "$dir/out"
  has "would change; run again with --yes" "$dir/out"
  [ "$before" = "$(md5sum "$dir/reference/manifest.tsv" "$dir/reference/prim_sphere.png")" ] || fail "stored without --yes"
  expect 0 "$pvrt" golden bless "$dir" prim_sphere --out "$out" --yes
  has $'prim_sphere\taa\t64\t40\t3\t[0-9a-f]*\tpvrt [0-9.]*\tpvrt render prim_sphere.xml -o prim_sphere.png -W 64 -H 40 --sampler pov --spp 9' \
    "$dir/reference/manifest.tsv"
  expect 0 "$pvrt" golden bless "$dir" prim_sphere --out "$out"
  has "prim_sphere.aa: unchanged" "$dir/out"
  cp "$dir/prim_sphere.xml" "$dir/newcomer.xml"
  expect 1 "$pvrt" golden run "$dir" --backends serial --out "$out"
  has "FAIL newcomer.aa.reference: no reference" "$dir/out"
  expect 0 "$pvrt" golden bless "$dir" newcomer --yes --width 64 --out "$out"
  has "newcomer.aa: new reference (64 x 40)" "$dir/out"
  expect 0 "$pvrt" golden run "$dir" --backends serial,openmp --out "$out"
  has "PASS newcomer.aa.openmp: identical" "$dir/out"
  ;;
external)  # another renderer's folder against the references
  mkdir "$dir/other"
  for s in "${scenes[@]}"; do cp "$dir/reference/$s.png" "$dir/other/"; done
  expect 0 "$pvrt" golden compare "$dir" --images "$dir/other" --out "$out"
  has "PASS prim_sphere.aa.external: identical" "$dir/out"
  "$pvrt" render "$dir/prim_sphere.xml" -o "$dir/other/prim_sphere.png" -W 64 -H 40 --spp 1 --quiet || fail "render"
  rm "$dir/other/background_ambient.png"
  expect 1 "$pvrt" golden compare "$dir" --images "$dir/other" --out "$out"
  has "FAIL prim_sphere.aa.external: over tolerance" "$dir/out"
  has "FAIL background_ambient.aa.external: no image" "$dir/out"
  has "PASS light_shadowless.aa.external" "$dir/out"
  has 'tests="3" failures="2"' "$out/junit.xml"
  "$pvrt" render "$dir/light_shadowless.xml" -o "$dir/other/light_shadowless.png" -W 32 -H 20 --quiet || fail "render"
  expect 1 "$pvrt" golden compare "$dir" --images "$dir/other" --out "$out"
  has "FAIL light_shadowless.aa.external: the images differ in size: .*/other/light_shadowless.png is 32 x 20, the reference 64 x 40" "$dir/out"
  ;;
new)  # what the <prefix>.new CTest test runs: only what a configure-time list does not name
  printf 'prim_sphere.aa\nlight_shadowless.aa\n' >"$dir/known"
  expect 0 "$pvrt" golden run "$dir" --skip-list "$dir/known" --backends serial --out "$out"
  has "1 tests, 0 failed" "$dir/out"
  has "PASS background_ambient.aa.serial" "$dir/out"
  ;;
append)  # tests run apart gather their results; `golden report` writes one report and fails with them
  break_sphere
  expect 0 "$pvrt" golden run "$dir" --scene light_shadowless --backends serial --out "$out" --append
  expect 1 "$pvrt" golden run "$dir" --scene prim_sphere --backends serial --out "$out" --append
  [ ! -e "$out/report.html" ] || fail "--append wrote a report"
  expect 1 "$pvrt" golden report "$out"
  has "2 tests, 1 failed" "$dir/out"
  has "report: $out/report.html" "$dir/out"
  has 'tests="2" failures="1"' "$out/junit.xml"
  ;;
cmake)  # pvrt_add_golden_tests in a project of its own: a scene added later is tested without re-running cmake
  mkdir "$dir/project"
  printf 'cmake_minimum_required(VERSION 3.20)\nproject(suite NONE)\nenable_testing()\ninclude(%s)\n%s\n' \
    "$root/cmake/PvrtGolden.cmake" \
    "pvrt_add_golden_tests(NAME mine SCENES $dir REFERENCES $dir/reference PVRT $pvrt BACKENDS serial LABELS mine)" \
    >"$dir/project/CMakeLists.txt"
  expect 0 cmake -S "$dir/project" -B "$dir/project/build"
  expect 0 ctest --test-dir "$dir/project/build" -N
  has "mine.prim_sphere.aa.serial" "$dir/out"
  has "Total Tests: 6" "$dir/out"  # 3 scenes, new, setup, report
  expect 0 ctest --test-dir "$dir/project/build" --output-on-failure
  cp "$dir/prim_sphere.xml" "$dir/later.xml"
  expect 0 "$pvrt" golden bless "$dir" later --width 64 --yes --out "$out"
  expect 0 ctest --test-dir "$dir/project/build" -R 'mine[.]new' -V
  has "PASS later.aa.serial: identical" "$dir/out"
  sed -i 's/0.9 0.25 0.2/0.2 0.9 0.25/' "$dir/later.xml"  # now stale: mine.new and mine.report fail, with the path
  expect 8 ctest --test-dir "$dir/project/build" --output-on-failure
  has "FAIL later.aa.serial: reference is stale" "$dir/out"
  has "report: $dir/project/build/mine-out/report.html" "$dir/out"
  ;;
mpi)  # the MPI backend through the real mpirun
  command -v mpirun >/dev/null || { echo "mpirun not installed"; exit 77; }
  expect 0 "$pvrt" golden run "$dir" --backends mpi --np 2 --out "$out"
  has "PASS prim_sphere.aa.mpi: identical" "$dir/out"
  ;;
usage)  # usage errors have their own code, 2; unwritable output 4; malformed suite files 3
  expect 2 "$pvrt" golden run "$dir/nowhere"
  has 'error: ".*/nowhere" is not a folder of scenes' "$dir/out"
  mkdir -p "$dir/empty"  # blind9: an empty folder passed, with 0 tests, and make wrote a manifest into it
  expect 2 "$pvrt" golden run "$dir/empty" --out "$out"
  has 'error: ".*/empty" holds no scenes (\*.xml) and no references: nothing to test' "$dir/out"
  expect 2 "$pvrt" golden make "$dir/empty"
  [ ! -e "$dir/empty/reference" ] || fail "golden make wrote into an empty folder"
  expect 2 "$pvrt" golden run "$dir" --backends serial,gpu --out "$out"
  has 'unknown backend "gpu"' "$dir/out"
  expect 2 "$pvrt" golden run "$dir" --scene nosuch --out "$out"
  expect 2 "$pvrt" golden
  expect 4 "$pvrt" golden run "$dir" --out /proc/no-such-folder
  has '^pvrt: error: cannot write "/proc/no-such-folder/images": ' "$dir/out"
  expect 2 "$pvrt" golden compare "$dir"
  # audit: an unwritable --report failed after every render, naming its scratch picture
  expect 4 "$pvrt" golden run "$dir" --backends serial --out "$out" --report /no/such/folder/r.html
  has '^pvrt: error: cannot write "/no/such/folder/r.html": ' "$dir/out"
  [ ! -e "$out/images" ] || fail "rendered before finding that the report cannot be written"
  printf 'scene\tvariant\n' >"$dir/reference/manifest.tsv"
  printf 'x\ty\n' >>"$dir/reference/manifest.tsv"
  expect 3 "$pvrt" golden run "$dir" --out "$out"
  has "manifest.tsv:2: error: 2 fields where the header has 8" "$dir/out"
  ;;
interrupt)  # audit: SIGINT to pvrt golden alone used to end only the render it hit (or, from a
  # shell that ignores it in the background, nothing): the run went on and wrote its report
  printf '#!/bin/sh\nexec sleep 30\n' >"$dir/slow-mpirun" && chmod +x "$dir/slow-mpirun"
  "$pvrt" golden run "$dir" --backends mpi --mpirun "$dir/slow-mpirun" --jobs 2 --out "$out" >"$dir/out" 2>&1 &
  pid=$!
  sleep 1
  kill -INT $pid
  started=$SECONDS
  wait $pid
  rc=$?
  cat "$dir/out"
  [ "$rc" -eq 130 ] || fail "exit code $rc, expected 130"
  [ $((SECONDS - started)) -le 5 ] || fail "took $((SECONDS - started)) s to stop"
  has "^pvrt: interrupted; nothing was written" "$dir/out"
  [ ! -e "$out/report.html" ] && [ ! -e "$out/junit.xml" ] || fail "an interrupted run wrote a report"
  ! pgrep -f "$dir/slow-mpirun" >/dev/null || fail "a render was left running"
  ;;
*) fail "unknown mode" ;;
esac
echo "golden-tool $mode: ok"
