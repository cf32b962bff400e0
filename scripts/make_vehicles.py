#!/usr/bin/env python3
"""Generates a procedural family of vehicle meshes for the detector's corpora (python3
stdlib only, deterministic).

    python3 scripts/make_vehicles.py --out DIR [--per-family N] [--seed S] [--families a,b]

DIR/<family>_<k>.obj   one vehicle each: long axis along x (front at +x), centred on the
                       origin in x and y, its lowest point (wheels, tracks) on z = 0; its
                       box is exactly the drawn length, width and height (metres)
DIR/vehicles.json      {"seed", "families": {name: {length_m, width_m, height_m ranges}},
                        "vehicles": [{"file", "family", "length_m", "width_m", "height_m",
                        "params"}]}, the list a corpus SPEC's vary.target_files takes

Families (FAMILIES below): cars, SUVs, pickups (open beds), vans, box trucks (cab and
cargo box), buses, wheeled APCs (with or without a turret and barrel), tracked carriers,
tanks (tracks, turret, barrel) and towed guns (two wheels, trails, shield, barrel). Each
vehicle draws its length, width and height uniformly within its family's ranges (all
within 3.5-12 m, 1.6-3.6 m and 1.3-3.5 m) and its parts' proportions, axle count, wheel
size and options from a random.Random seeded by (seed, family, k) alone: the same
arguments give byte-identical files, and a vehicle does not change when --per-family
grows. Every part is a closed solid (each edge shared by exactly two of its triangles,
counter-clockwise seen from outside), so the vehicle is a closed mesh of a few parts.

These meshes train and evaluate the trained detector (bench detect's leave-one-family-out
run); Debian's flightgear-data-models stay out of training, kept for evaluation.
"""

import argparse
import json
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_scenes import Mesh, box, num, obj_text, prism, sweep_y  # noqa: E402

# Each family's length, width and height ranges (metres, min and max).
FAMILIES = {
    "car": ((3.5, 5.0), (1.6, 1.9), (1.3, 1.6)),
    "suv": ((4.2, 5.2), (1.75, 2.05), (1.6, 2.0)),
    "pickup": ((4.8, 6.2), (1.8, 2.1), (1.7, 2.0)),
    "van": ((4.5, 6.8), (1.8, 2.2), (1.9, 2.8)),
    "box_truck": ((6.0, 10.0), (2.2, 2.6), (2.8, 3.5)),
    "bus": ((9.0, 12.0), (2.4, 2.6), (2.8, 3.4)),
    "wheeled_apc": ((5.5, 8.5), (2.4, 3.0), (2.0, 2.9)),
    "tracked_carrier": ((5.0, 7.5), (2.6, 3.4), (1.8, 2.6)),
    "tank": ((7.0, 11.0), (3.0, 3.6), (2.2, 3.0)),
    "towed_gun": ((5.0, 9.0), (1.8, 2.8), (1.3, 2.2)),
}
LIMITS = ((3.5, 12.0), (1.6, 3.6), (1.3, 3.5))


def solid(m):
    """The part with its triangles wound counter-clockwise seen from outside (positive
    signed volume), whatever the builder's winding."""
    vol = 0.0
    for a, b, c in m.f:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = m.v[a], m.v[b], m.v[c]
        vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    if vol < 0:
        m.f = [(a, c, b) for a, b, c in m.f]
    return m


def circle(cx, cz, r, n=12):
    """A regular n-gon about (cx, cz) in the (x, z) plane, counter-clockwise seen from -y."""
    return [(cx + r * math.cos(2 * math.pi * i / n), cz + r * math.sin(2 * math.pi * i / n)) for i in range(n)]


def wheels(xs, half_w, r, tread):
    """A wheel on each side at each x: cylinders across y, their outer faces at +-half_w."""
    parts = []
    for i, x in enumerate(xs):
        for side, (y0, y1) in (("left", (half_w - tread, half_w)), ("right", (-half_w, -half_w + tread))):
            parts.append(("wheel_%d_%s" % (i, side), sweep_y(circle(x, r, r), y0, y1)))
    return parts


