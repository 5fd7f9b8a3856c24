#!/usr/bin/env bash
# Regenerates the golden images in reference/ with POV-Ray 3.7 from every scene's export, and
# reference/manifest.tsv: `pvrt golden make` on the repository's own suite (docs/golden.md).
# Each reference keeps the size and antialiasing its manifest line records; a new scene gets
# 160 pixels wide and `+A0.0 +AM1 +R3 -J`. The golden tests (ctest -L golden) fail when an
# export no longer matches its recorded hash, i.e. when this script needs to be run again.
#
# Usage: tools/update-references.sh [BUILD_DIR] [SCENE_NAME...]   (default: build, all scenes)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
shift || true
[ -x "$build/pvrt" ] || { echo "update-references: $build/pvrt not built" >&2; exit 1; }
exec "$build/pvrt" golden make "$root/scenes" --references "$root/reference" "$@"
