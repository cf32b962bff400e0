#!/usr/bin/env python3
"""copc_laspy_test.py COPC_TOOL SCRATCH: laspy reads the hand-made COPC file that
`copc_tool make` writes as a plain LAZ (laspy.read: LASzip through the variable chunk
table) and must find the points io::CopcReader finds node by node (`copc_tool dump`):
count, bounds, coordinate sums in whole millimetres and roles; and the info VLR first
among the VLRs, the hierarchy among the EVLRs. (laspy.CopcReader needs the lazrs
backend, which Debian does not package; copcjs_test.sh reads the file node by node.)"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import laspy
import numpy as np

tool, scratch = sys.argv[1], Path(sys.argv[2])
shutil.rmtree(scratch, ignore_errors=True)
scratch.mkdir(parents=True)
path = scratch / "handmade.copc.laz"
subprocess.run([tool, "make", str(path)], check=True)
ours = json.loads(subprocess.run([tool, "dump", str(path)], check=True, capture_output=True, text=True).stdout)


def summary(points):
    mm = [np.rint(np.asarray(points[d], dtype=np.float64) * 1000.0).astype(np.int64) for d in ("x", "y", "z")]
    cls = np.asarray(points.classification)
    return {
        "points": int(len(cls)),
        "min_mm": [int(a.min()) for a in mm],
        "max_mm": [int(a.max()) for a in mm],
        "sum_mm": [str(int(a.sum())) for a in mm],
        "roles": [int((cls == 2).sum()), int(((cls != 2) & (cls != 64)).sum()), int((cls == 64).sum())],
    }


want = {k: ours[k] for k in ("points", "min_mm", "max_mm", "sum_mm", "roles")}
failed = False
whole = laspy.read(path)
if summary(whole.points) != want:
    print(f"laspy.read: {summary(whole.points)} != ours {want}")
    failed = True
vlrs = [(v.user_id, v.record_id) for v in whole.header.vlrs]
evlrs = [(v.user_id, v.record_id) for v in (whole.header.evlrs or [])]
if not vlrs or vlrs[0] != ("copc", 1):
    print(f"laspy: the first VLR is {vlrs[:1]}, not the COPC info VLR")
    failed = True
if ("copc", 1000) not in evlrs:
    print(f"laspy: no COPC hierarchy EVLR among {evlrs}")
    failed = True
sys.exit(1 if failed else print(f"copc_laspy_test: laspy agrees: {want['points']} points") or 0)
