#!/usr/bin/env python3
"""Draws a DTM written by `ladarvr ground --dtm` (an ESRI ASCII grid or a GeoTIFF) as a shaded relief,
and beside it, with --cloud, the surface of the survey's highest returns over the same
cells, so the two show what the ground filter took away (python3 with numpy and
matplotlib; laspy for --cloud).

    python3 scripts/dtm_hillshade.py DTM.asc|DTM.tif --out PICTURE.png [--cloud SURVEY.laz]
                                     [--block K] [--title TEXT] [--width-px 1400]

The relief is lit from the north-west, 45 degrees up (the cartographer's convention),
and tinted by height; cells holding -9999 (no tile held a point) are left white. The
heights and cells are the grid's own (in feet for a survey in feet), so the shading is
the same whatever the unit.
"""
import argparse
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_geotiff(path):
    """A GeoTIFF as ladarvr writes one (one band of floats, north up, placed by its
    pixel scale and one tie point at its top-left corner; PIL reads it): its heights and
    the ASCII grid's header for them."""
    from PIL import Image

    with Image.open(path) as img:
        z = np.asarray(img, dtype=np.float64)
        scale = img.tag_v2.get(33550)
        tie = img.tag_v2.get(33922)
        nodata = img.tag_v2.get(42113)
    if not scale or not tie or len(tie) < 6 or tie[0] != 0 or tie[1] != 0:
        sys.exit("dtm_hillshade: %s: no pixel scale and top-left tie point (not a GeoTIFF of ladarvr ground --dtm)"
                 % path)
    rows, cols = z.shape
    head = {"ncols": cols, "nrows": rows, "cellsize": float(scale[0]), "xllcorner": float(tie[3]),
            "yllcorner": float(tie[4]) - rows * float(scale[1])}
    if nodata is not None:
        z[z == float(str(nodata).strip("\0 "))] = np.nan
    return z, head


def read_grid(path):
    """The grid's heights (row 0 the northernmost, NaN where NODATA) and its header (the
    ESRI ASCII grid's keys, lower case)."""
    if path.lower().endswith((".tif", ".tiff")):
        return read_geotiff(path)
    head = {}
    with open(path) as f:
        for _ in range(6):
            key, value = f.readline().split()
            head[key.lower()] = float(value)
    z = np.loadtxt(path, skiprows=6, ndmin=2)
    z[z == head["nodata_value"]] = np.nan
    return z, head


def shade(z, cell, azimuth_deg=315.0, altitude_deg=45.0):
    """Lambertian hillshade in [0, 1] of heights `z` (row 0 north) on square cells."""
    filled = np.where(np.isnan(z), np.nanmin(z), z)
    dz_dy, dz_dx = np.gradient(filled, cell)
    dz_dy = -dz_dy  # rows run south, y north
    slope = np.arctan(np.hypot(dz_dx, dz_dy))
    aspect = np.arctan2(dz_dy, -dz_dx)
    az = np.radians(360.0 - azimuth_deg + 90.0)
    alt = np.radians(altitude_deg)
    lit = np.sin(alt) * np.cos(slope) + np.cos(alt) * np.sin(slope) * np.cos(az - aspect)
    return np.clip(lit, 0.0, 1.0)


def relief(z, cell, lo, hi):
    """RGB of `z`: heights tinted on a terrain map from `lo` to `hi`, times the shading."""
    tint = plt.get_cmap("terrain")(np.clip((z - lo) / max(hi - lo, 1e-9), 0, 1) * 0.8 + 0.15)[..., :3]
    rgb = tint * (0.35 + 0.65 * shade(z, cell))[..., None]
    rgb[np.isnan(z)] = 1.0
    return rgb


def highest_surface(cloud, head, shape, block):
    """The highest return in each block of `block` x `block` of the grid's cells, each
    block's value on its cells (NaN where none): a sparse survey leaves most single cells
    empty."""
    import laspy

    las = laspy.read(cloud)
    cell = head["cellsize"] * block
    rows, cols = -(-shape[0] // block), -(-shape[1] // block)
    i = np.floor((np.asarray(las.x) - head["xllcorner"]) / cell).astype(np.int64)
    j = rows - 1 - np.floor((np.asarray(las.y) - head["yllcorner"]) / cell).astype(np.int64)
    keep = (i >= 0) & (i < cols) & (j >= 0) & (j < rows)
    top = np.full(rows * cols, -np.inf)
    np.maximum.at(top, j[keep] * cols + i[keep], np.asarray(las.z)[keep])
    top[np.isinf(top)] = np.nan
    # Rows counted from the grid's top, which lies shape[0] cells above yllcorner.
    top = top.reshape(rows, cols)
    offset = rows * block - shape[0]
    full = np.repeat(np.repeat(top, block, axis=0), block, axis=1)
    return full[offset:offset + shape[0], : shape[1]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dtm", help="an ESRI ASCII grid (.asc) or a GeoTIFF (.tif) written by ladarvr ground --dtm")
    parser.add_argument("--out", required=True, help="the PNG to write")
    parser.add_argument("--cloud", help="the survey (LAS/LAZ): its highest returns drawn beside the DTM")
    parser.add_argument("--block", type=int, default=1,
                        help="with --cloud: the highest return of each block of this many cells a side")
    parser.add_argument("--title", default="", help="a line above the picture")
    parser.add_argument("--width-px", type=int, default=1400, help="the picture's width in pixels")
    a = parser.parse_args()
    z, head = read_grid(a.dtm)
    if np.isnan(z).all():
        sys.exit("dtm_hillshade: %s: every cell is NODATA" % a.dtm)
    panels = [("the ground (ladarvr ground --dtm)", z)]
    if a.cloud:
        name = "the highest return in each cell" if a.block == 1 else "the highest return in each %g x %g m" % (
            a.block * head["cellsize"], a.block * head["cellsize"])
        panels.insert(0, (name, highest_surface(a.cloud, head, z.shape, a.block)))
    rows, cols = z.shape
    width_in = a.width_px / 100.0
    height_in = width_in / len(panels) * rows / cols + (0.6 if a.title else 0.3)
    fig, axes = plt.subplots(1, len(panels), figsize=(width_in, height_in), dpi=100, squeeze=False)
    lo, hi = np.nanpercentile(z, 1), np.nanpercentile(z, 99)  # both panels on the ground's range
    for ax, (name, surface) in zip(axes[0], panels):
        ax.imshow(relief(surface, head["cellsize"], lo, hi), interpolation="bilinear")
        ax.set_title(name, fontsize=11)
        ax.set_axis_off()
    if a.title:
        fig.suptitle(a.title, fontsize=12)
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)
    print("dtm_hillshade: wrote %s (%d x %d cells)" % (a.out, cols, rows))


if __name__ == "__main__":
    main()
