#!/usr/bin/env python3
"""tests/corpus/make_vehicles_test.py: scripts/make_vehicles.py's vehicle families.

    make_vehicles_test.py LADARVR MAKE_VEHICLES_PY SCRATCH_DIR SCENE_JSON

Every family's vehicles, read back from their OBJ files: each part a closed solid (every
directed edge once and its reverse once), the box within the family's ranges (and the
issue's 3.5-12 x 1.6-3.6 x 1.3-3.5 m) and equal to the size vehicles.json records; the same
arguments write the same bytes; vehicle k does not change when --per-family grows. Then a
corpus item whose target is one of them: its manifest's target box is the mesh's box
where the item placed it, and its cloud holds target points.
"""

import collections
import json
import os
import shutil
import subprocess
import sys

LIMITS = ((3.5, 12.0), (1.6, 3.6), (1.3, 3.5))


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def read_obj(path):
    """The OBJ's vertices and its parts ("o" groups), each a list of faces (0-based)."""
    verts, parts = [], collections.OrderedDict()
    current = None
    with open(path) as fh:
        for line in fh:
            w = line.split()
            if not w:
                continue
            if w[0] == "o":
                current = parts.setdefault(w[1], [])
            elif w[0] == "v":
                verts.append(tuple(float(c) for c in w[1:4]))
            elif w[0] == "f":
                current.append(tuple(int(c) - 1 for c in w[1:4]))
    return verts, parts


def check_closed(name, faces):
    edges = collections.Counter()
    for a, b, c in faces:
        for e in ((a, b), (b, c), (c, a)):
            edges[e] += 1
    for (a, b), n in edges.items():
        if n != 1 or edges.get((b, a), 0) != 1:
            fail("%s: edge %d-%d is used %d times, its reverse %d times (not a closed solid)"
                 % (name, a, b, n, edges.get((b, a), 0)))


def run_script(script, out, per_family):
    subprocess.run([sys.executable, script, "--out", out, "--per-family", str(per_family), "--seed", "5"],
                   check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "vehicles.json")) as fh:
        return json.load(fh)


def check_vehicles(out, listing):
    families = collections.Counter()
    for v in listing["vehicles"]:
        path = os.path.join(out, v["file"])
        verts, parts = read_obj(path)
        if len(parts) < 3:
            fail("%s: %d parts; a vehicle has a body and wheels or tracks" % (path, len(parts)))
        for part, faces in parts.items():
            check_closed("%s part %s" % (v["file"], part), faces)
        lo = [min(p[k] for p in verts) for k in range(3)]
        hi = [max(p[k] for p in verts) for k in range(3)]
        size = [hi[k] - lo[k] for k in range(3)]
        ranges = listing["families"][v["family"]]
        for k, key in enumerate(("length_m", "width_m", "height_m")):
            r = ranges[key]
            if abs(size[k] - v[key]) > 0.002:
                fail("%s: %s %.3f in the mesh, %.3f in vehicles.json" % (v["file"], key, size[k], v[key]))
            if not (r[0] - 0.002 <= size[k] <= r[1] + 0.002 and LIMITS[k][0] - 0.002 <= size[k] <= LIMITS[k][1] + 0.002):
                fail("%s: %s %.3f outside the family's [%g, %g]" % (v["file"], key, size[k], r[0], r[1]))
        if abs(lo[2]) > 0.001 or abs(lo[0] + hi[0]) > 0.002 or abs(lo[1] + hi[1]) > 0.002:
            fail("%s: not centred on the origin on z = 0 (box %s to %s)" % (v["file"], lo, hi))
        families[v["family"]] += 1
    return families


def main():
    ladarvr, script, scratch, scene = sys.argv[1:5]
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    a, b, c = (os.path.join(scratch, n) for n in ("a", "b", "c"))
    listing = run_script(script, a, 3)
    families = check_vehicles(a, listing)
    expected = {"car", "suv", "pickup", "van", "box_truck", "bus", "wheeled_apc", "tracked_carrier", "tank",
                "towed_gun"}
    if set(families) != expected or set(families.values()) != {3}:
        fail("families built: %s; expected 3 of each of %s" % (dict(families), sorted(expected)))
    # Vehicles differ within a family (their sizes are drawn).
    for f in expected:
        sizes = {(v["length_m"], v["width_m"], v["height_m"]) for v in listing["vehicles"] if v["family"] == f}
        if len(sizes) != 3:
            fail("family %s: %d distinct sizes among 3 vehicles" % (f, len(sizes)))
    # Reproducible, and vehicle k the same whatever --per-family.
    run_script(script, b, 3)
    run_script(script, c, 5)
    for name in sorted(os.listdir(a)):
        with open(os.path.join(a, name), "rb") as fa, open(os.path.join(b, name), "rb") as fb:
            if fa.read() != fb.read():
                fail("%s differs between two runs with the same arguments" % name)
        if name.endswith(".obj"):
            with open(os.path.join(a, name), "rb") as fa, open(os.path.join(c, name), "rb") as fc:
                if fa.read() != fc.read():
                    fail("%s changed when --per-family grew from 3 to 5" % name)

    # A corpus item with a generated vehicle as its target: the label box follows the mesh.
    v = next(x for x in listing["vehicles"] if x["family"] == "bus")
    spec = {"scene": os.path.abspath(scene), "count": 2, "seed": 3,
            "vary": {"target_files": [os.path.join(a, v["file"])], "target_yaw_deg": 0, "views": 4,
                     "resolution": 32}}
    spec_path = os.path.join(scratch, "spec.json")
    with open(spec_path, "w") as fh:
        json.dump(spec, fh)
    corpus = os.path.join(scratch, "corpus")
    subprocess.run([ladarvr, "corpus", spec_path, "--out", corpus], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(corpus, "manifest.jsonl")) as fh:
        items = [json.loads(line) for line in fh if line.strip()]
    if len(items) != 2:
        fail("the corpus holds %d items, expected 2" % len(items))
    for item in items:
        t = item["target"]
        if not t["file"].endswith(v["file"]):
            fail("item %s: target %s, expected %s" % (item["id"], t["file"], v["file"]))
        size = [t["box_max"][k] - t["box_min"][k] for k in range(3)]
        for k, key in enumerate(("length_m", "width_m", "height_m")):
            if abs(size[k] - v[key]) > 0.01:
                fail("item %s: the label box's %s is %.3f, the mesh's %.3f" % (item["id"], key, size[k], v[key]))
        centre = [(t["box_max"][k] + t["box_min"][k]) / 2 for k in range(2)]
        if abs(centre[0] - t["position"][0]) > 0.01 or abs(centre[1] - t["position"][1]) > 0.01:
            fail("item %s: the label box is centred at %s, the target placed at %s" % (item["id"], centre,
                                                                                      t["position"]))
        if item["points_per_label"]["target"] == 0:
            fail("item %s: no target points in the cloud" % item["id"])
    print("make_vehicles_test: %d vehicles of %d families, corpus items labelled" % (len(listing["vehicles"]),
                                                                                   len(families)))


if __name__ == "__main__":
    main()
