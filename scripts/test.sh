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

# The release and bundle builds compile through ccache, in build/ccache: the bundle's build
# (tests/bundle/bundle_test.sh, another configuration of the same sources) then takes most of its
# objects from the release build's instead of compiling the project a third time. ccache's
# preprocessor mode hashes the preprocessed source, not -D and -I, so a file that does not use a
# definition only one configuration has is still a hit. Not the sanitizer build: nothing reuses
# its objects, and a miss costs a preprocessor run on top of the compile. (setup.sh --tests above
# installed ccache.)
export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
export CCACHE_DIR=${CCACHE_DIR:-$PWD/build/ccache}
ccache --zero-stats >/dev/null
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
ccache --show-stats | sed -n '1,12p'

# Last: a finding here should not hide a failure above. The clang build holds only the parsers.
phase "fuzzing (libFuzzer + ASan + UBSan, every input parser)"
bash scripts/fuzz.sh "${NURBSBENCH_FUZZ_SECONDS:-30}"
phase "done"
