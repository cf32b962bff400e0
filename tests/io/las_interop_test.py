#!/usr/bin/env python3
"""tests/io/las_interop_test.py: our LAS/LAZ and PLY files against the real laspy
(LAZ through python3-laszip) and Open3D, and theirs against our reader.

Usage: las_interop_test.py CLOUD_TOOL LADARVR SCRATCH_DIR
  1. our LAS and LAZ at a 10^7 m origin, read by laspy: every field equals what our
     reader reads (positions within 1 mm);
  2. LAS 1.2 and LAZ 1.4 written by laspy (not by us), read by our reader;
  3. our PLY read by Open3D: every scalar_* property kept, positions equal;
  4. `ladarvr generate` to PCD and LAZ: the same points, field for field;
  5. `ladarvr metric --p1/--p2/--p3` on LAZ clouds gives the metric of the PCD ones.
"""
import os
import shutil
import subprocess
import sys

import laspy
import numpy as np

tool, ladarvr, scratch = sys.argv[1:4]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
failures = []
checks = 0


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        failures.append(what)


def dump(path):
    """Our reader's view of a file: world x y z, rgb, label, view, range, intensity,
    return number, returns, incidence, scan angle, height above ground."""
    out = subprocess.run([tool, "dump", path], check=True, capture_output=True, text=True).stdout.splitlines()
    count = int(out[0].split()[1])
    rows = np.array([[float(v) for v in line.split()] for line in out[1:]]).reshape(count, 13)
    return rows


def near(a, b, tol):
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= tol))


origin = ("10000000.0", "5400000.0", "250.0")
# --- 1. our LAS and LAZ read by laspy -------------------------------------------------
for name in ("ours.las", "ours.laz"):
    path = os.path.join(scratch, name)
    subprocess.run([tool, "write", path, *origin], check=True)
    ours = dump(path)
    las = laspy.read(path)
    check(las.header.version.major == 1 and las.header.version.minor == 4, f"{name}: LAS 1.4")
    check(las.header.point_format.id == 7, f"{name}: point format 7")
    check(len(las.points) == len(ours), f"{name}: {len(las.points)} points, ours {len(ours)}")
    check(list(las.header.scales) == [0.001] * 3, f"{name}: scale 0.001")
    xyz = np.stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)], axis=1)
    check(near(xyz, ours[:, 0:3], 0.001), f"{name}: positions within 1 mm")
    check(abs(xyz[:, 0].mean() - 1e7) < 100, f"{name}: georeferenced at 10^7 m")
    rgb = (np.asarray(las.red).astype(np.int64) >> 8 << 16) | (np.asarray(las.green).astype(np.int64) >> 8 << 8) \
        | (np.asarray(las.blue).astype(np.int64) >> 8)
    check(np.array_equal(rgb, ours[:, 3].astype(np.int64)), f"{name}: rgb")
    role_class = np.array([2, 1, 64])[ours[:, 4].astype(int)]
    check(np.array_equal(np.asarray(las.classification), role_class), f"{name}: classification from the role")
    check(np.array_equal(np.asarray(las["label"]), ours[:, 4]), f"{name}: label extra bytes")
    check(np.array_equal(np.asarray(las.point_source_id), ours[:, 5]), f"{name}: point source ID = view")
    check(np.array_equal(np.asarray(las.gps_time), ours[:, 5] * 1.0), f"{name}: GPS time of the view")
    check(np.array_equal(np.asarray(las["range"], dtype=np.float32), ours[:, 6].astype(np.float32)), f"{name}: range")
    check(np.array_equal(np.asarray(las.intensity), ours[:, 7]), f"{name}: intensity")
    check(np.array_equal(np.asarray(las.return_number), ours[:, 8]), f"{name}: return number")
    check(np.array_equal(np.asarray(las.number_of_returns), ours[:, 9]), f"{name}: number of returns")
    check(np.array_equal(np.asarray(las["incidence_deg"], dtype=np.float32), ours[:, 10].astype(np.float32)),
          f"{name}: incidence")
    check(near(np.asarray(las.scan_angle) * 0.006, ours[:, 11], 0.0031), f"{name}: scan angle")
    check(np.array_equal(np.asarray(las["height_above_ground_m"], dtype=np.float32), ours[:, 12].astype(np.float32)),
          f"{name}: height above ground")

