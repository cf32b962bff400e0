#!/usr/bin/env python3
"""Open3D's RaycastingScene on the rays and triangles `ladarvr bench peers` dumped.

    peer_open3d.py DUMP OUT_HITS [--repeats N] [--threads T]

DUMP (little endian): b"LVRAYS01", uint64 vertex count V, triangle count T, ray count R,
then V x 3 float32 vertices, T x 3 uint32 indices, R x 6 float32 rays (ox oy oz dx dy dz).
Builds one RaycastingScene from the triangles (timed as the build), casts every ray once
to warm up, then N timed times; writes the hit distances of the last cast (float32, inf
for a miss) to OUT_HITS and prints one JSON line with the timings (seconds; the median is
what the bench compares).
"""
import argparse
import json
import statistics
import sys
import time

import numpy as np
import open3d as o3d


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dump")
    ap.add_argument("out_hits")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()
    with open(a.dump, "rb") as f:
        if f.read(8) != b"LVRAYS01":
            sys.exit("peer_open3d: %s: not a ladarvr ray dump" % a.dump)
        nv, nt, nr = np.frombuffer(f.read(24), dtype="<u8")
        vertices = np.frombuffer(f.read(int(nv) * 12), dtype="<f4").reshape(-1, 3)
        triangles = np.frombuffer(f.read(int(nt) * 12), dtype="<u4").reshape(-1, 3)
        rays = np.frombuffer(f.read(int(nr) * 24), dtype="<f4").reshape(-1, 6)
    if rays.shape[0] != nr or triangles.shape[0] != nt or vertices.shape[0] != nv:
        sys.exit("peer_open3d: %s: truncated dump" % a.dump)
    scene = o3d.t.geometry.RaycastingScene(nthreads=a.threads)
    scene.add_triangles(o3d.core.Tensor(np.ascontiguousarray(vertices)),
                        o3d.core.Tensor(np.ascontiguousarray(triangles)))
    rays_t = o3d.core.Tensor(np.ascontiguousarray(rays))
    # Open3D builds its BVH lazily on the first query: the warm-up cast includes it.
    t1 = time.perf_counter()
    result = scene.cast_rays(rays_t, nthreads=a.threads)
    warm = time.perf_counter() - t1
    times = []
    for _ in range(a.repeats):
        t1 = time.perf_counter()
        result = scene.cast_rays(rays_t, nthreads=a.threads)
        times.append(time.perf_counter() - t1)
    t_hit = result["t_hit"].numpy().astype("<f4")
    t_hit.tofile(a.out_hits)
    print(json.dumps({"open3d": o3d.__version__, "rays": int(nr), "triangles": int(nt),
                      "warmup_s": warm, "times_s": times, "median_s": statistics.median(times),
                      "hits": int(np.isfinite(t_hit).sum())}))


if __name__ == "__main__":
    main()
