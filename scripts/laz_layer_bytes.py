#!/usr/bin/env python3
"""Bytes per point of each compressed layer of a LAZ 1.4 file (point formats 6-8, LASzip's
layered chunks): of a plain LAZ file's chunks in all, or of a COPC file's nodes level by
level. Reads the layer sizes each chunk records; decodes nothing.

    python3 scripts/laz_layer_bytes.py FILE.laz
    python3 scripts/laz_layer_bytes.py FILE.copc.laz --copc
"""
import argparse
import collections
import struct
import sys

BASE = {6: 30, 7: 36, 8: 38}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--copc", action="store_true", help="group the nodes by octree level")
    a = ap.parse_args()
    data = open(a.file, "rb").read()
    fmt, record = data[104] & 0x3F, struct.unpack_from("<H", data, 105)[0]
    if fmt not in BASE:
        sys.exit(f"{a.file}: point format {fmt}: allowed 6, 7 or 8 (LAZ 1.4 layered chunks)")
    names = ["xy", "z", "class", "flags", "intensity", "scan", "user", "source", "gps"]
    names += (["rgb"] if fmt >= 7 else []) + (["nir"] if fmt == 8 else [])
    names += [f"extra{i}" for i in range(record - BASE[fmt])]
    head = record + 4 + 4 * len(names)  # the first point raw, the count, the layer sizes

    bytes_of = collections.defaultdict(collections.Counter)
    points = collections.Counter()

    def chunk(group, off):
        n = struct.unpack_from("<I", data, off + record)[0]
        sizes = struct.unpack_from(f"<{len(names)}I", data, off + record + 4)
        points[group] += n  # the chunk's points, its first one included
        bytes_of[group]["first point and sizes"] += head
        for k, v in zip(names, sizes):
            bytes_of[group][k] += v
        return n, head + sum(sizes)

    if a.copc:
        root_off, root_size = struct.unpack_from("<QQ", data, 375 + 54 + 40)

        def page(off, size):
            for e in range(size // 32):
                level, _, _, _, o, bs, pc = struct.unpack_from("<4iQii", data, off + 32 * e)
                if pc == -1:
                    page(o, bs)
                elif pc > 0:
                    chunk(f"level {level}", o)

        page(root_off, root_size)
    else:
        off = struct.unpack_from("<I", data, 96)[0] + 8
        total = struct.unpack_from("<Q", data, 247)[0]
        seen = 0
        while seen < total:
            n, size = chunk("all", off)
            seen, off = seen + n, off + size

    for group in sorted(points, key=lambda g: (len(g), g)):
        n, b = points[group], bytes_of[group]
        parts = " ".join(f"{k} {v / n:.2f}" for k, v in b.items() if v / n >= 0.005)
        print(f"{group}: {n} points, {sum(b.values()) / n:.2f} B/point: {parts}")


if __name__ == "__main__":
    main()
