#!/usr/bin/env bash
# Issue 6's CPU goals, each ratio taken within one `nurbsbench run` (docs/design.md §Timing:
# speed is measured as ratios in one run): cpu-tensor f64 vs SISL s1506 (goal >= 10x, stretch
# 20x); cpu-tensor f32 vs the machine's store bandwidth (limit-store-bandwidth row; goal >= 50%);
# cpu-tensor vs cpu-coxdeboor on one thread (goal >= 5x). On patch144 and the random bicubic
# 12x12, 1024x1024.
# Writes results/cpu-goals/{f64,f32,f64-1thread,f64-1thread-nosimd}/results.{json,csv} and results/cpu-goals/RATIOS.md.
# Then issue 30's goals (cpu-tensor at the memory limit: positions, normals, f64, many faces,
# trims), each case three times in separate processes, min / median / max of its ratio:
# results/cpu-goals/issue30/GOALS.md (scripts/cpu_goals30.py). ONLY=30 runs that part alone.
# Run on an otherwise idle machine: OpenMP timings collapse when other processes share the cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/release/harness/nurbsbench
out=${1:-results/cpu-goals}
if [[ "${ONLY:-}" == 30 ]]; then
  exec python3 scripts/cpu_goals30.py build/release "$out/issue30" "${RUNS:-3}"
fi
scenes=patch144,random-bicubic-12x12
"$bin" run --strategies cpu-tensor,sisl,occt,occt-cached,cpu-horner,cpu-coxdeboor \
  --scenes "$scenes" --samples 1024x1024 --precision f64 --repetitions 7 --out "$out/f64"
"$bin" run --strategies limit-store-bandwidth,cpu-tensor --scenes "$scenes" --samples 1024x1024 \
  --precision f32 --repetitions 15 --out "$out/f32"
"$bin" run --strategies cpu-tensor,cpu-horner,cpu-coxdeboor,sisl --scenes "$scenes" \
  --samples 1024x1024 --precision f64 --threads 1 --repetitions 5 --out "$out/f64-1thread"
# The split of the one-thread gain: the same run with cpu-tensor's kernels built without SIMD.
"$bin" run --strategies cpu-tensor,cpu-coxdeboor --scenes "$scenes" --samples 1024x1024 \
  --precision f64 --threads 1 --repetitions 5 --strategy-option simd=off --out "$out/f64-1thread-nosimd"
python3 scripts/cpu_goals.py "$out" | tee "$out/RATIOS.md"
python3 scripts/cpu_goals30.py build/release "$out/issue30" "${RUNS:-3}"
