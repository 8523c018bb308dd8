#!/usr/bin/env bash
# Issue 31 end to end, as a plugin author meets it: install nurbsbench into a fresh prefix, build
# examples/plugins and the broken test plugin OUT OF TREE against it with find_package, then
#  - one `run --plugin` of every broken plugin beside the C Cox-de Boor example and cpu-coxdeboor:
#    each misbehaviour gets its own status and reason, every other record is ok, and plugin records
#    carry role plugin, the library's path and its SHA-256 (checked against sha256sum);
#  - a plugin named like a built-in strategy is exit 2, with no output written;
#  - the SISL plugin's `eval` points equal the built-in sisl's, byte for byte, on several scenes,
#    samplings and both precisions;
#  - `check` passes a gate naming the C plugin and fails one naming a broken plugin.
# Usage: plugins_test.sh BUILD_DIR SOURCE_DIR (KEEP=1 keeps its temporary folder)
set -euo pipefail
build=$(realpath "$1")
source=$(realpath "$2")
work=$(mktemp -d "${TMPDIR:-/tmp}/nurbsbench-plugins-XXXXXX")
trap '[ -n "${KEEP:-}" ] || rm -rf "$work"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$work/prefix" >/dev/null
nb="$work/prefix/bin/nurbsbench"
cmake -S "$source/tests/plugins" -B "$work/plugins" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_C_FLAGS=-Werror >"$work/configure.log" ||
  { cat "$work/configure.log"; fail "configuring the plugins against the installed prefix"; }
cmake --build "$work/plugins" >"$work/build.log" || { cat "$work/build.log"; fail "building the plugins"; }
p="$work/plugins"
coxdeboor="$p/examples/libcoxdeboor_plugin.so"
sisl="$p/examples/libsisl_plugin.so"
printf 'not a shared library\n' >"$p/libbroken-load.so"

# ------------------------------------------------------------------ statuses of broken plugins
plugins=(--plugin "$coxdeboor" --plugin "$p/libbroken-load.so")
names=c-coxdeboor,cpu-coxdeboor,broken-load
for mode in crash hang nan short error version noentry nullfn; do
  plugins+=(--plugin "$p/libbroken-$mode.so")
  names+=",broken-$mode"
done
"$nb" run "${plugins[@]}" --strategies "$names" --scenes patch144 --samples 16x16 \
  --repetitions 1 --timeout 3 --out "$work/run" >"$work/run.log" 2>&1 ||
  { cat "$work/run.log"; fail "run --plugin exited $?"; }
python3 - "$work/run/results.json" "$p" <<'PY' || fail "records of the broken plugins"
import hashlib, json, sys
records = {r["strategy"]: r for r in json.load(open(sys.argv[1]))["records"]}
plugins = sys.argv[2]
expected = {
    "cpu-coxdeboor": ("ok", ""),
    "c-coxdeboor": ("ok", ""),
    "broken-load": ("failed", "fails to load: "),
    "broken-crash": ("crashed", "SIGSEGV"),
    "broken-hang": ("timed_out", "no answer within 3 s"),
    "broken-nan": ("failed", "samples are not finite"),
    "broken-short": ("failed", "wrong output count: surface 0: 255 of 256 samples written"),
    "broken-error": ("failed", "evaluate returned error 1: the broken plugin's deliberate error"),
    "broken-version": ("failed", "wrong ABI version 99 (this harness loads 1..1)"),
    "broken-noentry": ("failed", "missing entry points: the library exports no nurbsbench_evaluator()"),
    "broken-nullfn": ("failed", "missing entry points: evaluate"),
}
bad = []
for name, (status, reason) in expected.items():
    r = records.get(name)
    if r is None:
        bad.append(f"{name}: no record"); continue
    if r["status"] != status or reason not in r["reason"] or "\n" in r["reason"]:
        bad.append(f"{name}: {r['status']} '{r['reason']}', expected {status} '...{reason}...'")
    if name == "cpu-coxdeboor":
        if r["role"] == "plugin" or "library" in r: bad.append("cpu-coxdeboor: marked as a plugin")
        continue
    if r["role"] != "plugin": bad.append(f"{name}: role {r['role']}")
    file = f"{plugins}/examples/libcoxdeboor_plugin.so" if name == "c-coxdeboor" else f"{plugins}/lib{name}.so"
    digest = hashlib.sha256(open(file, "rb").read()).hexdigest()
    if r.get("library") != {"path": file, "sha256": digest}:
        bad.append(f"{name}: library {r.get('library')}, expected {file} {digest}")
