#!/usr/bin/env python3
"""Measures how much of a vehicle a ground filter keeps coloured on terrain with relief:
vehicles of scripts/make_vehicles.py's families placed on slopes of the hilly and slopes
scenes, along the slope and across it, generated with each sensor preset.

    python3 scripts/csf_target_kept.py [--ladarvr PATH] [--out DIR] [--families car,tank]
        [--scenes hilly,slopes] [--sensors ideal,riegl-vux1uav,livox-avia]
        [--rest tilted,level] [--ground csf] [--res 128] [--views 100] [--spots 2]

Run it inside the build environment (`./ladarvr shell -c "python3 scripts/..."`), after
building `ladarvr`. For each case it writes DIR/<scene>_<spot>_<orientation>_<rest>_
<vehicle>/scene.json (the base scene with its target replaced by the vehicle, the
environment meshes within 12 m of it left out), runs `generate --ground G --sensor S
--json` on it (the cloud is removed once measured) and prints one line: scene, spot,
slope, orientation, rest, vehicle, sensor, the target's points more than 0.5 m above the
true terrain and the share of them left coloured (`target kept`, docs/ground.md). The
last lines give the lowest share per sensor.

A spot is the first point of a ring 25-45 m out from the scene's centre (every 5 degrees)
where the ground slopes --slope-min to --slope-max (12-25 %), at most 5 % more over a
6 m disc, no environment mesh stands within 12 m and it is at least 25 m from the spots
taken before. "along": the vehicle's long axis up the slope; "across": along the
contour. "tilted": it rests on the slope as the forest scene's tank does, the plane that
best fits the ground under its footprint giving its pitch and roll, its bottom 5 cm into
that plane; "level": no pitch or roll, its centre's bottom 5 cm into the ground (the
uphill end sunk, the downhill end floating), as a vehicle dropped on the terrain.
"""

import argparse
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_scenes  # noqa: E402
import make_vehicles  # noqa: E402

ROOT = os.path.dirname(HERE)
HEIGHT = {"hilly": make_scenes.hilly_height, "slopes": make_scenes.slopes_height}
CLEAR_M = 12.0


def gradient(h, x, y):
    return h(x + 0.5, y) - h(x - 0.5, y), h(x, y + 0.5) - h(x, y - 0.5)


def disc_slope(h, x, y):
    """The steepest slope of the ground over a 6 m disc around (x, y)."""
    return max(math.hypot(*gradient(h, x + 3 * math.cos(a), y + 3 * math.sin(a)))
               for a in [k * math.pi / 4 for k in range(8)] + [0.0])


def find_spots(h, env, count, lo, hi):
    spots = []
    for radius in (30.0, 25.0, 35.0, 40.0, 45.0):
        for k in range(72):
            a = k * math.pi / 36
            x, y = radius * math.cos(a), radius * math.sin(a)
            s = math.hypot(*gradient(h, x, y))
            if not (lo <= s <= hi and disc_slope(h, x, y) <= hi + 0.05):
                continue
            if any(math.hypot(x - ex, y - ey) < CLEAR_M for ex, ey in env):
                continue
            if any(math.hypot(x - sx, y - sy) < 25.0 for sx, sy, _ in spots):
                continue
            spots.append((x, y, s))
            if len(spots) == count:
                return spots
    return spots


