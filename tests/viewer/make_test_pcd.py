#!/usr/bin/env python3
"""tests/viewer/make_test_pcd.py OUT.pcd: a known binary PCD for the viewer's streaming test:
a white 120 m x 120 m ground grid and a red 8 m x 4 m x 3 m block (label target) at the
centre, 163,840 points in all, origin 10^6 m away (as the generator writes them)."""
import struct
import sys

out = sys.argv[1]
points = []
n_ground = 400  # 400 x 400 = 160,000 ground points, 0.3 m apart
for i in range(n_ground):
    for j in range(n_ground):
        points.append((-60.0 + i * 0.3, -60.0 + j * 0.3, 0.0, 0xFFFFFF, 0))
# 3,840 target points on the block's top and sides.
k = 0
while len(points) < 163840:
    u, v = (k % 64) / 63.0, (k // 64 % 60) / 59.0
    if k < 1920:
        points.append((-4.0 + 8.0 * u, -2.0 + 4.0 * v, 3.0, 0xFF0000, 2))
    else:
        points.append((-4.0 + 8.0 * u, -2.0, 3.0 * v, 0xFF0000, 2))
    k += 1
header = ("# .PCD v0.7 - Point Cloud Data file format\n"
          "# ladarvr origin 1000000 2000000 50\n"
          "VERSION 0.7\nFIELDS x y z rgb label\nSIZE 4 4 4 4 1\nTYPE F F F U U\nCOUNT 1 1 1 1 1\n"
          f"WIDTH {len(points)}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(points)}\nDATA binary\n")
with open(out, "wb") as f:
    f.write(header.encode())
    f.write(b"".join(struct.pack("<fffIB", *p) for p in points))
