#!/usr/bin/env bash
# Usage: tools/sanitize.sh [ctest options...]
# Builds everything with AddressSanitizer and UndefinedBehaviorSanitizer (PVRT_SANITIZE=ON) in
# build-asan/ and runs the unit tests and the bad-input end-to-end tests there. A sanitizer
# report aborts the process, and the tests count that as a failure (an end-to-end test also
# fails on the report's extra lines on stderr).
set -euo pipefail
cd "$(dirname "$0")/.."
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPVRT_SANITIZE=ON "${launcher[@]}" >/dev/null
nice -n 5 cmake --build build-asan -j"${PVRT_JOBS:-2}"
# Leaks are reported too; halt_on_error keeps the first report the only one.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:halt_on_error=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir build-asan -L unit -j"${PVRT_JOBS:-2}" --output-on-failure "$@"
ctest --test-dir build-asan -L 'bad-input|robustness' -j"${PVRT_JOBS:-2}" --output-on-failure "$@"