def resting(h, x, y, yaw, length, width):
    """Position z, pitch and roll of a vehicle of that footprint resting on the plane that
    best fits the ground under it (least squares in its own axes), 5 cm into it."""
    ca, sa = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    nu, nv = int(length / 0.5), int(width / 0.5)
    samples = [(length * (i / nu - 0.5), width * (j / nv - 0.5)) for i in range(nu + 1) for j in range(nv + 1)]
    zs = [h(x + ca * u - sa * v, y + sa * u + ca * v) for u, v in samples]
    mean = sum(zs) / len(zs)
    along = sum(u * (z - mean) for (u, _), z in zip(samples, zs)) / sum(u * u for u, _ in samples)
    across = sum(v * (z - mean) for (_, v), z in zip(samples, zs)) / sum(v * v for _, v in samples)
    return mean - 0.05, -math.degrees(math.atan(along)), math.degrees(math.atan(across))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ladarvr", default=os.path.join(ROOT, "build/release/app/ladarvr"))
    ap.add_argument("--out", default="/tmp/csf_target_kept")
    ap.add_argument("--families", default="car,towed_gun,wheeled_apc,tank")
    ap.add_argument("--scenes", default="hilly,slopes")
    ap.add_argument("--sensors", default="ideal,riegl-vux1uav,livox-avia")
    ap.add_argument("--ground", default="csf")
    ap.add_argument("--res", type=int, default=128)
    ap.add_argument("--views", type=int, default=100)
    ap.add_argument("--spots", type=int, default=2)
    ap.add_argument("--extra", default="", help="more generate options, space-separated")
    ap.add_argument("--rest", default="tilted,level", help="tilted (on the plane under it), level (its centre on the ground)")
    ap.add_argument("--slope-min", type=float, default=0.12)
    ap.add_argument("--slope-max", type=float, default=0.25)
    a = ap.parse_args()
    vdir = os.path.join(a.out, "vehicles")
    os.makedirs(vdir, exist_ok=True)
    vehicles = []
    for family in [f for f in a.families.split(",") if f]:
        parts, record = make_vehicles.vehicle(1, family, 0)
        path = os.path.join(vdir, record["file"])
        make_vehicles.write_atomic(path, make_vehicles.obj_text(parts, "vehicle for csf_target_kept.py",
                                                                "scripts/make_vehicles.py"))
        vehicles.append((family, path, record["length_m"], record["width_m"]))
    worst = {}
    print("scene spot slope orientation rest vehicle sensor above kept_%")
    for scene in [s for s in a.scenes.split(",") if s]:
        base_path = os.path.join(ROOT, "assets", scene, "scene.json")
        with open(base_path) as fh:
            base = json.load(fh)
        base_dir = os.path.dirname(base_path)
        env = [tuple(m.get("position", [0, 0, 0])[:2]) for m in base["meshes"] if m["role"] != "ground"]
        h = HEIGHT[scene]
        for si, (x, y, s) in enumerate(find_spots(h, env, a.spots, a.slope_min, a.slope_max)):
            gx, gy = gradient(h, x, y)
            up_deg = math.degrees(math.atan2(gy, gx))
            for orient, yaw, rest in [(o, yw, r) for o, yw in (("along", up_deg), ("across", up_deg + 90.0))
                                      for r in a.rest.split(",")]:
                for family, vpath, length, width in vehicles:
                    z, pitch, roll = resting(h, x, y, yaw, length, width)
                    if rest == "level":
                        z, pitch, roll = h(x, y) - 0.05, 0.0, 0.0
                    meshes = []
                    for m in base["meshes"]:
                        if m["role"] == "target":
                            continue
                        px, py = m.get("position", [0, 0, 0])[:2]
                        if m["role"] == "environment" and math.hypot(px - x, py - y) < CLEAR_M:
                            continue
                        m = dict(m)
                        m["file"] = os.path.normpath(os.path.join(base_dir, m["file"]))
                        meshes.append(m)
                    meshes.append({"file": vpath, "role": "target", "position": [round(x, 3), round(y, 3), round(z, 3)],
                                   "yaw_deg": round(yaw, 2), "pitch_deg": round(pitch, 2), "roll_deg": round(roll, 2)})
                    case = "%s_%d_%s_%s_%s" % (scene, si, orient, rest, family)
                    cdir = os.path.join(a.out, case)
                    os.makedirs(cdir, exist_ok=True)
                    scene_file = os.path.join(cdir, "scene.json")
                    with open(scene_file, "w") as fh:
                        json.dump({"comment": "csf_target_kept.py case " + case, "meshes": meshes}, fh, indent=1)
                    cloud = os.path.join(cdir, "cloud.pcd")  # 50-100 MB each: removed once measured
                    for sensor in [s for s in a.sensors.split(",") if s]:
                        cmd = [a.ladarvr, "generate", "--scene", scene_file, "--ground", a.ground, "--sensor", sensor,
                               "--xres", str(a.res), "--yres", str(a.res), "--views", str(a.views), "--json",
                               "--out", cloud] + a.extra.split()
                        run = subprocess.run(cmd, capture_output=True, text=True)
                        if os.path.exists(cloud):
                            os.remove(cloud)
                        if run.returncode != 0:
                            print(case, sensor, "failed:", run.stderr.strip().splitlines()[-1:], flush=True)
                            continue
                        out = json.loads(run.stdout)
                        kept = out["target_kept_coloured"]
                        print("%s %d %.1f%% %s %s %s %s %d %.2f" % (scene, si, 100 * s, orient, rest, family, sensor,
                                                                 out["target_above_terrain"], 100 * kept), flush=True)
                        worst[sensor] = min(worst.get(sensor, 1.0), kept)
    for sensor, kept in worst.items():
        print("lowest %s: %.2f %%" % (sensor, 100 * kept))


if __name__ == "__main__":
    main()