# --- 2. files written by laspy, read by our reader -------------------------------------
rng = np.random.default_rng(7)
n = 5000
for name, fmt, version in (("laspy12.las", 3, "1.2"), ("laspy14.laz", 7, "1.4")):
    header = laspy.LasHeader(point_format=fmt, version=version)
    header.scales = np.array([0.001, 0.001, 0.001])
    header.offsets = np.array([10000000.0, 5400000.0, 0.0])
    data = laspy.LasData(header)
    data.x = 10000000.0 + rng.uniform(-500, 500, n)
    data.y = 5400000.0 + rng.uniform(-500, 500, n)
    data.z = rng.uniform(0, 80, n)
    data.intensity = rng.integers(0, 65535, n, dtype=np.uint16)
    classes = rng.choice(np.array([1, 2, 6, 64 if fmt >= 6 else 5], dtype=np.uint8), n)
    data.classification = classes
    data.point_source_id = rng.integers(0, 100, n, dtype=np.uint16)
    data.return_number = np.ones(n, dtype=np.uint8)
    data.number_of_returns = np.ones(n, dtype=np.uint8)
    data.red = rng.integers(0, 256, n, dtype=np.uint16) * 257
    data.green = rng.integers(0, 256, n, dtype=np.uint16) * 257
    data.blue = rng.integers(0, 256, n, dtype=np.uint16) * 257
    path = os.path.join(scratch, name)
    data.write(path, laz_backend=laspy.LazBackend.Laszip) if name.endswith(".laz") else data.write(path)
    back = laspy.read(path)
    ours = dump(path)
    check(len(ours) == n, f"{name}: our reader read {len(ours)} of {n} points")
    xyz = np.stack([np.asarray(back.x), np.asarray(back.y), np.asarray(back.z)], axis=1)
    check(near(xyz, ours[:, 0:3], 0.001), f"{name}: positions within 1 mm")
    roles = np.where(classes == 2, 0, np.where(classes == 64, 2, 1))
    check(np.array_equal(ours[:, 4], roles), f"{name}: classes mapped to roles")
    check(np.array_equal(ours[:, 5], np.asarray(back.point_source_id)), f"{name}: point source ID")
    check(np.array_equal(ours[:, 7], np.asarray(back.intensity)), f"{name}: intensity")
    rgb = (np.asarray(back.red).astype(np.int64) >> 8 << 16) | (np.asarray(back.green).astype(np.int64) >> 8 << 8) \
        | (np.asarray(back.blue).astype(np.int64) >> 8)
    check(np.array_equal(ours[:, 3].astype(np.int64), rgb), f"{name}: rgb")

# --- 3. our PLY read by Open3D -----------------------------------------------------------
import open3d as o3d  # noqa: E402 (after laspy: its import is slow)

ply = os.path.join(scratch, "ours.ply")
subprocess.run([tool, "write", ply, *origin], check=True)
ours = dump(ply)
pc = o3d.t.io.read_point_cloud(ply)
keys = set(pc.point)
want = {"positions", "colors", "scalar_label", "scalar_view", "scalar_range", "scalar_intensity",
        "scalar_return_number", "scalar_number_of_returns", "scalar_incidence_deg", "scalar_scan_angle_deg",
        "scalar_height_above_ground_m"}
