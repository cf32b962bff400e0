#!/usr/bin/env python3
"""Plot error against time of the visibility metric (paper §IV-B) from `ladarvr bench metric`.

Usage: python3 scripts/plot_metric_bench.py out/bench_metric.csv docs/img/metric_error_vs_time.png

One column per scene: x = median milliseconds per view (log), y = mean absolute error
against the exact Embree reference of the paper's point metric (xor, top row) and of the
depth-aware variant (bottom row); one marker shape per resolution, the
splat size written next to each point, filled markers with skips, hollow without; black
crosses: the GL_POINTS rasteriser baseline.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    with open(argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.stderr.write(f"plot_metric_bench: {argv[1]}: no rows\n")
        return 1
    scenes = sorted({r["scene"] for r in rows}, key=lambda s: (s != "demo", s))
    markers = {128: "o", 256: "s", 512: "D", 1024: "^"}
    colours = {128: "tab:blue", 256: "tab:green", 512: "tab:orange", 1024: "tab:red"}
    panels = [("mae_metric", "MAE of |I2 xor I3| / |I1| (paper) vs exact"),
              ("mae_depth", "MAE of the depth-aware variant vs exact")]
    fig, axes = plt.subplots(len(panels), len(scenes), figsize=(6.5 * len(scenes), 4.6 * len(panels)),
                             squeeze=False)
    for row_axes, (column, ylabel) in zip(axes, panels):
        for ax, scene in zip(row_axes, scenes):
            for r in (r for r in rows if r["scene"] == scene):
                res = int(r["resolution"])
                skip = r["skip"] == "1"
                if r.get("rasterizer", "compute") == "raster":
                    if column != "mae_metric":
                        continue  # the raster path has no depth-aware variant
                    ax.scatter(float(r["ms_per_view"]), float(r[column]), marker="x" if skip else "+", s=60,
                               color="k")
                    continue
                x, y = float(r["ms_per_view"]), float(r[column])
                ax.scatter(x, y, marker=markers.get(res, "x"), s=45,
                           facecolors=colours.get(res, "k") if skip else "none",
                           edgecolors=colours.get(res, "k"))
                ax.annotate(r["splat_px"], (x, y), textcoords="offset points", xytext=(4, 3), fontsize=7)
            for res, m in markers.items():
                ax.scatter([], [], marker=m, color=colours[res], label=f"{res} px")
            ax.scatter([], [], marker="o", facecolors="none", edgecolors="k", label="without skips (hollow)")
            if column == "mae_metric":
                ax.scatter([], [], marker="x", color="k", label="GL_POINTS baseline, 512 px (+: no skips)")
            ax.set_xscale("log")
            ax.set_xlabel("median time per view, ms (GPU part, llvmpipe)")
            ax.set_ylabel(ylabel)
            ax.set_title(f"{scene} scene (labels: splat px)")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.suptitle("Visibility metric (paper §IV-B): error against run time")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