def tracks(length, half_w, tread, height):
    """A track on each side: a hexagonal run with sloped ends, on z = 0."""
    h = length / 2
    prof = [(-h, 0.5 * height), (-h + 0.35 * height, 0.0), (h - 0.35 * height, 0.0), (h, 0.5 * height),
            (h - 0.2 * height, height), (-h + 0.2 * height, height)]
    return [("track_left", sweep_y(prof, half_w - tread, half_w)),
            ("track_right", sweep_y(prof, -half_w, -half_w + tread))]


def barrel(x0, x1, y, z, r):
    """A closed cylinder along x (a gun's barrel)."""
    return prism(0.0, 0.0, r, 8, x0, x1).transformed(lambda px, py, pz: (pz, y + py, z - px))


def axle_xs(rng, length, count, r):
    """`count` axle positions along a wheelbase that leaves the overhangs inside the body."""
    front = length / 2 - r - rng.uniform(0.25, 0.6)
    rear = -length / 2 + r + rng.uniform(0.3, 0.9)
    if count == 1:
        return [0.0]
    if count == 2:
        return [rear, front]
    # tandem rear axles, the rest spread to the front
    return [rear + k * (front - rear) / (count - 1) for k in range(count)]


def car_like(rng, L, W, H, kind):
    r = rng.uniform(0.29, 0.36) * (1.15 if kind == "suv" else 1.0)
    hw = W / 2
    body_top = H * rng.uniform(0.5, 0.6)
    parts = [("body", box(-L / 2, L / 2, -hw, hw, 0.6 * r, body_top))]
    # the cabin: a trapezoid from the bonnet's end to the rear (a car's boot stays lower)
    x_front = L / 2 - L * rng.uniform(0.25, 0.32)
    x_rear = -L / 2 + (L * rng.uniform(0.12, 0.2) if kind == "car" else 0.15)
    slope_f = L * rng.uniform(0.08, 0.14)
    slope_r = L * (rng.uniform(0.04, 0.1) if kind == "car" else 0.02)
    prof = [(x_rear, body_top), (x_front, body_top), (x_front - slope_f, H), (x_rear + slope_r, H)]
    parts.append(("cabin", sweep_y(prof, -hw * 0.92, hw * 0.92)))
    parts += wheels(axle_xs(rng, L, 2, r), hw * 0.98, r, 0.22)
    return parts, {"wheel_radius_m": round(r, 3), "axles": 2}


def pickup(rng, L, W, H):
    r = rng.uniform(0.36, 0.42)
    hw = W / 2
    floor = 2.0 * r * rng.uniform(0.9, 1.05)
    bed_len = L * rng.uniform(0.32, 0.42)
    wall_h = rng.uniform(0.45, 0.55)
    x_bed = -L / 2 + bed_len
    parts = [("chassis", box(-L / 2, L / 2, -hw * 0.9, hw * 0.9, 0.6 * r, floor)),
             ("bonnet", box(x_bed + 0.1, L / 2, -hw, hw, floor, floor + 0.35 * (H - floor))),
             ("cab", box(x_bed + 0.1, L / 2 - L * 0.22, -hw * 0.95, hw * 0.95, floor, H)),
             # the open bed: a floor and three walls, nothing on top
             ("bed_floor", box(-L / 2, x_bed, -hw, hw, floor, floor + 0.08)),
             ("bed_left", box(-L / 2, x_bed, hw - 0.08, hw, floor + 0.08, floor + wall_h)),
             ("bed_right", box(-L / 2, x_bed, -hw, -hw + 0.08, floor + 0.08, floor + wall_h)),
             ("tailgate", box(-L / 2, -L / 2 + 0.08, -hw + 0.08, hw - 0.08, floor + 0.08, floor + wall_h))]
    parts += wheels(axle_xs(rng, L, 2, r), hw * 0.97, r, 0.25)
    return parts, {"wheel_radius_m": round(r, 3), "axles": 2, "bed_length_m": round(bed_len, 3)}


