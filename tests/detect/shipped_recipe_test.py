#!/usr/bin/env python3
"""tests/detect/shipped_recipe_test.py: the shipped model's recipe, scripts/train_shipped_model.sh,
and its SPECs, assets/detect/shipped_*.json, agree without running it.

    shipped_recipe_test.py LADARVR REPO SCRATCH_DIR

Every SPEC's scene and target files are ones the recipe makes (the vehicles of its
make_vehicles.py call, the real places of its scene from-cloud calls), bundled assets or
Debian's assimp-testmodels vehicles (every SPEC draws both; never flightgear-data-models);
its vehicles are not seed 1's (bench detect --families evaluates those) and its surveys
are none of the real places kept for evaluation; each SPEC names a sensor, an orbit
range and densities as the docs say; the bundled scenes' SPECs build an item with
`ladarvr corpus` (shrunk to a tiny orbit); and the script refuses a bad argument in one
line with exit 2.
"""

import glob
import json
import os
import re
import shutil
import subprocess
import sys

EVALUATION_ONLY = ("CSite2", "CSite3", "FSite5")
DEBIAN_VEHICLES = ("/usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf",
                   "/usr/share/assimp/models/MS3D/jeep1.ms3d")


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def main():
    ladarvr, repo, scratch = sys.argv[1:4]
    script_path = os.path.join(repo, "scripts", "train_shipped_model.sh")
    script = open(script_path).read()
    detect = os.path.join(repo, "assets", "detect")
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)

    # The recipe's vehicles: its own make_vehicles.py arguments, run here.
    m = re.search(r"make_vehicles\.py\" --out \"\$generated/vehicles\" --per-family (\d+) --seed (\d+)", script)
    if not m:
        fail("the script's make_vehicles.py call was not found")
    per_family, seed = m.group(1), m.group(2)
    if seed == "1":
        fail("the recipe trains on make_vehicles.py's seed 1, the vehicles bench detect --families evaluates")
    mirror = os.path.join(scratch, "detect")
    subprocess.run([sys.executable, os.path.join(repo, "scripts", "make_vehicles.py"), "--out",
                    os.path.join(mirror, "generated", "vehicles"), "--per-family", per_family, "--seed", seed],
                   check=True, stdout=subprocess.DEVNULL)
    made = set(os.listdir(os.path.join(mirror, "generated", "vehicles")))

    # The recipe's real places: the folders its scene from-cloud calls write.
    places = dict(re.findall(r"scene from-cloud \"\$real/([^\"]+)\" --out \"\$generated/real/([a-z0-9_]+)\"", script))
    if len(places) < 4:
        fail("expected four real places in the script, found %s" % places)
    for survey in places:
        if any(survey.startswith(e) for e in EVALUATION_ONLY):
            fail("the recipe trains on %s, a real place kept for evaluation" % survey)
        if not os.path.isfile(os.path.join(repo, "tests", "data", "real", survey)):
            fail("the script's survey %s is not in tests/data/real" % survey)
    real_scenes = {"generated/real/%s/scene.json" % name for name in places.values()}

    specs = sorted(glob.glob(os.path.join(detect, "shipped_*.json")))
    if len(specs) != 18:
        fail("expected 18 SPECs assets/detect/shipped_*.json, found %d" % len(specs))
    used_places = set()
    for path in specs:
        name = os.path.basename(path)
        spec = json.load(open(path))
        scene = spec["scene"]
        if scene.startswith("generated/"):
            if scene not in real_scenes:
                fail("%s: scene %s is not one the script makes" % (name, scene))
            used_places.add(scene)
            if spec.get("placement") != "triangles":
                fail("%s: a real place needs \"placement\": \"triangles\"" % name)
        elif not os.path.isfile(os.path.join(detect, scene)):
            fail("%s: scene %s does not exist" % (name, scene))
        files = [f["file"] if isinstance(f, dict) else f for f in spec["vary"]["target_files"]]
        for f in files:
            if f.startswith("generated/vehicles/"):
                if f[len("generated/vehicles/"):] not in made:
                    fail("%s: target %s is not a vehicle the script makes" % (name, f))
            elif f in DEBIAN_VEHICLES:
                if not os.path.isfile(f):
                    fail("%s: %s missing: the root lacks assimp-testmodels (third_party/packages-build.txt)" % (name, f))
            elif not os.path.isfile(os.path.join(detect, f)) or "truck" in f:
                fail("%s: target %s: allowed the script's vehicles, the tank, APC and van, and Debian's vehicles" % (name, f))
        if any(v not in files for v in DEBIAN_VEHICLES):
            fail("%s: Debian's vehicles %s are not all drawn" % (name, DEBIAN_VEHICLES))
        vary = spec["vary"]
        presets = vary.get("sensor_preset")
        top_m = vary["altitude_m"]["max"]
        if name.endswith("_sensors.json"):
            if presets != ["riegl-vux1uav", "livox-avia"] or top_m > 300:
                fail("%s: presets %s up to %s m; allowed both presets within 300 m" % (name, presets, top_m))
        elif presets is not None or top_m != 400:
            fail("%s: the ideal sensor up to 400 m expected, got %s up to %s m" % (name, presets, top_m))
        if vary["altitude_m"]["min"] != 100 or vary["resolution"] != [64, 128]:
            fail("%s: densities: altitude from 100 m and 64 or 128 rays expected" % name)
    if used_places != real_scenes:
        fail("real places made but not trained on: %s" % sorted(real_scenes - used_places))

    # The bundled scenes' SPECs as `ladarvr corpus` reads them: one tiny item each.
    for d in ("demo", "common"):
        os.symlink(os.path.join(repo, "assets", d), os.path.join(scratch, d))
    for base in ("shipped_demo", "shipped_demo_sensors"):
        spec = json.load(open(os.path.join(detect, base + ".json")))
        spec["count"] = 1
        spec["vary"]["views"] = 2
        spec["vary"]["resolution"] = 16
        tiny = os.path.join(mirror, base + ".json")
        json.dump(spec, open(tiny, "w"))
        r = subprocess.run([ladarvr, "corpus", tiny, "--out", os.path.join(scratch, base), "--threads", "1"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            fail("corpus %s: %s" % (base, r.stderr.strip()[-400:]))
        if len(open(os.path.join(scratch, base, "manifest.jsonl")).read().splitlines()) != 1:
            fail("corpus %s: not one item" % base)

    # Bad arguments: one line, exit 2, before any work.
    for args, want in ((["--bogus"], "unknown argument '--bogus'"), (["--jobs", "0"], "--jobs '0': allowed")):
        r = subprocess.run(["bash", script_path] + args, capture_output=True, text=True,
                           env={**os.environ, "LADARVR": "/nonexistent"})
        if r.returncode != 2 or want not in r.stderr or len(r.stderr.strip().splitlines()) != 1:
            fail("script %s: exit %d, stderr %r" % (args, r.returncode, r.stderr))
    print("OK")


if __name__ == "__main__":
    main()
