#!/usr/bin/env bash
# The test command: installs what is needed, builds, runs every test (CTest labels unit,
# accuracy, gpu-sw, slow, plus the accuracy gates of results/gates.json), then builds the CPU
# parts with ASan+UBSan and runs their unit and accuracy tests, then fuzzes every input parser for
# NURBSBENCH_FUZZ_SECONDS (default 30) each. Exit status 0 only if all pass.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --tests

jobs=$(nproc)
# Each phase prints its elapsed time: CI has a 40-minute budget on 2 cores, and this shows where it goes.
phase() { echo "== $1 (at ${SECONDS}s)"; }
phase "sanitizer build (ASan + UBSan, CPU parts)"
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
phase "sanitizer tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --preset asan

phase "release build"
cmake --preset release >/dev/null
cmake --build --preset release -j "$jobs"
phase "release tests"
# On the project's machines every strategy must be available (docs/design.md §The strategy interface).
NURBSBENCH_REQUIRE_ALL_STRATEGIES=1 ctest --preset release

# The relocatable bundle (scripts/bundle.sh) in a minimal Debian root that holds only glibc and
# the software drivers: what a GPU node without packages runs (issue 27).
phase "relocatable bundle in a minimal Debian root"
bash tests/bundle/bundle_test.sh

# Last: a finding here should not hide a failure above. The clang build holds only the parsers.
phase "fuzzing (libFuzzer + ASan + UBSan, every input parser)"
bash scripts/fuzz.sh "${NURBSBENCH_FUZZ_SECONDS:-30}"
phase "done"