def van(rng, L, W, H):
    r = rng.uniform(0.33, 0.4)
    hw = W / 2
    nose = L * rng.uniform(0.12, 0.2)
    bonnet_top = H * rng.uniform(0.42, 0.52)
    x_body = L / 2 - nose
    parts = [("body", box(-L / 2, x_body, -hw, hw, 0.6 * r, H)),
             ("bonnet", box(x_body, L / 2, -hw * 0.95, hw * 0.95, 0.6 * r, bonnet_top)),
             ("windscreen", sweep_y([(x_body, bonnet_top), (L / 2, bonnet_top), (x_body, H)], -hw * 0.95, hw * 0.95))]
    parts += wheels(axle_xs(rng, L, 2, r), hw * 0.97, r, 0.24)
    return parts, {"wheel_radius_m": round(r, 3), "axles": 2}


def box_truck(rng, L, W, H):
    r = rng.uniform(0.45, 0.55)
    hw = W / 2
    axles = 3 if L > 8.0 and rng.random() < 0.6 else 2
    cab_len = rng.uniform(1.8, 2.4)
    cab_h = H * rng.uniform(0.78, 0.9)
    frame_top = 2 * r + 0.1
    x_cab = L / 2 - cab_len
    parts = [("chassis", box(-L / 2, L / 2, -hw * 0.85, hw * 0.85, r, frame_top)),
             ("cargo", box(-L / 2, x_cab - 0.15, -hw, hw, frame_top, H)),
             ("cab", box(x_cab, L / 2, -hw * 0.96, hw * 0.96, frame_top, cab_h))]
    xs = axle_xs(rng, L, 2, r)
    if axles == 3:
        xs = [xs[0] - 2.2 * r, xs[0], xs[1]]
    parts += wheels(xs, hw * 0.95, r, 0.3)
    return parts, {"wheel_radius_m": round(r, 3), "axles": axles, "cab_length_m": round(cab_len, 3)}


def bus(rng, L, W, H):
    r = rng.uniform(0.48, 0.55)
    hw = W / 2
    axles = 3 if L > 11.0 and rng.random() < 0.5 else 2
    # the body with a sloped windscreen at +x and a rounded-off roof edge at the rear
    prof = [(-L / 2, 0.6 * r), (L / 2, 0.6 * r), (L / 2, 0.55 * H), (L / 2 - 0.25, H), (-L / 2 + 0.15, H),
            (-L / 2, H - 0.15)]
    parts = [("body", sweep_y(prof, -hw, hw))]
    xs = axle_xs(rng, L, 2, r)
    xs[1] = L / 2 - r - rng.uniform(1.8, 2.6)  # a bus's front overhang is long
    xs[0] = -L / 2 + r + rng.uniform(2.2, 3.2)
    if axles == 3:
        xs = [xs[0] - 2.3 * r, xs[0], xs[1]]
    parts += wheels(xs, hw * 0.97, r, 0.3)
    return parts, {"wheel_radius_m": round(r, 3), "axles": axles}


def wheeled_apc(rng, L, W, H):
    axles = rng.choice([3, 4]) if L > 6.5 else rng.choice([2, 3])
    r = rng.uniform(0.5, 0.6)
    hw = W / 2
    turret = rng.random() < 0.6
    hull_top = H * (rng.uniform(0.7, 0.8) if turret else rng.uniform(0.85, 0.92))
    belly = 0.9 * r
    prof = [(-L / 2, belly), (L / 2 - 0.7, belly), (L / 2, belly + 0.5 * (hull_top - belly)), (L / 2 - 0.9, hull_top),
            (-L / 2 + 0.2, hull_top), (-L / 2, hull_top - 0.4)]
    parts = [("hull", sweep_y(prof, -hw * 0.9, hw * 0.9))]
    front = L / 2 - r - 0.6
    rear = -L / 2 + r + 0.5
    parts += wheels([rear + k * (front - rear) / (axles - 1) for k in range(axles)], hw, r, 0.35)
    params = {"wheel_radius_m": round(r, 3), "axles": axles, "turret": turret}
    x_t = rng.uniform(-0.3, 0.8)
    if turret:
        tr = min(hw * 0.55, rng.uniform(0.8, 1.1))
        parts.append(("turret", prism(x_t, 0.0, tr, 8, hull_top, H, r_top=tr * 0.85, phase=math.pi / 8)))
        length = rng.uniform(1.5, 3.0)
        parts.append(("barrel", barrel(x_t + tr * 0.7, min(x_t + tr + length, L / 2 - 0.05), 0.0,
                                       hull_top + 0.5 * (H - hull_top), 0.06)))
        params["barrel_length_m"] = round(length, 3)
    else:
        parts.append(("cupola", prism(x_t, 0.0, 0.5, 8, hull_top, H, r_top=0.45, phase=math.pi / 8)))
    return parts, params