if len(records) != len(expected): bad.append(f"{len(records)} records, expected {len(expected)}")
print("\n".join(bad))
sys.exit(1 if bad else 0)
PY

# ------------------------------------------------------------ a built-in's name is refused
set +e
"$nb" run --plugin "$p/libbroken-clash.so" --strategies cpu-coxdeboor --scenes patch144 \
  --samples 8x8 --repetitions 1 --out "$work/clash" >"$work/clash.log" 2>&1
code=$?
set -e
[ "$code" -eq 2 ] || { cat "$work/clash.log"; fail "a plugin named cpu-coxdeboor: exit $code, expected 2"; }
grep -q "strategy name 'cpu-coxdeboor' is already a strategy (built in)" "$work/clash.log" ||
  { cat "$work/clash.log"; fail "the clash's message"; }
[ ! -e "$work/clash" ] || fail "the refused run wrote $work/clash"

# ------------------------------------------------- the SISL plugin equals the built-in sisl
printf 'surface,u,v\n0,0,0\n0,1,1\n0,0.3,0.71\n0,0.999,0.001\n0,0.5,0.5\n' >"$work/uv.csv"
for scene in patch144 torus duck; do
  for precision in f32 f64; do
    for sampling in "--samples 33x17" "--span-samples 5" "--uv $work/uv.csv"; do
      [ "$scene" != duck ] || [ "${sampling%% *}" != --uv ] || continue  # the list names surface 0 only
      # shellcheck disable=SC2086
      "$nb" eval --scene "$scene" --strategy sisl --precision "$precision" $sampling \
        --out "$work/builtin.csv" 2>"$work/eval.log" || { cat "$work/eval.log"; fail "eval sisl"; }
      # shellcheck disable=SC2086
      "$nb" eval --plugin "$sisl" --scene "$scene" --strategy sisl-plugin --precision "$precision" \
        $sampling --out "$work/plugin.csv" 2>"$work/eval.log" ||
        { cat "$work/eval.log"; fail "eval sisl-plugin"; }
      cmp -s "$work/builtin.csv" "$work/plugin.csv" ||
        fail "sisl-plugin differs from sisl: $scene $precision $sampling"
      [ "$(wc -l <"$work/plugin.csv")" -gt 5 ] || fail "no points: $scene $precision $sampling"
    done
  done
done

# ------------------------------------------------------------------ gates naming a plugin
cat >"$work/gates.json" <<'JSON'
[{"strategy": "c-coxdeboor", "scene": "*", "metric": "max_ulp", "max": 32}]
JSON
"$nb" check --gates "$work/gates.json" --results "$work/run" >"$work/check.log" ||
  { cat "$work/check.log"; fail "a gate on c-coxdeboor"; }
cat >"$work/gates-broken.json" <<'JSON'
[{"strategy": "broken-nan", "scene": "*", "metric": "max_ulp", "max": 32}]
JSON
set +e
"$nb" check --gates "$work/gates-broken.json" --results "$work/run" >"$work/check.log"
code=$?
set -e
[ "$code" -eq 1 ] && grep -q "FAIL broken-nan on patch144" "$work/check.log" ||
  { cat "$work/check.log"; fail "a gate on broken-nan: exit $code, expected 1"; }

# ------------------------------------------------------------------------ list names them
"$nb" list --plugin "$coxdeboor" --json >"$work/list.json"
python3 - "$work/list.json" "$coxdeboor" <<'PY' || fail "list --plugin"
import json, sys
s = {x["name"]: x for x in json.load(open(sys.argv[1]))["strategies"]}
c = s["c-coxdeboor"]
assert c["role"] == "plugin" and c["library"]["path"] == sys.argv[2], c
assert c["capabilities"]["precisions"] == ["f32", "f64"] and not c["capabilities"]["normals"], c
PY
echo "plugins_test: ok"
