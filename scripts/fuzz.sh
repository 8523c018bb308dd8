#!/usr/bin/env bash
# Fuzzes every input parser: builds the `fuzz` preset (clang, libFuzzer + ASan + UBSan; the
# parsers only) and runs each target of tests/fuzz/ for SECONDS (default 30), starting from its
# committed seeds (plus scenes/invalid/ for the scene loader). Prints executions and coverage per
# target; exit 1 when any target finds something, its reproducer left in build/fuzz/findings/.
# The grown corpus is kept in build/fuzz/corpus/ (not committed), so local runs build on each
# other; CI starts from the seeds.
#   scripts/fuzz.sh [SECONDS] [TARGET...]      targets: scene_json uv_file cli_lists tsm
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_json uv_file cli_lists tsm)

cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"

# Inputs larger than the seeds, so the scene loader sees many surfaces and the uv reader a line
# past its bound (kMaxUvLineBytes = 4096).
declare -A max_len=([scene_json]=16384 [uv_file]=8192 [cli_lists]=2048 [tsm]=16384)
# Runs one target; its verdict goes to build/fuzz/logs/TARGET.result for the table below.
fuzz_one() {
  local target=$1
  local binary=build/fuzz/tests/fuzz/fuzz_$target
  local corpus=build/fuzz/corpus/$target findings=build/fuzz/findings/$target
  local log=build/fuzz/logs/$target.log
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  local seeds=(tests/fuzz/corpus/"$target")
  [ "$target" = scene_json ] && seeds+=(scenes/invalid)
  [ "$target" = tsm ] && seeds+=(scenes/data/tsplines)
  local result=ok
  # -rss_limit_mb: the parsers must refuse absurd sizes before allocating, so 2 GiB is plenty;
  # -timeout: no input of a few KiB may take seconds.
  if ! "$binary" -max_total_time="$seconds" -max_len="${max_len[$target]}" -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=1 -dict="tests/fuzz/$target.dict" \
      -artifact_prefix="$findings/" "$corpus" "${seeds[@]}" >"$log" 2>&1; then
    result="FINDING (see $log, reproducer in $findings/)"
  fi
  echo "$result" >"build/fuzz/logs/$target.result"
}

for target in "${targets[@]}"; do
  [ -x "build/fuzz/tests/fuzz/fuzz_$target" ] || { echo "fuzz: no target $target" >&2; exit 2; }
  rm -f "build/fuzz/logs/$target.result"
done
# One target per core at a time (each libFuzzer process is single-threaded): every target still
# gets SECONDS of a whole core, in a fraction of the wall time.
running=0
for target in "${targets[@]}"; do
  if [ "$running" -ge "$(nproc)" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  fuzz_one "$target" &
  running=$((running + 1))
done
wait

status=0
printf '\n%-11s %12s %9s %8s %8s  %s\n' target executions exec/s cov features result
for target in "${targets[@]}"; do
  log=build/fuzz/logs/$target.log
  result=$(cat "build/fuzz/logs/$target.result" 2>/dev/null || echo "FINDING (no result: see $log)")
  [ "$result" = ok ] || status=1
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  printf '%-11s %12s %9s %8s %8s  %s\n' "$target" "${execs:-?}" "${rate:-?}" "${cov:-?}" \
    "${ft:-?}" "$result"
  if [ "$result" != ok ]; then
    grep -E 'fuzz finding|ERROR: |SUMMARY|terminate called|what\(\)' "$log" | head -5 >&2 || true
  fi
done
exit $status
