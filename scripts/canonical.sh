#!/usr/bin/env bash
# Regenerates the canonical results of this machine: results/<machine-tag>/ with one results set
# per paper figure (each a `nurbsbench run` with the samples its chart needs), the LOD, memory and
# deforming studies where this build has them, the report (REPORT.md, index.html, charts), a
# Google Benchmark JSON of the evaluation-time run, and the machine record.
#
#   scripts/canonical.sh                  # the full job (about 10 min on 2 cores, after the build)
#   scripts/canonical.sh --tiny           # the same steps on tiny grids (a minute): proves the script
#   scripts/canonical.sh --out DIR        # somewhere else than results/<machine-tag>
#   scripts/canonical.sh --no-build       # use build/release as it is
#
# The machine tag is the CPU model and the thread count (override: NURBSBENCH_MACHINE_TAG).
set -euo pipefail
cd "$(dirname "$0")/.."

tiny=0 build=1 out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --tiny) tiny=1 ;;
    --no-build) build=0 ;;
    --out) out="$2"; shift ;;
    *) echo "canonical.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
  shift
done

if [ "$build" = 1 ]; then
  bash scripts/setup.sh
  cmake --preset release >/dev/null
  cmake --build --preset release -j "$(nproc)" --target nurbsbench
fi
nb="$PWD/build/release/harness/nurbsbench"

cpu=$(sed -n 's/^model name[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo | head -n1)
tag=${NURBSBENCH_MACHINE_TAG:-$(echo "${cpu:-unknown-cpu}" | tr '[:upper:]' '[:lower:]' |
  sed -e 's/([^)]*)//g' -e 's/[^a-z0-9]\+/-/g' -e 's/^-//' -e 's/-$//')-$(nproc)t}
[ "$tiny" = 1 ] && tag="$tag-tiny"
out=${out:-results/$tag}
mkdir -p "$out"
echo "canonical: $out (CPU: ${cpu:-unknown}, $(nproc) threads)"

# Per figure: scenes, samples, repetitions (tiny: the same scenes where cheap, tiny grids). The
# full ones are the report's "regenerate" lines (the sections table, harness/report/sections.cpp,
# checked against the results they made by tests/cli/regenerate_test.cpp): change both together.
if [ "$tiny" = 1 ]; then
  fig7=(patch144 4x4,16x16 1)
  fig9_tspline=(tspline-tjunction 4x4,16x16 1)
  fig14=(tan16 8x8 1)
  fig8=(many-1,many-4 16x16 1)
  fig8_ducks=(many-ducks-1,many-ducks-2 16x16 1)
  accuracy=(patch144,degree-2,degree-3 8x8 1)
  deforming=(patch144 16x16 1)
  lod=(--samples 32x32,64x64 --repetitions 1)
  camera=(--scenes teapot --frames 4 --viewport 160x120 --pixels-per-sample 4 --fixed-samples 16x16)
else
  fig7=(patch144 4x4,8x8,16x16,32x32,64x64,128x128,256x256,512x512,1024x1024,2048x2048 3)
  fig9_tspline=(tspline-tjunction 4x4,8x8,16x16,32x32,64x64,128x128,256x256,512x512,1024x1024 3)
  fig14=(tan16,tan64,tan256 256x256 5)
  fig8=(many-1,many-4,many-16,many-64,many-256,many-1024,many-4096 16x16 3)
  # 000 Fig 8 as it ran: ducks, one third trimmed (evaluate + classify + draw per frame).
  fig8_ducks=(many-ducks-1,many-ducks-2,many-ducks-4,many-ducks-8,many-ducks-16,many-ducks-32,many-ducks-64 16x16 5)
  accuracy=(default 64x64 3)
  deforming=(teapot,patch144,many-256 16x16 1)  # RPNS's scenes; frames below
  lod=(--samples 128x128,512x512,1024x1024)      # 002 Fig 15's sizes (the verb's defaults)
  camera=(--scenes teapot --frames 60 --viewport 640x480 --pixels-per-sample 4 --fixed-samples 64x64)
fi

run() {  # run <subdir> <scenes> <samples> <repetitions> [extra run options...]
  local dir="$out/$1" scenes="$2" samples="$3" reps="$4"
  shift 4
  echo "canonical: run $dir ($scenes at $samples)"
  "$nb" run --scenes "$scenes" --strategies all --samples "$samples" --repetitions "$reps" \
    --out "$dir" "$@" >"$dir.log" 2>&1 || { echo "canonical: run $dir failed, see $dir.log" >&2; exit 1; }
  results+=(--results "$dir")
}
mkdir -p "$out"
results=()
run fig7-time-vs-points "${fig7[@]}"
run fig9-tspline-time-vs-points "${fig9_tspline[@]}"
run fig14-deboor-vs-basis "${fig14[@]}"
run fig8-many-surfaces "${fig8[@]}"
run fig8-trimmed-ducks "${fig8_ducks[@]}" --threads 1
run accuracy "${accuracy[@]}"

# RPNS per-frame time with deforming control points (30 frames), the Table 1 memory figures,
# 002 Fig 15 and 000 §3.2's camera path. The side files (lod.json, camera_path.json, memory.json)
# each get their own folder, a results set of their own for the report.
run deforming "${deforming[@]}" --deforming 30
# 003 §4: vk-ksquad in each mapping, deforming, on grids and span grids (its own report beside
# its sets; the sets go into the machine's report too).
if [ "$tiny" = 1 ]; then
  mappings=(--modes uniform,adaptive --scenes patch144 --deforming 2)
else
  mappings=(--modes uniform,adaptive,gs,nonuniform --scenes teapot,patch144 --samples 16x16
            --span-samples 4 --deforming 30 --repetitions 1)
fi
echo "canonical: rpns mappings"
bash scripts/rpns_mappings.sh --nurbsbench "$nb" --out "$out/rpns-mappings" "${mappings[@]}" \
  >"$out/rpns-mappings.log" 2>&1 ||
  { echo "canonical: rpns mappings failed, see $out/rpns-mappings.log" >&2; exit 1; }
for d in "$out"/rpns-mappings/*/; do
  [ -f "$d/results.json" ] && results+=(--results "${d%/}")
done
side() {  # side <subdir> <verb> [options...]: a verb that writes its file into DIR alone
  local dir="$out/$1" verb="$2"
  shift 2
  echo "canonical: $verb"
  mkdir -p "$dir"
  "$nb" "$verb" "$@" --out "$dir" >"$dir.log" 2>&1 ||
    { echo "canonical: $verb failed, see $dir.log" >&2; exit 1; }
  results+=(--results "$dir")
}
side lod lod "${lod[@]}"
side camera-path camera-path "${camera[@]}"
echo "canonical: memory"
mkdir -p "$out/memory"
"$nb" memory --scenes all --json >"$out/memory/memory.json"
results+=(--results "$out/memory")

echo "canonical: report"
"$nb" report "${results[@]}" --out "$out/report"
"$nb" gbench-json --results "$out/fig7-time-vs-points" --out "$out/fig7-time-vs-points/gbench.json"

# The machine record: what `run` recorded, plus every strategy's availability and device here.
/usr/bin/python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))["machine"], indent=1))' \
  "$out/fig7-time-vs-points/results.json" >"$out/machine.json"
"$nb" list --json >"$out/strategies.json"
echo "canonical: done: $out/report/REPORT.md"
