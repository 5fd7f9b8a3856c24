#!/usr/bin/env bash
# Usage: tools/fuzz.sh [--run-only] [SECONDS] [-- libFuzzer options...]
# Builds the scene-loader fuzz target in build-fuzz/ (clang with libFuzzer, AddressSanitizer
# and UndefinedBehaviorSanitizer) and runs it for SECONDS (default 60) on a corpus seeded with
# scenes/*.xml and tests/e2e/bad/*.xml, with a dictionary of the format's names. The corpus
# it grows is kept in build-fuzz/fuzz-corpus/; findings (crash-*, leak-*, timeout-*, oom-*)
# go to build-fuzz/fuzz-artifacts/ and make the script fail. Reproduce one with
#   build-fuzz/tests/fuzz/scene_loader_fuzz build-fuzz/fuzz-artifacts/crash-...
# --run-only: no configure or build; exit 77 (skipped) when build-fuzz/ has no fuzz target.
set -euo pipefail
cd "$(dirname "$0")/.."
run_only=0
if [ "${1:-}" = "--run-only" ]; then run_only=1; shift; fi
seconds=${1:-60}
[ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
fuzzer=build-fuzz/tests/fuzz/scene_loader_fuzz

if [ "$run_only" -eq 0 ]; then
  if ! command -v clang++ >/dev/null; then
    echo "fuzz.sh: clang++ is needed (Debian: apt-get install clang libclang-rt-14-dev); skipped" >&2
    exit 77
  fi
  launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPVRT_FUZZ=ON -DPVRT_BUILD_TESTS=OFF "${launcher[@]}" >/dev/null
  nice -n 5 cmake --build build-fuzz -j"${PVRT_JOBS:-2}" --target scene_loader_fuzz
elif [ ! -x "$fuzzer" ]; then
  echo "fuzz.sh: no fuzz build in build-fuzz/ (run tools/fuzz.sh once to make it); skipped"
  exit 77
fi

mkdir -p build-fuzz/fuzz-corpus build-fuzz/fuzz-artifacts
# New inputs go to the first folder only; the seed folders are read.
exec "$fuzzer" build-fuzz/fuzz-corpus scenes tests/e2e/bad \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len=32768 \
  -dict=tests/fuzz/scene.dict -artifact_prefix=build-fuzz/fuzz-artifacts/ -print_final_stats=1 "$@"
