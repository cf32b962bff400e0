#!/usr/bin/env python3
"""tests/app/cmd_index_test.py: `ladarvr index` and `generate --out X.copc.laz` as a user
runs them, their COPC files read by the real laspy (LAZ through python3-laszip) and taken
apart by a parser of the COPC layout written here.

Usage: cmd_index_test.py LADARVR SCRATCH_DIR
  1. `generate` to PCD, PLY, LAS and LAZ; `index` of each gives a COPC file that laspy reads
     whole: the input's point count, class counts and positions (to the millimetre);
  2. every file: the info VLR first at 375, the LASzip VLR with variable chunks, the
     hierarchy EVLR whose pages (followed from the root page) hold every point once;
  3. `generate --out X.copc.laz` writes COPC; `--format laz` with that name is refused;
  4. the same file for --threads 1 and 3;
  5. --node-points caps every node (index and generate), with more nodes for a lower cap;
  6. bad runs (an output that is an input, a name not ending in .copc.laz, inputs whose
     fields differ, a missing input, a plan beyond --memory-mb, a cap out of range): exit 1,
     one line, no file.
"""
import os
import shutil
import struct
import subprocess
import sys

import laspy
import numpy as np

ladarvr, scratch = sys.argv[1:3]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
failures = []
checks = 0


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        failures.append(what)
        print("FAIL: " + what, file=sys.stderr)


def run(*args):
    return subprocess.run([ladarvr, *args], capture_output=True, text=True)


def path(name):
    return os.path.join(scratch, name)


SMALL = ["--views", "6", "--xres", "120", "--yres", "90"]


def copc_layout(name):
    """Parses the COPC layout; returns (point count, {key: count}) or raises."""
    data = open(name, "rb").read()
    assert data[:4] == b"LASF" and data[24:26] == bytes([1, 4])
    assert struct.unpack_from("<H", data, 94)[0] == 375
    point_data, vlrs = struct.unpack_from("<II", data, 96)
    evlr_at, evlrs, points = struct.unpack_from("<QIQ", data, 235)
    assert data[377:381] == b"copc" and struct.unpack_from("<HH", data, 393) == (1, 160)
    cx, cy, cz, half, spacing, root_at, root_size, gmin, gmax = struct.unpack_from("<5d2Q2d", data, 429)
    assert abs(spacing - 2 * half / 128) < 1e-12 * max(1.0, half)
    at, chunk_size = 375, None
    for _ in range(vlrs):
        user = data[at + 2:at + 18].rstrip(b"\0")
        rid, length = struct.unpack_from("<HH", data, at + 18)
        if user == b"laszip encoded" and rid == 22204:
            chunk_size = struct.unpack_from("<I", data, at + 54 + 12)[0]
        at += 54 + length
    assert at == point_data and chunk_size == 0xFFFFFFFF
    assert evlrs == 1 and data[evlr_at + 2:evlr_at + 6] == b"copc"
    assert struct.unpack_from("<H", data, evlr_at + 18)[0] == 1000
    size = struct.unpack_from("<Q", data, evlr_at + 20)[0]
    assert root_at == evlr_at + 60 and evlr_at + 60 + size == len(data)
    nodes, seen = {}, [0]

    def page(off, n):
        seen[0] += n
        for e in range(off, off + n, 32):
            level, x, y, z, offset, nbytes, count = struct.unpack_from("<4iQii", data, e)
            if count == -1:
                page(offset, nbytes)
            else:
                assert (level, x, y, z) not in nodes
                nodes[(level, x, y, z)] = count
                assert count == 0 or point_data + 8 <= offset < evlr_at

    page(root_at, root_size)
    assert seen[0] == size, "dead hierarchy space"
    assert sum(nodes.values()) == points
    return points, nodes


# 1 and 2: index from every format we read.
formats = {"pcd": "p.pcd", "ply": "p.ply", "las": "p.las", "laz": "p.laz"}
for fmt, name in formats.items():
    r = run("generate", "--out", path(name), *SMALL)
    check(r.returncode == 0, "generate " + name + ": " + r.stderr)
reference = laspy.read(path("p.laz"))
ref_xyz = np.sort(np.round(np.column_stack([reference.x, reference.y, reference.z]) * 1000).astype(np.int64), axis=0)
for fmt, name in formats.items():
    out = path("i_" + fmt + ".copc.laz")
    r = run("index", path(name), "--out", out, "--threads", "2")
    check(r.returncode == 0, "index " + name + ": " + r.stderr)
    if r.returncode != 0:
        continue
    check("index: wrote" in r.stderr, "index " + name + " prints its summary: " + r.stderr)
    las = laspy.read(out)
    check(len(las.points) == len(reference.points), fmt + ": laspy reads every point")
    check(las.header.point_format.id == 7, fmt + ": point format 7")
    check(np.array_equal(np.bincount(las.classification, minlength=65),
                         np.bincount(reference.classification, minlength=65)), fmt + ": class counts")
    xyz = np.sort(np.round(np.column_stack([las.x, las.y, las.z]) * 1000).astype(np.int64), axis=0)
    check(np.abs(xyz - ref_xyz).max() <= 1, fmt + ": positions to the millimetre")
    try:
        points, nodes = copc_layout(out)
        check(points == len(reference.points), fmt + ": header count")
        check(len(nodes) >= 1, fmt + ": nodes")
    except (AssertionError, struct.error) as e:
        check(False, fmt + ": COPC layout: " + repr(e))

