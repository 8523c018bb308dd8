#!/usr/bin/env bash
# The main job: installs what is needed, builds, runs the default benchmark (every built-in scene
# x every available strategy) and prints the summary table, then a per-scene digest (fastest within
# its gates, ratio to cpu-coxdeboor). Results: results/latest/results.json
# and results.csv. Extra arguments go to `nurbsbench run` (e.g. --samples 1024x1024).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release >/dev/null
# Only the CLI: `run` needs no other target (its isolated measurements re-exec this same binary,
# and shaders, kernels and scene data are compiled into it). The tests are scripts/test.sh's.
cmake --build --preset release -j "$(nproc)" --target nurbsbench
exec build/release/harness/nurbsbench run --out results/latest "$@"
