#!/usr/bin/env bash
# gpu-check: the bundle's one-call GPU check (scripts/bundle.sh installs this file as
# bin/gpu-check). On a machine that has only a GPU driver (no packages, no root, no network) it
# prints the devices each API finds, runs the GPU-relevant subset of the canonical sets
# (scripts/canonical.sh) at GPU sizes within a time budget, writes the report, and packs it all
# into OUTDIR/nurbsbench-gpu-check-<tag>.tar.gz (under 16 MiB).
#
#   gpu-check OUTDIR [--minutes N] [--driver-dir DIR]... [--tiny]
#
#   --minutes N      the budget (default 8): steps run in order of what the papers' claims need;
#                    a step that no longer fits is skipped and named in SUMMARY.txt, the largest
#                    grids (Fig 7 at 2048² and 4096²) last so that they are the first dropped
#   --driver-dir DIR a GPU driver installed where the loaders do not look (repeatable); folders
#                    that GPU containers commonly mount (/usr/local/nvidia) are added when present
#   --tiny           the same steps on tiny grids (a minute on a CPU): proves the check itself
#
# Every figure is labelled with its device: on llvmpipe, lavapipe or PoCL it is a CPU figure.
set -uo pipefail

usage() { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 1 ] || usage
out="" minutes=8 tiny=0 driver_dirs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes)
      [[ "${2:-}" =~ ^[0-9]+$ ]] && [ "$2" -ge 1 ] ||
        { echo "gpu-check: --minutes = '${2:-}': must be a whole number >= 1" >&2; exit 2; }
      minutes=$2; shift ;;
    --driver-dir)
      [ -d "${2:-}" ] || { echo "gpu-check: --driver-dir = '${2:-}': not a folder" >&2; exit 2; }
      driver_dirs+=("$2"); shift ;;
    --tiny) tiny=1 ;;
    -h|--help) usage ;;
    -*) echo "gpu-check: unknown option '$1' (see gpu-check --help)" >&2; exit 2 ;;
    *) [ -z "$out" ] || { echo "gpu-check: one OUTDIR only (got '$out' and '$1')" >&2; exit 2; }
       out=$1 ;;
  esac
  shift
done
[ -n "$out" ] || usage
here=$(cd "$(dirname "$(readlink -f "$0")")" && pwd)
nb="$here/nurbsbench"
[ -x "$nb" ] || { echo "gpu-check: $nb not found (run gpu-check from an unpacked bundle)" >&2; exit 2; }
if [ -e "$out" ] && [ -n "$(ls -A "$out" 2>/dev/null)" ]; then
  echo "gpu-check: OUTDIR '$out' exists and is not empty (nothing is overwritten)" >&2
  exit 2
fi
mkdir -p "$out/sets" "$out/logs" || { echo "gpu-check: cannot make '$out'" >&2; exit 2; }
out=$(cd "$out" && pwd)

# Driver folders GPU containers mount outside the loaders' standard locations.
for d in /usr/local/nvidia; do
  [ -d "$d" ] && driver_dirs+=("$d")
done
drivers=()
for d in "${driver_dirs[@]}"; do drivers+=(--driver-dir "$d"); done

log() { echo "gpu-check: $*" | tee -a "$out/SUMMARY.txt"; }
start=$SECONDS
budget=$((minutes * 60))
# Kept back for the report and the archive.
reserve=$((tiny ? 10 : 25))
left() { echo $((budget - reserve - (SECONDS - start))); }