# 3: generate writes COPC under a .copc.laz name, never a plain LAZ.
r = run("generate", "--out", path("g.copc.laz"), *SMALL)
check(r.returncode == 0, "generate g.copc.laz: " + r.stderr)
try:
    points, _ = copc_layout(path("g.copc.laz"))
    check(points == len(reference.points), "generate COPC: every point")
except (AssertionError, struct.error, FileNotFoundError) as e:
    check(False, "generate COPC layout: " + repr(e))
r = run("generate", "--out", path("h.copc.laz"), "--format", "laz", *SMALL)
check(r.returncode == 1 and not os.path.exists(path("h.copc.laz")), "generate .copc.laz --format laz refused")

# 4: the same bytes for any thread count.
run("index", path("p.laz"), "--out", path("t1.copc.laz"), "--threads", "1")
run("index", path("p.laz"), "--out", path("t3.copc.laz"), "--threads", "3")
check(open(path("t1.copc.laz"), "rb").read() == open(path("t3.copc.laz"), "rb").read(), "threads 1 and 3: same file")
# Merged inputs: twice the points.
r = run("index", path("p.las"), path("p.laz"), "--out", path("m.copc.laz"))
check(r.returncode == 0 and len(laspy.read(path("m.copc.laz")).points) == 2 * len(reference.points),
      "two inputs merged: " + r.stderr)

# A folder of tiles: its .las/.laz files in name order, the same bytes as those files named.
os.makedirs(path("tiles"))
shutil.copy(path("p.las"), path("tiles/a.las"))
shutil.copy(path("p.laz"), path("tiles/b.laz"))
with open(path("tiles/README.txt"), "w") as f:
    f.write("not a cloud\n")
r = run("index", path("tiles"), "--out", path("f.copc.laz"))
check(r.returncode == 0 and "2 inputs" in r.stdout + r.stderr, "a folder of two tiles: " + r.stdout + r.stderr)
run("index", path("tiles/a.las"), path("tiles/b.laz"), "--out", path("fn.copc.laz"))
check(open(path("f.copc.laz"), "rb").read() == open(path("fn.copc.laz"), "rb").read(),
      "a folder of tiles: the same bytes as its files named")
os.makedirs(path("empty_tiles"))
r = run("index", path("tiles"), "--out", path("tiles/all.copc.laz"))
check(r.returncode == 1 and "inside the input folder" in r.stderr and not os.path.exists(path("tiles/all.copc.laz")),
      "an output among the tiles it reads is refused: " + r.stderr)

# 5: the node cap.
_, default_nodes = copc_layout(path("t1.copc.laz"))
for cap in ("2000", "500"):
    r = run("index", path("p.laz"), "--out", path("n" + cap + ".copc.laz"), "--node-points", cap)
    check(r.returncode == 0, "index --node-points " + cap + ": " + r.stderr)
    _, nodes = copc_layout(path("n" + cap + ".copc.laz"))
    check(max(nodes.values()) <= int(cap), "--node-points " + cap + ": the largest node holds " +
          str(max(nodes.values())))
    check(len(nodes) > len(default_nodes), "--node-points " + cap + ": more nodes than the default cap's")
    default_nodes = nodes
r = run("generate", "--out", path("g500.copc.laz"), "--node-points", "500", *SMALL)
check(r.returncode == 0, "generate --node-points 500: " + r.stderr)
if r.returncode == 0:
    _, nodes = copc_layout(path("g500.copc.laz"))
    check(max(nodes.values()) <= 500, "generate --node-points 500: the largest node holds " + str(max(nodes.values())))
r = run("generate", "--out", path("g50.copc.laz"), "--node-points", "50", *SMALL)
check(r.returncode == 1 and "(--node-points) = 50: allowed 100 to 4000000" in r.stderr and
      not os.path.exists(path("g50.copc.laz")), "generate --node-points 50: " + r.stderr)


# 6: bad runs.
def bad(expect, *args):
    before = set(os.listdir(scratch))
    r = run("index", *args)
    lines = r.stderr.strip().splitlines()
    check(r.returncode == 1, "index " + " ".join(args) + ": exit " + str(r.returncode))
    check(len(lines) == 1 and expect in r.stderr, "index " + " ".join(args) + ": " + r.stderr)
    check(set(os.listdir(scratch)) == before, "index " + " ".join(args) + ": left files")


shutil.copy(path("i_laz.copc.laz"), path("in.copc.laz"))
bad("is the input file", path("in.copc.laz"), "--out", path("in.copc.laz"))
bad("allowed a name ending in .copc.laz", path("p.laz"), "--out", path("x.laz"))
bad("merged inputs must carry the same fields", path("p.pcd"), path("p.las"), "--out", path("y.copc.laz"))
bad("does not exist", path("missing.pcd"), "--out", path("y.copc.laz"))
bad("is a folder that holds no .las or .laz file", path("empty_tiles"), "--out", path("y.copc.laz"))
bad("raise --memory-mb", path("p.laz"), "--out", path("y.copc.laz"), "--memory-mb", "1")
bad("index: --node-points 99: allowed 100 to 4000000", path("p.laz"), "--out", path("y.copc.laz"),
    "--node-points", "99")
bad("index: --node-points 4000001: allowed 100 to 4000000", path("p.laz"), "--out", path("y.copc.laz"),
    "--node-points", "4000001")

print("%d checks, %d failed" % (checks, len(failures)))
sys.exit(1 if failures else 0)