def tracked(rng, L, W, H, turret):
    hw = W / 2
    tread = rng.uniform(0.45, 0.65)
    hull_len = L * (rng.uniform(0.62, 0.72) if turret else 1.0)
    track_h = rng.uniform(0.8, 1.1)
    hull_top = H * (rng.uniform(0.55, 0.65) if turret else rng.uniform(0.8, 0.9))
    x_back = -L / 2
    x_front = x_back + hull_len
    parts = tracks(hull_len, hw, tread, track_h)
    parts = [(name, m.transformed(lambda x, y, z, c=(x_back + x_front) / 2: (x + c, y, z))) for name, m in parts]
    prof = [(x_back + 0.1, 0.45 * track_h), (x_front - 0.5, 0.45 * track_h), (x_front, 0.5 * (track_h + hull_top)),
            (x_front - 0.6, hull_top), (x_back + 0.1, hull_top)]
    parts.append(("hull", sweep_y(prof, -(hw - tread * 0.4), hw - tread * 0.4)))
    params = {"track_width_m": round(tread, 3), "turret": turret}
    if turret:
        tr = min(hw * 0.8, rng.uniform(1.2, 1.6))
        x_t = x_back + hull_len * rng.uniform(0.4, 0.5)
        parts.append(("turret", prism(x_t, 0.0, tr, 8, hull_top, H, r_top=tr * 0.85, phase=math.pi / 8)))
        z_b = hull_top + 0.5 * (H - hull_top)
        parts.append(("barrel", barrel(x_t + tr * 0.6, L / 2, 0.0, z_b, rng.uniform(0.08, 0.12))))
        params["barrel_length_m"] = round(L / 2 - x_t - tr * 0.6, 3)
    else:
        parts.append(("hatch", box(x_back + 0.5, x_back + 1.3, -0.5, 0.5, hull_top, H)))
    return parts, params


def towed_gun(rng, L, W, H):
    hw = W / 2
    r = rng.uniform(0.4, 0.55)
    x_axle = rng.uniform(-0.3, 0.4)
    carriage_top = 2 * r + 0.1
    trail_len = L * rng.uniform(0.4, 0.5)
    parts = wheels([x_axle], hw, r, 0.25)
    parts.append(("carriage", box(x_axle - 0.6, x_axle + 0.8, -hw + 0.3, hw - 0.3, r * 0.8, carriage_top)))
    # the split trails: two beams from the axle down to spades on the ground behind it
    for side in (-1, 1):
        y0 = side * 0.15
        y1 = side * min(hw - 0.3, 0.15 + trail_len * 0.25)
        prof = [(x_axle - trail_len, 0.0), (x_axle - trail_len + 0.4, 0.0), (x_axle, r * 0.8),
                (x_axle, r * 0.8 + 0.25), (x_axle - trail_len, 0.3)]
        parts.append(("trail_" + ("left" if side > 0 else "right"), sweep_y(prof, min(y0, y1), max(y0, y1))))
    parts.append(("shield", box(x_axle + 0.8, x_axle + 0.9, -hw + 0.2, hw - 0.2, r, H)))
    # the barrel, raised over the carriage, reaching the front of the box
    z_b = carriage_top + 0.5 * (H - carriage_top)
    parts.append(("cradle", box(x_axle - 0.8, x_axle + 1.2, -0.25, 0.25, carriage_top, z_b + 0.2)))
    parts.append(("barrel", barrel(x_axle - 0.5, L / 2, 0.0, z_b, rng.uniform(0.07, 0.1))))
    # the front of the box at L/2, the spades' ends at -L/2: shift the gun so both hold
    return parts, {"wheel_radius_m": round(r, 3), "trail_length_m": round(trail_len, 3)}


