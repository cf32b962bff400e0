#!/usr/bin/env python3
"""Writes a synthetic corridor survey (a road, rail or power-line flight) as LAS, for timing
`ladarvr ground` on a survey whose bounding box is mostly empty (python3 with laspy and
numpy, deterministic).

    python3 scripts/make_corridor.py --out FILE.las [--length-m 2000] [--width-m 60]
                                     [--points-per-m2 2] [--seed 3]

The strip runs diagonally (45 degrees), so its box is about length / sqrt(2) on a side
and the strip covers a small share of it (6 % with the defaults: 1457 x 1456 cells of
1 m around 240,000 points). The ground rises 2 % along the strip with a 0.5 m wave every
314 m and 5 cm of noise; 15 % of the points stand 1-13 m above it (vegetation and
buildings, uniformly). LAS 1.2, point format 1, scale 0.01 m, UTM-like offsets; no
classes (every point class 0), so `ladarvr ground` classifies all of it.
"""
import argparse

import laspy
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="LAS file to write")
    ap.add_argument("--length-m", type=float, default=2000.0)
    ap.add_argument("--width-m", type=float, default=60.0)
    ap.add_argument("--points-per-m2", type=float, default=2.0)
    ap.add_argument("--seed", type=int, default=3)
    a = ap.parse_args()
    if not (a.length_m > 0 and a.width_m > 0 and a.points_per_m2 > 0):
        ap.error("--length-m, --width-m and --points-per-m2: allowed > 0")
    rng = np.random.default_rng(a.seed)
    n = int(a.length_m * a.width_m * a.points_per_m2)
    along = rng.random(n) * a.length_m
    across = (rng.random(n) - 0.5) * a.width_m
    half = np.sqrt(0.5)
    x = 500000.0 + (along - across) * half
    y = 5000000.0 + (along + across) * half
    z = 100.0 + 0.02 * along + 0.5 * np.sin(along / 50.0) + rng.normal(0.0, 0.05, n)
    raised = rng.random(n) < 0.15
    z[raised] += rng.random(int(raised.sum())) * 12.0 + 1.0
    header = laspy.LasHeader(point_format=1, version="1.2")
    header.scales = [0.01, 0.01, 0.01]
    header.offsets = [500000.0, 5000000.0, 0.0]
    las = laspy.LasData(header)
    las.x, las.y, las.z = x, y, z
    las.write(a.out)
    print(f"{a.out}: {n} points")


if __name__ == "__main__":
    main()
