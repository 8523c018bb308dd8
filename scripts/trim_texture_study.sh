#!/usr/bin/env bash
# The trim texture's resolution curve (Krishnamurthy 2007 §4, issue 15): the misclassification
# rate outside the band as a function of the trim-texture resolution R and of the tessellation
# tolerance, on trimmed-plate and hammer, for the GL strategies that trim. One `nurbsbench run`
# per (R, tolerance) into OUT/r<R>-t<T>/ (its log beside it), then the report of them all in
# OUT/report (section "trim_texture_resolution"). GL on llvmpipe is a CPU: its times are CPU times.
#
#   scripts/trim_texture_study.sh                        # results/canonical/trim-texture-study
#   scripts/trim_texture_study.sh --out DIR
#   scripts/trim_texture_study.sh --nurbsbench PATH      # default build/rel, then build/release
#   scripts/trim_texture_study.sh --resolutions 64,1024 --tolerances 1e-5 --samples 128x128
set -euo pipefail
cd "$(dirname "$0")/.."

out=results/canonical/trim-texture-study
nb=""
resolutions=64,128,256,512,1024,2048,4096
tolerances=1e-2,1e-3,1e-5  # fractions of each surface's (u,v) domain diagonal
samples=256x256
strategies=gl-pingpong,glsl-deboor
repetitions=3
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift ;;
    --nurbsbench) nb="$2"; shift ;;
    --resolutions) resolutions="$2"; shift ;;
    --tolerances) tolerances="$2"; shift ;;
    --samples) samples="$2"; shift ;;
    --repetitions) repetitions="$2"; shift ;;
    *) echo "trim_texture_study.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
  shift
done
if [ -z "$nb" ]; then
  for candidate in build/rel/harness/nurbsbench build/release/harness/nurbsbench; do
    [ -x "$candidate" ] && { nb="$candidate"; break; }
  done
fi
[ -x "$nb" ] || { echo "trim_texture_study.sh: no nurbsbench binary (build first or pass --nurbsbench)" >&2; exit 2; }

mkdir -p "$out"
results=()
for tol in ${tolerances//,/ }; do
  for r in ${resolutions//,/ }; do
    dir="$out/r$r-t$tol"
    echo "trim_texture_study: R=$r tolerance=$tol -> $dir"
    "$nb" run --scenes trimmed-plate,hammer --strategies "$strategies" --samples "$samples" \
      --repetitions "$repetitions" --strategy-option "trim-resolution=$r" \
      --strategy-option "trim-tolerance=$tol" --out "$dir" >"$dir.log" 2>&1 ||
      { echo "trim_texture_study.sh: run $dir failed, see $dir.log" >&2; exit 1; }
    results+=(--results "$dir")
  done
done
"$nb" report "${results[@]}" --error-images 0 --out "$out/report"
echo "trim_texture_study: done: $out/report/REPORT.md"
