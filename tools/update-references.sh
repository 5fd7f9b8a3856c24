#!/usr/bin/env bash
# Regenerates the golden images in reference/: POV-Ray 3.7's renders of every scene's
# export, made with the reproducible recipe of shared/povray-semantics.md section 0, and
# reference/manifest.tsv, which records for each the export's SHA-256, POV-Ray's version
# and the full command line. The golden tests (ctest -L golden) fail when an export no
# longer matches its recorded hash, i.e. when this script needs to be run again.
#
# Usage: tools/update-references.sh [BUILD_DIR] [SCENE_NAME...]   (default: build, all scenes)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
shift || true
pvrt=$build/pvrt
[ -x "$pvrt" ] || { echo "update-references: $pvrt not built" >&2; exit 1; }
command -v povray >/dev/null || { echo "update-references: povray not installed (tools/install-deps.sh)" >&2; exit 1; }

# Scenes that also get a one-sample-per-pixel (-A) reference.
noaa=" paper1 shapes lights "
# Scenes that also get POV-Ray's adaptive antialiasing: +A0.3 with method 1 (a03) and 2 (am2).
adaptive=" paper1 shapes lights fidelity_checker_rows "
test_width=160

# POV-Ray may only write below /tmp or the current directory (Debian's povray.conf).
work=$(mktemp -d /tmp/pvrt-references.XXXXXX)
trap 'rm -rf "$work"' EXIT
version=$(povray --version 2>&1 | sed -n 's/^POV-Ray \([0-9][^ ]*\).*/\1/p' | head -1)

manifest=$root/reference/manifest.tsv
mkdir -p "$root/reference"
declare -A keep
if (($#)); then  # partial update: keep the other scenes' lines
  for n in "$@"; do keep[$n]=0; done
fi
tmp_manifest=$work/manifest.tsv
printf 'scene\tvariant\twidth\theight\taa_depth\tsdl_sha256\tpovray\tcommand\n' >"$tmp_manifest"
if (($#)) && [ -f "$manifest" ]; then
  tail -n +2 "$manifest" | while IFS=$'\t' read -r name rest; do
    [ -n "${keep[$name]+x}" ] || printf '%s\t%s\n' "$name" "$rest"
  done >>"$tmp_manifest"
fi

scenes=()
if (($#)); then for n in "$@"; do scenes+=("$root/scenes/$n.xml"); done
else scenes=("$root"/scenes/*.xml); fi

for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .xml)
  # Test size: 160 pixels wide, the scene's own aspect ratio.
  w=$(sed -n 's/.*<image[^>]*width="\([0-9]*\)".*/\1/p' "$scene" | head -1)
  h=$(sed -n 's/.*<image[^>]*height="\([0-9]*\)".*/\1/p' "$scene" | head -1)
  w=${w:-320} h=${h:-240}
  width=$test_width
  height=$(( (test_width * h + w / 2) / w ))
  "$pvrt" export-pov --strict "$scene" -o "$work/$name.pov"
  sha=$(sha256sum "$work/$name.pov" | cut -c1-64)
  variants=(aa)
  [[ $noaa == *" $name "* ]] && variants+=(noaa)
  [[ $adaptive == *" $name "* ]] && variants+=(a03 am2)
  for variant in "${variants[@]}"; do
    # pvrt's options for the variant; pvrt prints the POV-Ray command that matches them.
    case $variant in
      aa) depth=3 opts=(--spp 9) out=$name.png ;;
      noaa) depth=0 opts=(--spp 1) out=$name.noaa.png ;;
      a03) depth=3 opts=(--spp 9 --aa-threshold 0.3 --aa-method 1) out=$name.a03.png ;;
      am2) depth=3 opts=(--spp 9 --aa-threshold 0.3 --aa-method 2) out=$name.am2.png ;;
    esac
    cmd=$("$pvrt" export-pov --strict "$scene" -o "$work/$name.pov" --povray-command -W "$width" -H "$height" "${opts[@]}")
    cmd=${cmd/+O$name.png/+O$out}
    (cd "$work" && $cmd >"$work/$name.log" 2>&1) || { cat "$work/$name.log" >&2; exit 1; }
    cp "$work/$out" "$root/reference/$out"
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$variant" "$width" "$height" "$depth" "$sha" "$version" "$cmd" \
      >>"$tmp_manifest"
    echo "update-references: $out ($width x $height, $variant)"
  done
done
{ head -1 "$tmp_manifest"; tail -n +2 "$tmp_manifest" | sort -t$'\t' -k1,1 -k2,2; } >"$manifest"
echo "update-references: wrote $manifest"
