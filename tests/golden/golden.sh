#!/usr/bin/env bash
# Golden-image checks against POV-Ray's renders in reference/ (see reference/README.md).
#   golden.sh fresh   ROOT BUILD SCENE             the export still hashes to the manifest's SHA-256
#   golden.sh render  ROOT BUILD SCENE VARIANT BACKEND
#                                                  pvrt's render matches the reference within the
#                                                  thresholds; on failure new/ref/diff go to the report
#   golden.sh povray  ROOT BUILD SCENE VARIANT     POV-Ray re-renders the reference pixel for pixel
#   golden.sh report  ROOT BUILD                   writes the HTML report of all failures, if any
set -uo pipefail
mode=$1 root=$2 build=$3
pvrt=$build/pvrt
manifest=$root/reference/manifest.tsv
report=$build/golden-report
regenerate="tools/update-references.sh $build"

field() {  # field SCENE VARIANT COLUMN -> value from the manifest
  awk -F'\t' -v s="$1" -v v="$2" -v c="$3" 'NR > 1 && $1 == s && $2 == v { print $c; exit }' "$manifest"
}

case $mode in
fresh)
  scene=$4
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  "$pvrt" export-pov --strict "$root/scenes/$scene.xml" -o "$work/$scene.pov" || exit 1
  have=$(sha256sum "$work/$scene.pov" | cut -c1-64)
  want=$(field "$scene" aa 6)
  if [ -z "$want" ]; then echo "$scene has no reference; run $regenerate $scene"; exit 1; fi
  if [ "$have" != "$want" ]; then
    echo "reference for $scene is stale: export hashes to $have, manifest says $want"
    echo "regenerate with: $regenerate $scene"
    exit 1
  fi
  echo "export of $scene matches the manifest ($have)"
  ;;
render)
  scene=$4 variant=$5 backend=$6
  width=$(field "$scene" "$variant" 3) height=$(field "$scene" "$variant" 4) depth=$(field "$scene" "$variant" 5)
  ref=$root/reference/$scene.png
  [ "$variant" != aa ] && ref=$root/reference/$scene.$variant.png
  spp=$((depth > 0 ? depth * depth : 1))
  # POV-Ray's adaptive antialiasing, read from the reference's own command line.
  cmd=$(field "$scene" "$variant" 8)
  aa=()
  [[ $cmd =~ \ \+A([0-9.]+)\  ]] && aa+=(--aa-threshold "${BASH_REMATCH[1]}")
  [[ $cmd =~ \ \+AM([0-9])\  ]] && aa+=(--aa-method "${BASH_REMATCH[1]}")
  [[ $cmd =~ \ \+BS([0-9]+) ]] && aa+=(--aa-block "${BASH_REMATCH[1]}")
  # Per-scene thresholds, only with a written reason (reference/tolerances.tsv); a line for
  # SCENE.VARIANT holds for that variant alone and comes before one for SCENE.
  levels=2 fraction=0
  line=$(awk -F'\t' -v s="$scene" -v sv="$scene.$variant" 'NR > 1 && $1 == sv { print $2 "\t" $3; found = 1; exit }
    NR > 1 && $1 == s && !any { any = $2 "\t" $3 } END { if (!found && any) print any }' "$root/reference/tolerances.tsv")
  [ -n "$line" ] && IFS=$'\t' read -r levels fraction <<<"$line"
  out=$build/golden-out/$scene.$variant.$backend.png
  mkdir -p "$build/golden-out"
  case $backend in
    serial) run=("$pvrt" render --backend serial) ;;
    openmp) run=("$pvrt" render --backend openmp --threads 2) ;;
    mpi) run=(mpirun --allow-run-as-root --oversubscribe --bind-to none -np 3 "$pvrt" render --backend mpi --threads 1) ;;
    *) echo "unknown backend $backend"; exit 2 ;;
  esac
  "${run[@]}" "$root/scenes/$scene.xml" -o "$out" -W "$width" -H "$height" --spp "$spp" --sampler pov "${aa[@]}" --quiet || exit 1
  stats=$("$pvrt" compare "$out" "$ref" --max-levels "$levels" --max-fraction-over-1 "$fraction")
  rc=$?
  echo "$stats"
  if [ $rc -gt 1 ]; then
    dir=$report/$scene.$variant.$backend
    mkdir -p "$dir"
    cp "$out" "$dir/new.png"
    cp "$ref" "$dir/reference.png"
    "$pvrt" compare "$out" "$ref" --diff "$dir/diff.png" >/dev/null
    echo "$stats" >"$dir/stats.txt"
    echo "golden failure kept in $dir"
    exit 1
  fi
  ;;
povray)
  scene=$4 variant=$5
  command -v povray >/dev/null || { echo "povray not installed"; exit 1; }
  cmd=$(field "$scene" "$variant" 8)
  work=$(mktemp -d /tmp/pvrt-golden.XXXXXX)  # POV-Ray may only write below /tmp
  trap 'rm -rf "$work"' EXIT
  "$pvrt" export-pov --strict "$root/scenes/$scene.xml" -o "$work/$scene.pov" || exit 1
  (cd "$work" && $cmd >"$work/log" 2>&1) || { cat "$work/log"; exit 1; }
  png=$(sed -n 's/.*+O\([^ ]*\).*/\1/p' <<<"$cmd")
  # Decoded pixels must be identical (the files differ: POV-Ray stamps the date in them).
  "$pvrt" compare "$work/$png" "$root/reference/$png" --max-levels 0 --max-fraction-over-1 0
  [ $? -eq 0 ] || exit 1
  ;;
report)
  [ -d "$report" ] || { echo "no golden failures"; exit 0; }
  html=$report/index.html
  {
    echo "<!doctype html><meta charset=utf-8><title>pvrt golden failures</title>"
    echo "<style>img{image-rendering:pixelated;width:320px}td{vertical-align:top}</style>"
    echo "<h1>pvrt golden-image failures</h1>"
    echo "<p>If the new pictures are right, regenerate the references with <code>$regenerate</code>.</p>"
    echo "<table><tr><th>case</th><th>new</th><th>reference</th><th>difference x16</th><th>statistics</th></tr>"
    for dir in "$report"/*/; do
      name=$(basename "$dir")
      echo "<tr><td>$name</td><td><img src=\"$name/new.png\"></td><td><img src=\"$name/reference.png\"></td>"
      echo "<td><img src=\"$name/diff.png\"></td><td><pre>$(cat "$dir/stats.txt")</pre></td></tr>"
    done
    echo "</table>"
  } >"$html"
  echo "golden failures: report at $html"
  ;;
*) echo "unknown mode $mode"; exit 2 ;;
esac
