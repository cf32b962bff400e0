#!/usr/bin/env python3
"""Plot the precision-recall curves of `ladarvr bench detect` (the trained detector and the
clustering baseline on the same evaluation clouds).

Usage: python3 scripts/plot_detect_pr.py out/bench_detect_pr.csv docs/img/detect_pr.png

x = recall (the share of clouds whose target a candidate at or above the threshold finds),
y = precision (true candidates / candidates at or above it); a marker where the curve first
reaches 90 % recall, labelled with the false candidates per cloud there.
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
        sys.stderr.write(f"plot_detect_pr: {argv[1]}: no rows\n")
        return 1
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    colours = {"trained": "tab:blue", "baseline": "tab:orange"}
    for detector in ("trained", "baseline"):
        curve = [r for r in rows if r["detector"] == detector]
        if not curve:
            continue
        recall = [float(r["recall"]) for r in curve]
        precision = [float(r["precision"]) for r in curve]
        ax.plot(recall, precision, color=colours[detector], label=detector)
        at90 = next((r for r in curve if float(r["recall"]) >= 0.9), None)
        if at90:
            x, y = float(at90["recall"]), float(at90["precision"])
            ax.scatter([x], [y], color=colours[detector], zorder=3)
            ax.annotate(f"{float(at90['false_per_cloud']):.1f} false / cloud", (x, y), textcoords="offset points",
                        xytext=(-110, 8), fontsize=8, color=colours[detector])
    ax.set_xlim(0, 1.02)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("recall: clouds whose target is found")
    ax.set_ylabel("precision: true candidates / candidates")
    ax.set_title("ladarvr bench detect: trained detector vs clustering baseline")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