check(want <= keys, f"Open3D dropped {sorted(want - keys)}")
if want <= keys:
    pos = pc.point["positions"].numpy().astype(np.float64) + np.array([float(v) for v in origin])
    check(near(pos, ours[:, 0:3], 1e-6), "Open3D: positions")
    col = np.rint(pc.point["colors"].numpy().astype(np.float64) * (255.0 if pc.point["colors"].dtype != o3d.core.uint8 else 1.0)).astype(np.int64)
    check(np.array_equal((col[:, 0] << 16) | (col[:, 1] << 8) | col[:, 2], ours[:, 3].astype(np.int64)), "Open3D: colours")
    for key, column in (("scalar_label", 4), ("scalar_view", 5), ("scalar_range", 6), ("scalar_intensity", 7),
                        ("scalar_return_number", 8), ("scalar_number_of_returns", 9), ("scalar_incidence_deg", 10),
                        ("scalar_scan_angle_deg", 11), ("scalar_height_above_ground_m", 12)):
        got = pc.point[key].numpy().reshape(-1)
        check(np.array_equal(got.astype(np.float32), ours[:, column].astype(np.float32)), f"Open3D: {key}")

# --- 4. the generator's PCD and LAZ hold the same points ---------------------------------
small = ["--xres", "32", "--yres", "24", "--views", "6"]
pcd = os.path.join(scratch, "gen.pcd")
laz = os.path.join(scratch, "gen.laz")
for out in (pcd, laz):
    subprocess.run([ladarvr, "generate", *small, "--out", out], check=True, capture_output=True)
raw = open(pcd, "rb").read()
head_end = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
header = raw[:head_end].decode()
count = int(header.split("\nPOINTS ")[1].split()[0])
pcd_origin = np.array([float(v) for v in header.split("# ladarvr origin ")[1].split("\n")[0].split()])
rec = np.frombuffer(raw[head_end:], dtype=np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4"),
                                                     ("label", "u1"), ("view", "<u2"), ("range", "<f4")]), count=count)
las = laspy.read(laz)
check(len(las.points) == count, f"generate: LAZ has {len(las.points)} points, PCD {count}")
if len(las.points) == count:
    world = np.stack([rec["x"], rec["y"], rec["z"]], axis=1).astype(np.float64) + pcd_origin
    xyz = np.stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)], axis=1)
    check(near(xyz, world, 0.0006), "generate: LAZ positions within 1 mm of the PCD's")
    check(np.array_equal(np.asarray(las.point_source_id), rec["view"]), "generate: views")
    check(np.array_equal(np.asarray(las.classification), np.array([2, 1, 64])[rec["label"]]), "generate: classes")
    check(np.array_equal(np.asarray(las["range"], dtype=np.float32), rec["range"]), "generate: ranges")

# --- 5. the metric reads LAZ clouds as it reads PCD ----------------------------------------
import json  # noqa: E402

means = {}
for ext in ("pcd", "laz"):
    for name, roles in (("t", ["--roles", "target"]), ("e", ["--roles", "environment", "--white"]),
                        ("te", ["--roles", "target,environment"])):
        subprocess.run([ladarvr, "generate", *small, *roles, "--out", os.path.join(scratch, f"{name}.{ext}")],
                       check=True, capture_output=True)
    run = subprocess.run([ladarvr, "metric", *(a for k in ("p1", "p2", "p3") for a in (
        f"--{k}", os.path.join(scratch, {"p1": "t", "p2": "e", "p3": "te"}[k] + "." + ext))),
        "--views", "4", "--width", "64", "--height", "64", "--json", "--out", os.path.join(scratch, "m_" + ext)],
        check=True, capture_output=True, text=True)
    summary = json.loads(run.stdout)
    means[ext] = (summary["metric_mean"], summary["visible_mean"], summary["depth_visible_mean"])
check(means["pcd"] == means["laz"] and means["pcd"][0] is not None, f"metric on LAZ {means['laz']} vs PCD {means['pcd']}")

if failures:
    for f in failures:
        print("FAIL:", f, file=sys.stderr)
    sys.exit(1)
print(f"las_interop: all {checks} checks passed")
