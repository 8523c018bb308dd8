#!/usr/bin/python3
"""Draws the charts of `nurbsbench report` from its chart JSON (nurbsbench-charts/1).

usage: plot_report.py CHARTS.json OUT_DIR

The report computes every number; this script only draws (matplotlib, Agg backend). It prints one
line per chart, "drawn ID FILE" or "failed ID: REASON", and exits 3 with "matplotlib missing:
REASON" when matplotlib cannot be imported. `nurbsbench report` embeds this file and runs it with
/usr/bin/python3 (or --python); it can also be run by hand on a report's charts.json.
"""
import json
import math
import os
import sys
import textwrap


def main():
    if len(sys.argv) != 3:
        print("usage: plot_report.py CHARTS.json OUT_DIR", file=sys.stderr)
        return 2
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt  # noqa: F401
        from matplotlib.colors import LogNorm  # noqa: F401
    except Exception as e:  # ImportError, or a broken installation
        print(f"matplotlib missing: {type(e).__name__}: {e}")
        return 3
    with open(sys.argv[1]) as f:
        document = json.load(f)
    failures = 0
    for chart in document.get("charts", []):
        chart_id = chart.get("id", "chart")
        path = os.path.join(sys.argv[2], chart.get("file", chart_id + ".png"))
        try:
            draw(chart, path)
            print(f"drawn {chart_id} {path}")
        except Exception as e:  # one bad chart must not stop the others
            failures += 1
            print(f"failed {chart_id}: {type(e).__name__}: {e}".replace("\n", " "))
    return 0


def finite(x):
    return x is not None and isinstance(x, (int, float)) and math.isfinite(x)


def positive(x):
    return finite(x) and x > 0


def draw(chart, path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 6.5))
    kind = chart["kind"]
    if kind == "lines":
        lines(ax, chart)
    elif kind == "bars":
        bars(ax, chart)
    elif kind == "stacked":
        stacked(ax, chart)
    elif kind == "heatmap":
        heatmap(fig, ax, chart)
    else:
        raise ValueError(f"unknown chart kind {kind!r}")
    title = chart.get("title", "")
    context = "\n".join(textwrap.wrap(chart.get("context", ""), 140))
    ax.set_title(title + ("\n" + context if context else ""), fontsize=9, loc="left")
    command = "\n".join(textwrap.wrap("regenerate: " + chart.get("command", ""), 150))
    fig.text(0.01, 0.01, command, fontsize=7, family="monospace", va="bottom")
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def style(k):
    """Series k's colour (tab20's dark shades, then its light ones: 20 distinct colours), with a
    marker and a line style that also differ, so series stay apart past 20 and in grey print."""
    import matplotlib.pyplot as plt

    colors = plt.get_cmap("tab20").colors
    return {
        "color": colors[(2 * k) % 20 + (k // 10) % 2],
        "marker": "osD^vPX*<>"[k % 10],
        "linestyle": "-" if (k // 10) % 2 == 0 else "--",
    }


def lines(ax, chart):
    """Series with "axis": "y2" go on a second y axis at the right (y2label, y2log): two
    quantities of one x, e.g. frame time and triangles per frame along a camera path."""
    xlog, ylog = chart.get("xlog", False), chart.get("ylog", False)
    right = None
    for k, s in enumerate(chart["series"]):
        on_right = s.get("axis") == "y2"
        if on_right and right is None:
            right = ax.twinx()
            right.set_ylabel(chart.get("y2label", ""))
            if chart.get("y2log", False):
                right.set_yscale("log")
        target = right if on_right else ax
        logy = chart.get("y2log", False) if on_right else ylog
        pts = [
            (x, y)
            for x, y in zip(s["x"], s["y"])
            if finite(x) and finite(y) and (not xlog or x > 0) and (not logy or y > 0)
        ]
        if pts:
            target.plot([p[0] for p in pts], [p[1] for p in pts], label=s["label"], markersize=5,
                        **style(k))
    if xlog:
        ax.set_xscale("log", base=2)
    if ylog:
        ax.set_yscale("log")
    ax.set_xlabel(chart.get("xlabel", ""))
    ax.set_ylabel(chart.get("ylabel", ""))
    ax.grid(True, which="both", alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if right is not None:
        more_handles, more_labels = right.get_legend_handles_labels()
        handles, labels = handles + more_handles, labels + more_labels
    ax.legend(handles, labels, fontsize=7, ncol=2)


def bars(ax, chart):
    categories = chart["categories"]
    series = chart["series"]
    width = 0.8 / max(1, len(series))
    for k, s in enumerate(series):
        xs = [c + (k - (len(series) - 1) / 2) * width for c in range(len(categories))]
        ys = [v if positive(v) else 0 for v in s["values"]]
        ax.bar(xs, ys, width=width, label=s["label"], color=style(k)["color"])
    ax.set_xticks(range(len(categories)))
    ax.set_xticklabels(categories, rotation=20 if len(categories) > 4 else 0, fontsize=8)
    if chart.get("ylog") and any(positive(v) for s in series for v in s["values"]):
        ax.set_yscale("log")
    ax.set_ylabel(chart.get("ylabel", ""))
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)


def stacked(ax, chart):
    categories = chart["categories"]
    bottom = [0.0] * len(categories)
    for stack in chart["stacks"]:
        values = [v if positive(v) else 0 for v in stack["values"]]
        ax.bar(range(len(categories)), values, bottom=bottom, label=stack["label"])
        bottom = [b + v for b, v in zip(bottom, values)]
    ax.set_xticks(range(len(categories)))
    ax.set_xticklabels(categories, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel(chart.get("ylabel", ""))
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8)


def heatmap(fig, ax, chart):
    import numpy as np
    from matplotlib.colors import LogNorm

    rows, cols = chart["rows"], chart["cols"]
    grid = np.full((len(rows), len(cols)), np.nan)
    for i, row in enumerate(chart["values"]):
        for j, v in enumerate(row):
            if v == "inf":
                grid[i, j] = np.inf
            elif finite(v):
                grid[i, j] = v
    shown = np.where(np.isfinite(grid), np.maximum(grid, 1e-3), np.nan)
    finite_values = shown[np.isfinite(shown)]
    vmax = float(finite_values.max()) if finite_values.size else 1.0
    vmin = float(finite_values.min()) if finite_values.size else 1e-3
    if vmax <= vmin:
        vmax = vmin * 10
    image = ax.imshow(shown, aspect="auto", cmap="viridis", norm=LogNorm(vmin=vmin, vmax=vmax))
    fig.colorbar(image, ax=ax, label=chart.get("colorbar", ""))
    ax.set_xticks(range(len(cols)))
    ax.set_xticklabels(cols, rotation=60, ha="right", fontsize=7)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels(rows, fontsize=7)
    for i in range(len(rows)):
        for j in range(len(cols)):
            v = grid[i, j]
            text = "inf" if np.isinf(v) else ("" if np.isnan(v) else f"{v:.2g}")
            if text:
                ax.text(j, i, text, ha="center", va="center", fontsize=6, color="white")


if __name__ == "__main__":
    sys.exit(main())