BUILDERS = {
    "car": lambda rng, L, W, H: car_like(rng, L, W, H, "car"),
    "suv": lambda rng, L, W, H: car_like(rng, L, W, H, "suv"),
    "pickup": pickup,
    "van": van,
    "box_truck": box_truck,
    "bus": bus,
    "wheeled_apc": wheeled_apc,
    "tracked_carrier": lambda rng, L, W, H: tracked(rng, L, W, H, False),
    "tank": lambda rng, L, W, H: tracked(rng, L, W, H, True),
    "towed_gun": towed_gun,
}


def fitted(parts, L, W, H):
    """The parts moved and stretched so that their box is exactly [-L/2, L/2] x [-W/2, W/2]
    x [0, H] (each axis scaled alone: the builders' proportions, the drawn size)."""
    vs = [p for _, m in parts for p in m.v]
    lo = [min(p[k] for p in vs) for k in range(3)]
    hi = [max(p[k] for p in vs) for k in range(3)]
    size = (L, W, H)
    s = [size[k] / (hi[k] - lo[k]) for k in range(3)]

    def fn(x, y, z):
        return ((x - lo[0]) * s[0] - L / 2, (y - lo[1]) * s[1] - W / 2, (z - lo[2]) * s[2])
    return [(name, solid(m.transformed(fn))) for name, m in parts]


def vehicle(seed, family, k):
    """Vehicle k of a family: its parts (name, Mesh) and its record for vehicles.json."""
    rng = random.Random("%d:%s:%d" % (seed, family, k))
    (l0, l1), (w0, w1), (h0, h1) = FAMILIES[family]
    L, W, H = round(rng.uniform(l0, l1), 3), round(rng.uniform(w0, w1), 3), round(rng.uniform(h0, h1), 3)
    parts, params = BUILDERS[family](rng, L, W, H)
    record = {"file": "%s_%02d.obj" % (family, k), "family": family, "length_m": L, "width_m": W, "height_m": H,
              "params": params}
    return fitted(parts, L, W, H), record


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="\n") as fh:
        fh.write(text)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="folder for the meshes and vehicles.json")
    ap.add_argument("--per-family", type=int, default=8, help="vehicles per family, [1, 1000]")
    ap.add_argument("--seed", type=int, default=1, help="the draws' seed, >= 0")
    ap.add_argument("--families", default="", help="comma-separated families (default all): " + ", ".join(FAMILIES))
    a = ap.parse_args()
    if not 1 <= a.per_family <= 1000:
        ap.error("--per-family %d: allowed [1, 1000]" % a.per_family)
    if a.seed < 0:
        ap.error("--seed %d: allowed >= 0" % a.seed)
    families = [f for f in a.families.split(",") if f] or list(FAMILIES)
    for f in families:
        if f not in FAMILIES:
            ap.error("--families: '%s' is not one of %s" % (f, ", ".join(FAMILIES)))
    os.makedirs(a.out, exist_ok=True)
    records = []
    for family in families:
        for k in range(a.per_family):
            parts, record = vehicle(a.seed, family, k)
            comment = "%s %d (seed %d): %s x %s x %s m" % (family, k, a.seed, num(record["length_m"]),
                                                             num(record["width_m"]), num(record["height_m"]))
            write_atomic(os.path.join(a.out, record["file"]), obj_text(parts, comment, "scripts/make_vehicles.py"))
            records.append(record)
    ranges = {f: {"length_m": list(FAMILIES[f][0]), "width_m": list(FAMILIES[f][1]), "height_m": list(FAMILIES[f][2])}
              for f in families}
    write_atomic(os.path.join(a.out, "vehicles.json"),
                 json.dumps({"seed": a.seed, "families": ranges, "vehicles": records}, indent=1) + "\n")
    print("make_vehicles: %d vehicles of %d families in %s" % (len(records), len(families), a.out))


if __name__ == "__main__":
    main()