log "bundle $nb, budget ${minutes} min, $(nproc) CPU threads, $(sed -n 's/^model name[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo | head -n1)"
[ ${#driver_dirs[@]} -gt 0 ] && log "driver folders: ${driver_dirs[*]}"
"$nb" "${drivers[@]}" list >"$out/list.txt" 2>"$out/logs/list.err"
"$nb" "${drivers[@]}" list --json >"$out/list.json" 2>>"$out/logs/list.err"
sed -n '/^devices/,$p' "$out/list.txt"
if command -v nvidia-smi >/dev/null; then
  nvidia-smi >"$out/nvidia-smi.txt" 2>&1
  # The link and clocks a transfer or bandwidth figure depends on: a GPU in a gen3 slot or at a
  # lowered clock reads as a slow strategy otherwise.
  nvidia-smi --query-gpu=name,driver_version,pcie.link.gen.current,pcie.link.gen.max,pcie.link.width.current,pcie.link.width.max,clocks.sm,clocks.mem,clocks.max.sm,clocks.max.mem,power.limit \
    --format=csv >"$out/gpu-link-and-clocks.csv" 2>&1 &&
    log "GPU link and clocks: $(tail -n +2 "$out/gpu-link-and-clocks.csv" | head -n1)"
fi

# The machine tag: the first GPU any API found, else "cpu-stand-in".
gpu=$(sed -n 's/^    \(#[0-9]* \)\{0,1\}\(.*\) (gpu.*/\2/p' "$out/list.txt" | head -n1)
tag=$(echo "${gpu:-cpu stand-in}" | tr '[:upper:]' '[:lower:]' | sed -e 's/([^)]*)//g' \
  -e 's/[^a-z0-9]\+/-/g' -e 's/^-//' -e 's/-$//' | cut -c1-40)
[ "$tiny" = 1 ] && tag="$tag-tiny"
if [ -n "$gpu" ]; then log "GPU found: $gpu (tag $tag)"; else log "no GPU found: every figure is a CPU figure"; fi

results=() skipped=()
# step NAME NEEDS_SECONDS COMMAND...: runs COMMAND (a nurbsbench verb) within what is left of
# the budget; skipped when less than NEEDS_SECONDS is left, cut at the budget otherwise.
step() {
  local name=$1 needs=$2
  shift 2
  local remaining
  remaining=$(left)
  if [ "$remaining" -lt "$needs" ]; then
    skipped+=("$name")
    log "skipped $name: ${remaining}s of the budget left, it needs about ${needs}s"
    return 1
  fi
  local t0=$SECONDS
  timeout --kill-after=10 "$remaining" "$nb" "${drivers[@]}" "$@" >"$out/logs/$name.log" 2>&1
  local rc=$?
  if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
    log "cut $name at the budget after $((SECONDS - t0))s (what it measured so far is kept)"
  elif [ $rc -ne 0 ]; then
    log "$name exited $rc after $((SECONDS - t0))s: $(tail -n1 "$out/logs/$name.log")"
  else
    log "$name: $((SECONDS - t0))s"
  fi
  return 0
}
# set NAME NEEDS SCENES SAMPLES REPETITIONS [run options...]: one results set of every strategy.
set_run() {
  local name=$1 needs=$2 scenes=$3 samples=$4 reps=$5
  shift 5
  if step "$name" "$needs" run --scenes "$scenes" --strategies all --samples "$samples" \
    --repetitions "$reps" --timeout 120 --out "$out/sets/$name" "$@"; then
    [ -f "$out/sets/$name/results.json" ] && results+=(--results "$out/sets/$name")
  fi
  return 0
}

# The sizes: canonical.sh's sets at GPU sizes (Fig 7 to 4096²); --tiny keeps the steps, tiny.
if [ "$tiny" = 1 ]; then
  fig7=(patch144 4x4,16x16 1)
  fig7_large=(patch144 32x32 1)
  fig14=(tan16 8x8 1)
  fig8=(many-1,many-4 16x16 1)
  ducks=(many-ducks-1,many-ducks-2 16x16 1)
  deforming=(patch144 16x16 1)
  frames=2
  fig9=(tspline-tjunction 4x4,16x16 1)
  accuracy=(patch144,degree-2,degree-3 8x8 1)
  lod=(--samples 32x32,64x64 --repetitions 1)
  camera=(--scenes teapot --frames 4 --viewport 160x120 --pixels-per-sample 4 --fixed-samples 16x16)
  mapping_modes=(uniform adaptive)
  mapping=(--scenes patch144 --samples 16x16 --span-samples 4 --deforming 2 --repetitions 1)
else
  # At least 5 repetitions at every size: a figure's min/median/max rest on them.
  fig7=(patch144 4x4,16x16,64x64,256x256,1024x1024 5)
  fig7_large=(patch144 2048x2048,4096x4096 5)
  fig14=(tan16,tan64,tan256 256x256 5)
  fig8=(many-1,many-4,many-16,many-64,many-256,many-1024,many-4096 16x16 5)
  ducks=(many-ducks-1,many-ducks-4,many-ducks-16,many-ducks-64 16x16 5)
  deforming=(teapot,patch144,many-256 16x16 1)
  frames=30
  fig9=(tspline-tjunction 4x4,16x16,64x64,256x256,1024x1024 5)
  accuracy=(default 64x64 1)
  lod=(--samples 128x128,512x512,1024x1024)
  camera=(--scenes teapot --frames 60 --viewport 640x480 --pixels-per-sample 4 --fixed-samples 64x64)
  mapping_modes=(uniform adaptive gs nonuniform)
  mapping=(--scenes teapot,patch144 --samples 16x16 --span-samples 4 --deforming 30 --repetitions 1)
fi
n=$((tiny ? 5 : 30))  # the least a step is started with, in seconds

# In the order the papers' claims need them (report section "claims").
set_run fig7-time-vs-points "$n" "${fig7[@]}"
set_run fig8-many-surfaces "$n" "${fig8[@]}"
set_run fig14-deboor-vs-basis "$n" "${fig14[@]}"
set_run deforming "$n" "${deforming[@]}" --deforming "$frames"
set_run fig8-trimmed-ducks "$n" "${ducks[@]}" --threads 1
# 002 Fig 15 and 000 §3.2's camera path, and the memory figures: each file in its own set.
side_set() {  # side_set VERB [options...]: the verb's file in sets/VERB, a set when it was written
  step "$1" "$n" "$@" --out "$out/sets/$1" &&
    ls "$out/sets/$1"/*.json >/dev/null 2>&1 && results+=(--results "$out/sets/$1")
  return 0
}
side_set lod "${lod[@]}"
side_set camera-path "${camera[@]}"
mkdir -p "$out/sets/memory"
"$nb" memory --scenes all --json >"$out/sets/memory/memory.json" 2>>"$out/logs/memory.log" &&
  results+=(--results "$out/sets/memory")
# Every built-in scene: the accuracy gates under the vendor's shader compiler (checked below).
set_run accuracy "$n" "${accuracy[@]}"
set_run fig9-tspline-time-vs-points "$n" "${fig9[@]}"
# 003 §4: vk-ksquad in each mapping, deforming.
for mode in "${mapping_modes[@]}"; do
  name=rpns-mapping-$mode
  if step "$name" "$n" run --strategies vk-ksquad --strategy-option "vk-mode=$mode" \
    "${mapping[@]}" --timeout 120 --out "$out/sets/$name"; then
    [ -f "$out/sets/$name/results.json" ] && results+=(--results "$out/sets/$name")
  fi
done
# The largest grids last: the first dropped when the budget is short.
set_run fig7-large "$((tiny ? 5 : 60))" "${fig7_large[@]}"

# The report: every set beside the others (charts where python3 with matplotlib is here).
if [ ${#results[@]} -gt 0 ]; then
  "$nb" report "${results[@]}" --error-images 0 --trim-masks 0 --out "$out/report" >"$out/logs/report.log" 2>&1 ||
    log "report failed: $(tail -n1 "$out/logs/report.log")"
else
  log "no results set was measured: no report"
fi
# The CI accuracy gates (results/gates.json, shipped in share/) on every set measured here.
gates="$here/../share/nurbsbench/gates.json"
if [ -f "$gates" ] && [ ${#results[@]} -gt 0 ]; then
  violated=()
  for ((k = 1; k < ${#results[@]}; k += 2)); do
    echo "== ${results[k]#"$out"/}" >>"$out/gates.txt"
    # A gate no record of this set matches is not a violation here: each set measures a part.
    checked=$("$nb" check --gates "$gates" --results "${results[k]}" 2>&1 |
      grep -v "matched no measured result")
    echo "$checked" >>"$out/gates.txt"
    grep -q "^FAIL" <<<"$checked" && violated+=("$(basename "${results[k]}")")
  done
  if [ ${#violated[@]} -eq 0 ]; then
    log "accuracy gates: every gated record holds"
  else
    log "accuracy gates VIOLATED in ${violated[*]} (gates.txt)"
  fi
fi
[ ${#skipped[@]} -gt 0 ] && log "dropped for the budget: ${skipped[*]}"
log "done in $((SECONDS - start))s"

# One archive under 16 MiB: the sets, the report, the device lists and the logs.
archive="$out/nurbsbench-gpu-check-$tag.tar.gz"
parts=(SUMMARY.txt list.txt list.json sets)
[ -f "$out/nvidia-smi.txt" ] && parts+=(nvidia-smi.txt)
[ -f "$out/gpu-link-and-clocks.csv" ] && parts+=(gpu-link-and-clocks.csv)
[ -f "$out/gates.txt" ] && parts+=(gates.txt)
[ -d "$out/report" ] && parts+=(report)
tar czf "$archive" -C "$out" "${parts[@]}" logs
if [ "$(stat -c %s "$archive")" -gt $((16 * 1024 * 1024)) ]; then
  tar czf "$archive" -C "$out" "${parts[@]}"  # the logs are what can go
fi
size=$(stat -c %s "$archive")
echo "gpu-check: $archive ($((size / 1024)) KiB)"
[ "$size" -le $((16 * 1024 * 1024)) ] || { echo "gpu-check: archive over 16 MiB" >&2; exit 1; }
[ ${#results[@]} -gt 0 ]
