#!/usr/bin/env bash
# RPNS 2014 §4's mappings of vk-ksquad onto the pipeline side by side (issue 16): one deforming
# `nurbsbench run` of vk-ksquad per mapping (vk-mode=uniform|adaptive|gs|nonuniform) on the same
# scenes, grids and span grids, into OUT/<mode>/ (its log beside it), then the report of them all
# in OUT/report (section "rpns_mappings"). A mapping that cannot serve a sampling says so in its
# record (the GS mapping refuses grids and span grids past its output limit). Vulkan on lavapipe is
# a CPU: its times are CPU times.
#
#   scripts/rpns_mappings.sh                          # results/canonical/rpns-mappings
#   scripts/rpns_mappings.sh --out DIR
#   scripts/rpns_mappings.sh --nurbsbench PATH        # default build/rel, then build/release
#   scripts/rpns_mappings.sh --modes uniform,adaptive --scenes teapot --samples 16x16 \
#     --span-samples 4 --deforming 30 --repetitions 1
set -euo pipefail
cd "$(dirname "$0")/.."

out=results/canonical/rpns-mappings
nb=""
modes=uniform,adaptive,gs,nonuniform
scenes=teapot,patch144
samples=16x16
span_samples=4
deforming=30
repetitions=1
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift ;;
    --nurbsbench) nb="$2"; shift ;;
    --modes) modes="$2"; shift ;;
    --scenes) scenes="$2"; shift ;;
    --samples) samples="$2"; shift ;;
    --span-samples) span_samples="$2"; shift ;;
    --deforming) deforming="$2"; shift ;;
    --repetitions) repetitions="$2"; shift ;;
    *) echo "rpns_mappings.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
  shift
done
if [ -z "$nb" ]; then
  for candidate in build/rel/harness/nurbsbench build/release/harness/nurbsbench; do
    [ -x "$candidate" ] && { nb="$candidate"; break; }
  done
fi
[ -x "$nb" ] || { echo "rpns_mappings.sh: no nurbsbench binary (build first or pass --nurbsbench)" >&2; exit 2; }

mkdir -p "$out"
results=()
for mode in ${modes//,/ }; do
  dir="$out/$mode"
  echo "rpns_mappings: vk-mode=$mode -> $dir"
  "$nb" run --scenes "$scenes" --strategies vk-ksquad --samples "$samples" \
    --span-samples "$span_samples" --deforming "$deforming" --repetitions "$repetitions" \
    --strategy-option "vk-mode=$mode" --out "$dir" >"$dir.log" 2>&1 ||
    { echo "rpns_mappings.sh: run $dir failed, see $dir.log" >&2; exit 1; }
  results+=(--results "$dir")
done
"$nb" report "${results[@]}" --error-images 0 --out "$out/report"
echo "rpns_mappings: done: $out/report/REPORT.md"
