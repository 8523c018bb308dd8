#!/usr/bin/env python3
"""Issue 30's CPU goals, each case run three times in separate processes (nurbsbench_gbench with
one --benchmark_filter each), reported as min / median / max of the ratio with the machine's CPU
model and the memory write speed the store pass measured in the same process.

Every ratio is taken inside one process: the store-limit cases time cpu-tensor's evaluate() and a
store pass (over at least 4x the last-level cache, harness/store_limit.h) alternately, the
trim-cost cases evaluate() and classify() alternately, so load from other processes falls on both
sides alike. Three processes give the spread a single run hides: quote the median and the spread,
never the best run.

Usage: cpu_goals30.py BUILD_DIR OUT_DIR [RUNS]; writes OUT_DIR/raw/*.json and OUT_DIR/GOALS.md
(also printed). THREADS (default 2) sets OMP_NUM_THREADS for the strategy and the store pass.
"""
import json
import os
import platform
import statistics
import subprocess
import sys
from pathlib import Path

# (goal, benchmark name, counter, target). of_store_limit = store time / evaluate time for the
# same points and bytes; kept = evaluate / (evaluate + classify); speedup = cpu-tspline's evaluate
# time / cpu-tspline-bezier's, alternating in one process.
GOALS = [
    ("patch144 4096^2 f32 positions", "store-limit/cpu-tensor/patch144/4096x4096/f32/stores=cached",
     "of_store_limit", 0.8),
    ("patch144 4096^2 f64 positions", "store-limit/cpu-tensor/patch144/4096x4096/f64/stores=cached",
     "of_store_limit", 0.8),
    ("patch144 4096^2 f32 + normals",
     "store-limit/cpu-tensor/patch144/4096x4096/f32+normals/stores=cached", "of_store_limit", 0.6),
    ("patch144 4096^2 f64 + normals",
     "store-limit/cpu-tensor/patch144/4096x4096/f64+normals/stores=cached", "of_store_limit", 0.6),
    ("many-4096 at 64^2 f32", "store-limit/cpu-tensor/many-4096/64x64/f32/stores=cached",
     "of_store_limit", 0.7),
    ("hammer 256^2 a face, trimmed / untrimmed", "trim-cost/cpu-tensor/hammer/256x256/f32", "kept",
     0.8),
    ("bearing.iges 256^2 a face, trimmed / untrimmed", "trim-cost/cpu-tensor/bearing/256x256/f32",
     "kept", 0.8),
    ("T-spline fast path, tsm-gearbox 1024^2 f32",
     "tspline-speedup/cpu-tspline-bezier/tsm-gearbox/1024x1024/f32", "speedup", 20),
    ("T-spline fast path, tspline-tjunction 1024^2 f32",
     "tspline-speedup/cpu-tspline-bezier/tspline-tjunction/1024x1024/f32", "speedup", 20),
]


def cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def run_case(gbench, name, out, run, env):
    path = out / "raw" / f"{name.replace('/', '_').replace('+', '_')}-{run}.json"
    pattern = name.replace(".", "\\.").replace("+", "\\+")  # gbench names carry /manual_time
    command = [str(gbench), f"--benchmark_filter=^{pattern}(/manual_time)?$", "--benchmark_min_time=1",
               "--benchmark_format=json", f"--benchmark_out={path}"]
    subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    cases = [b for b in json.loads(path.read_text())["benchmarks"] if b.get("run_type") == "iteration"]
    return cases[0] if cases else None


def main():
    build, out = Path(sys.argv[1]), Path(sys.argv[2])
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    gbench = build / "harness" / "nurbsbench_gbench"
    (out / "raw").mkdir(parents=True, exist_ok=True)
    threads = os.environ.get("THREADS", "2")
    env = dict(os.environ, OMP_NUM_THREADS=threads)
    rows, speeds = [], []
    for goal, name, counter, target in GOALS:
        values = []
        for run in range(runs):
            case = run_case(gbench, name, out, run, env)
            if case is None or counter not in case:
                continue
            values.append(case[counter])
            # The store pass's bytes/s: the result's bytes over its (scaled) mean time.
            if counter == "of_store_limit" and case.get("store_ms") and case.get("points/s"):
                points = case["points/s"] * case["evaluate_ms"] / 1e3
                bytes_per_point = (24 if "f64" in name else 12) * (2 if "normals" in name else 1)
                speeds.append(points * bytes_per_point / (case["store_ms"] / 1e3) / 1e9)
        rows.append((goal, name, target, values))
    commit = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], capture_output=True,
                            text=True).stdout.strip() or "unknown"
    load = os.getloadavg()
    lines = ["# Issue 30 CPU goals: measured ratios", "",
             f"Machine: {cpu_model()}, {os.cpu_count()} logical cores; threads {threads}; commit "
             f"{commit}; load average at the end {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f}. "
             f"Each case {runs} times, separate processes. Regenerate: `scripts/cpu_goals.sh` "
             "(issue 30 part only: `ONLY=30 scripts/cpu_goals.sh`).", ""]
    if speeds:
        lines += [f"Memory write speed (the store pass over >= 4x the last-level cache): median "
                  f"{statistics.median(speeds):.1f} GB/s, min {min(speeds):.1f}, max "
                  f"{max(speeds):.1f} over the store-limit cases.", ""]
    lines += ["| goal | case | target | min | median | max | median meets target |",
              "|---|---|---|---|---|---|---|"]
    for goal, name, target, values in rows:
        if not values:
            lines.append(f"| {goal} | `{name}` | >= {target} | - | - | - | not measured |")
            continue
        median = statistics.median(values)
        lines.append(f"| {goal} | `{name}` | >= {target} | {min(values):.3f} | {median:.3f} | "
                     f"{max(values):.3f} | {'yes' if median >= target else 'no'} |")
    lines += ["", "Not measured here: the read-back spread, asserted as page faults by "
              "tests/harness/phase_reuse_test.cpp rather than timed."]
    text = "\n".join(lines) + "\n"
    (out / "GOALS.md").write_text(text)
    print(text, end="")


if __name__ == "__main__":
    main()
