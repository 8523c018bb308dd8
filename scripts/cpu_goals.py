#!/usr/bin/env python3
"""Prints issue 6's goal ratios (Markdown) from the three result sets of scripts/cpu_goals.sh.
Every ratio divides two records of the same run: same machine state, same threads setting."""
import json
import sys
from pathlib import Path


def records(directory):
    document = json.loads((directory / "results.json").read_text())
    return document, {(r["scene"], r["strategy"]): r for r in document["records"]
                      if r["status"] == "ok"}


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "results/cpu-goals")
    f64, f64_records = records(root / "f64")
    _, f32_records = records(root / "f32")
    one, one_records = records(root / "f64-1thread")
    machine = f64["machine"]
    print("# Issue 6 CPU goals: measured ratios\n")
    print(f"Machine: {machine.get('cpu_model', '?')}, {machine.get('logical_cores', '?')} logical cores; "
          f"threads {f64['settings']['threads']} (1 in the one-thread run); commit "
          f"{machine.get('git_commit', '?')}. "
          "Regenerate: `scripts/cpu_goals.sh`.\n")
    print("| scene | goal | numerator | denominator | ratio | goal met |")
    print("|---|---|---|---|---|---|")
    scenes = sorted({scene for scene, _ in f64_records})

    def row(scene, goal, num, den, ratio, target):
        met = "yes" if ratio >= target else "no"
        print(f"| {scene} | {goal} | {num} | {den} | {ratio:.3g} | {met} |")

    def ms(r):
        return f"{r['strategy']} {r['evaluate']['median_s'] * 1e3:.3f} ms"

    for scene in scenes:
        t, s = f64_records.get((scene, "cpu-tensor")), f64_records.get((scene, "sisl"))
        if t and s:
            row(scene, "cpu-tensor f64 >= 10x SISL s1506 (stretch 20x)", ms(t), ms(s),
                s["evaluate"]["median_s"] / t["evaluate"]["median_s"], 10)
        t, lim = f32_records.get((scene, "cpu-tensor")), f32_records.get(
            (scene, "limit-store-bandwidth"))
        if t and lim:
            bytes_per_s = t["throughput_pts_per_s"] * lim["figures"]["bytes_per_point"]
            row(scene, "cpu-tensor f32 >= 50% of store bandwidth",
                f"{ms(t)} = {bytes_per_s / 1e9:.2f} GB/s written",
                f"store limit {lim['figures']['store_bytes_per_s'] / 1e9:.2f} GB/s",
                t["throughput_pts_per_s"] / lim["throughput_pts_per_s"], 0.5)
        t, c = one_records.get((scene, "cpu-tensor")), one_records.get((scene, "cpu-coxdeboor"))
        if t and c:
            row(scene, "cpu-tensor >= 5x cpu-coxdeboor, 1 thread (f64)", ms(t), ms(c),
                c["evaluate"]["median_s"] / t["evaluate"]["median_s"], 5)
    nosimd_dir = root / "f64-1thread-nosimd"
    if nosimd_dir.exists():
        _, nosimd = records(nosimd_dir)
        print("\nWhere cpu-tensor's gain over cpu-coxdeboor comes from (f64, 1024x1024): algorithm = "
              "cpu-coxdeboor / cpu-tensor with simd=off (one run, 1 thread); SIMD = simd=off / "
              "simd=on (two 1-thread runs); threads = 1 thread / all threads (two runs).\n")
        print("| scene | algorithm | SIMD | threads | total |")
        print("|---|---|---|---|---|")
        for scene in scenes:
            try:
                cox = nosimd[(scene, "cpu-coxdeboor")]["evaluate"]["median_s"]
                scalar = nosimd[(scene, "cpu-tensor")]["evaluate"]["median_s"]
                simd = one_records[(scene, "cpu-tensor")]["evaluate"]["median_s"]
                threads = f64_records[(scene, "cpu-tensor")]["evaluate"]["median_s"]
            except KeyError:
                continue
            print(f"| {scene} | {cox / scalar:.3g}x | {scalar / simd:.3g}x | "
                  f"{simd / threads:.3g}x | {cox / threads:.3g}x |")
    print("\nAll records of the f64 run:\n")
    print("| scene | strategy | evaluate median | points/s |")
    print("|---|---|---|---|")
    for (scene, strategy), r in sorted(f64_records.items()):
        print(f"| {scene} | {strategy} | {r['evaluate']['median_s'] * 1e3:.3f} ms | "
              f"{r['throughput_pts_per_s']:.3g} |")


if __name__ == "__main__":
    main()
