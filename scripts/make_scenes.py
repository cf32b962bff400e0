#!/usr/bin/env python3
"""Generates the bundled scenes under assets/ (python3 stdlib only, deterministic).

    python3 scripts/make_scenes.py [--out ASSETS_DIR]

assets/common/  meshes shared by the scenes (buildings, trees, the tank, the grounds), a
                box truck, a second target model the detector benchmark evaluates on,
                and an APC and a van, the trained detector's other training targets
assets/demo/    the demo: a tank beside a house, half under a tree, in a village
assets/hard/    the tank in a narrow street between long buildings, in a dense forest
assets/hilly/   a village and the tank on ground with ~15 m of relief (for terrain-following ground filters)
assets/slopes/  the tank on a small level pad in steep terrain: ~27 m of relief inside the
                covered disc, slopes up to 30 %, houses and trees on the slopes
assets/forest/  the slopes' ground under a forest canopy, the tank on a slope half hidden
                under trees (ground returns only through gaps, as later returns)

World frame: metres, z up. The tank's centre sits at the world origin in every scene
so the default orbit centre is sensible. Several mesh formats are used on purpose
(OBJ, binary and ASCII PLY, binary glTF with y up, AC3D) so the scene loader is
exercised on each. Running the script twice gives byte-identical files.
"""

import argparse
import json
import math
import os
import random
import struct


# ----------------------------------------------------------------------------------
# Geometry: a Mesh is vertices (x, y, z) and triangles (i, j, k), counter-clockwise
# seen from outside. All meshes are authored z up in metres.
# ----------------------------------------------------------------------------------

class Mesh:
    def __init__(self):
        self.v = []
        self.f = []

    def vert(self, x, y, z):
        self.v.append((float(x), float(y), float(z)))
        return len(self.v) - 1

    def tri(self, a, b, c):
        self.f.append((a, b, c))

    def quad(self, a, b, c, d):
        self.tri(a, b, c)
        self.tri(a, c, d)

    def add(self, other):
        base = len(self.v)
        self.v.extend(other.v)
        self.f.extend((a + base, b + base, c + base) for a, b, c in other.f)
        return self

    def transformed(self, fn):
        m = Mesh()
        m.v = [fn(*p) for p in self.v]
        m.f = list(self.f)
        return m


def box(x0, x1, y0, y1, z0, z1):
    m = Mesh()
    p = [m.vert(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    # p index: x + 2y + 4z
    m.quad(p[0], p[2], p[3], p[1])  # bottom
    m.quad(p[4], p[5], p[7], p[6])  # top
    m.quad(p[0], p[1], p[5], p[4])  # y0
    m.quad(p[2], p[6], p[7], p[3])  # y1
    m.quad(p[0], p[4], p[6], p[2])  # x0
    m.quad(p[1], p[3], p[7], p[5])  # x1
    return m


def prism(cx, cy, r, n, z0, z1, r_top=None, phase=0.0):
    """A closed n-gon prism (or frustum / cone when r_top is 0) about a vertical axis."""
    r_top = r if r_top is None else r_top
    m = Mesh()
    bottom = [m.vert(cx + r * math.cos(phase + 2 * math.pi * i / n),
                     cy + r * math.sin(phase + 2 * math.pi * i / n), z0) for i in range(n)]
    if r_top > 0:
        top = [m.vert(cx + r_top * math.cos(phase + 2 * math.pi * i / n),
                      cy + r_top * math.sin(phase + 2 * math.pi * i / n), z1) for i in range(n)]
        for i in range(n):
            j = (i + 1) % n
            m.quad(bottom[i], bottom[j], top[j], top[i])
        for i in range(1, n - 1):
            m.tri(top[0], top[i], top[i + 1])
    else:
        apex = m.vert(cx, cy, z1)
        for i in range(n):
            m.tri(bottom[i], bottom[(i + 1) % n], apex)
    for i in range(1, n - 1):
        m.tri(bottom[0], bottom[i + 1], bottom[i])
    return m


def sweep_y(prof, y0, y1, flipped=False):
    """A closed solid: the convex (x, z) polygon `prof` (counter-clockwise seen from -y)
    swept from y = y0 to y1. Its faces wind counter-clockwise seen from outside, or the
    other way with `flipped` (the tank's tracks were made so; ray casting does not see the
    winding, and the meshes stay as they are)."""
    m = Mesh()
    lo = [m.vert(x, y0, z) for x, z in prof]
    hi = [m.vert(x, y1, z) for x, z in prof]
    n = len(prof)
    for i in range(n):
        j = (i + 1) % n
        if flipped:
            m.quad(lo[i], lo[j], hi[j], hi[i])
        else:
            m.quad(lo[i], hi[i], hi[j], lo[j])
    for i in range(1, n - 1):
        if flipped:
            m.tri(lo[0], lo[i + 1], lo[i])
            m.tri(hi[0], hi[i], hi[i + 1])
        else:
            m.tri(lo[0], lo[i], lo[i + 1])
            m.tri(hi[0], hi[i + 1], hi[i])
    return m


def extrude_y(prof, half_width):
    """`prof` swept from y = -half_width to +half_width (a vehicle's hull)."""
    return sweep_y(prof, -half_width, half_width)


def cylinder_x(x0, x1, cy, cz, r, n):
    """A closed cylinder along x (the tank's barrel)."""
    return prism(0.0, 0.0, r, n, x0, x1).transformed(lambda x, y, z: (z, cy + y, cz - x))


def icosphere(cx, cy, cz, rx, ry, rz, subdiv=1):
    t = (1 + math.sqrt(5)) / 2
    pts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
           (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    pts = [tuple(c / math.sqrt(sum(k * k for k in p)) for c in p) for p in pts]
    for _ in range(subdiv):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                p = [(pts[a][i] + pts[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(c * c for c in p))
                pts.append(tuple(c / n for c in p))
                cache[key] = len(pts) - 1
            return cache[key]

        new = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    m = Mesh()
    m.v = [(cx + rx * x, cy + ry * y, cz + rz * z) for x, y, z in pts]
    m.f = faces
    return m


def house(width, depth, eave_h, ridge_h, base=-4.0, overhang=0.4):
    """Walls (a box from `base`, below the ground, to the eaves) and a gable roof whose
    ridge runs along x. Footprint centred on the origin."""
    m = box(-width / 2, width / 2, -depth / 2, depth / 2, base, eave_h)
    r = Mesh()
    x0, x1 = -width / 2 - overhang, width / 2 + overhang
    y0, y1 = -depth / 2 - overhang, depth / 2 + overhang
    a0, a1 = r.vert(x0, y0, eave_h), r.vert(x1, y0, eave_h)
    b0, b1 = r.vert(x0, y1, eave_h), r.vert(x1, y1, eave_h)
    c0, c1 = r.vert(x0, 0.0, ridge_h), r.vert(x1, 0.0, ridge_h)
    r.quad(a0, a1, c1, c0)      # south slope
    r.quad(b1, b0, c0, c1)      # north slope
    r.tri(a0, c0, b0)           # west gable
    r.tri(a1, b1, c1)           # east gable
    r.quad(a0, b0, b1, a1)      # underside
    return m.add(r)


def flat_building(width, depth, height, base=-4.0):
    m = box(-width / 2, width / 2, -depth / 2, depth / 2, base, height)
    # a parapet-free roof box for some detail
    return m.add(box(-1.5, 1.5, -1.5, 1.5, height, height + 2.0))


def broadleaf_tree(rng):
    """Trunk to 4.5 m and a porous canopy of leaf clumps (rays pass through the gaps,
    as they do through real foliage). About 6 m wide, 9.5 m tall."""
    m = prism(0, 0, 0.25, 6, -1.5, 5.5, r_top=0.18)
    for _ in range(22):
        while True:
            x, y, z = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
            if x * x + y * y + z * z <= 1:
                break
        r = rng.uniform(0.7, 1.1)
        m.add(icosphere(2.2 * x, 2.2 * y, 6.8 + 1.6 * z, r, r, r * 0.8, subdiv=1))
    return m


def conifer_tree():
    """Trunk and three stacked cones; about 4.4 m wide and 11 m tall."""
    m = prism(0, 0, 0.22, 6, -1.5, 3.0)
    for z0, r, h in ((2.0, 2.2, 4.5), (4.5, 1.7, 4.0), (7.0, 1.1, 4.0)):
        m.add(prism(0, 0, r, 10, z0, z0 + h, r_top=0.0))
    return m


def tank():
    """A tank-like target, its long axis along x, centred on the origin, on z = 0:
    7.0 m x 3.5 m x 2.5 m without the barrel, which reaches 3.6 m beyond the bow."""
    parts = []
    # tracks with sloped ends
    for side in (-1, 1):
        y0, y1 = (1.05, 1.75) if side > 0 else (-1.75, -1.05)
        pts = [(-3.5, 0.5), (-3.2, 0.0), (3.2, 0.0), (3.5, 0.5), (3.3, 1.0), (-3.3, 1.0)]
        t = sweep_y(pts, y0, y1, flipped=True)
        parts.append(("track_" + ("left" if side > 0 else "right"), t))
    # hull with a sloped glacis at +x
    prof = [(-3.4, 0.45), (3.0, 0.45), (3.45, 1.0), (3.0, 1.55), (-3.4, 1.55)]
    parts.append(("hull", extrude_y(prof, 1.25)))
    parts.append(("turret", prism(-0.4, 0.0, 1.55, 8, 1.55, 2.5, r_top=1.3, phase=math.pi / 8)))
    parts.append(("barrel", cylinder_x(0.9, 7.1, 0.0, 2.05, 0.11, 8)))
    return parts


def truck():
    """A box truck of boxes, its long axis along x (cab at +x), centred on the origin,
    wheels on z = 0: 8.0 m x 2.5 m x 3.4 m. A second target model: the trained detector's
    benchmark evaluates on it while training only on the tank."""
    parts = [("chassis", box(-4.0, 4.0, -1.1, 1.1, 0.55, 1.0)),
             ("cargo", box(-4.0, 1.6, -1.25, 1.25, 1.0, 3.4)),
             ("cab", box(1.8, 4.0, -1.2, 1.2, 1.0, 2.9))]
    for i, x in enumerate((-3.0, -1.8, 2.9)):
        for side, (y0, y1) in (("left", (0.8, 1.2)), ("right", (-1.2, -0.8))):
            parts.append(("wheel_%d_%s" % (i, side), box(x - 0.5, x + 0.5, y0, y1, 0.0, 1.0)))
    return parts


def apc():
    """A wheeled armoured personnel carrier, its long axis along x (sloped nose at +x),
    centred on the origin, wheels on z = 0: 7.6 m x 2.9 m x 2.6 m with its cupola. A
    training target beside the tank, so that the trained detector learns a vehicle
    rather than one mesh."""
    # hull: a flat-bottomed box with a sloped glacis and a sloped rear, sides straight
    prof = [(-3.8, 0.5), (3.2, 0.5), (3.8, 1.3), (3.0, 2.1), (-3.6, 2.1), (-3.8, 1.6)]
    parts = [("hull", extrude_y(prof, 1.45)),
             ("cupola", prism(0.6, 0.0, 0.7, 8, 2.1, 2.6, r_top=0.6, phase=math.pi / 8))]
    for i, x in enumerate((-2.6, -1.2, 1.2, 2.6)):
        for side, (y0, y1) in (("left", (1.0, 1.45)), ("right", (-1.45, -1.0))):
            parts.append(("wheel_%d_%s" % (i, side), box(x - 0.55, x + 0.55, y0, y1, 0.0, 1.1)))
    return parts


def van():
    """A panel van, its long axis along x (bonnet at +x), centred on the origin, wheels on
    z = 0: 6.0 m x 2.2 m x 2.7 m. A second training target (see apc)."""
    parts = [("body", box(-3.0, 2.0, -1.1, 1.1, 0.45, 2.7)),
             ("bonnet", box(2.0, 3.0, -1.05, 1.05, 0.45, 1.3))]
    # the windscreen's slope from the bonnet to the roof
    parts.append(("windscreen", extrude_y([(2.0, 1.3), (3.0, 1.3), (2.0, 2.7)], 1.05)))
    for i, x in enumerate((-2.0, 2.2)):
        for side, (y0, y1) in (("left", (0.75, 1.1)), ("right", (-1.1, -0.75))):
            parts.append(("wheel_%d_%s" % (i, side), box(x - 0.4, x + 0.4, y0, y1, 0.0, 0.8)))
    return parts


# ----------------------------------------------------------------------------------
# Ground
# ----------------------------------------------------------------------------------

def grid(half_size, cell, height):
    n = int(round(2 * half_size / cell))
    m = Mesh()
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = -half_size + i * cell, -half_size + j * cell
            m.vert(x, y, height(x, y))
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            m.quad(a, a + 1, a + n + 2, a + n + 1)
    return m


def flat_height(x, y):
    """Gentle relief, |z| < 0.45 m: keeps the ground inside the 3 m RANSAC band."""
    return 0.25 * math.sin(x / 23.0) * math.cos(y / 31.0) + 0.15 * math.sin((x + 2 * y) / 13.0)


def hilly_base(x, y):
    return (6.0 * math.sin(x / 40.0 + 0.6) * math.cos(y / 55.0 - 0.3)
            + 3.5 * math.sin((x - y) / 27.0 + 1.1) + 0.01 * x)


def hilly_height(x, y):
    """About 15-20 m of relief over the covered disc, blended into a level pad of
    ~12 m radius around the origin so the tank and its house stand level."""
    w = math.exp(-(x * x + y * y) / (2 * 12.0 * 12.0))
    return (1 - w) * hilly_base(x, y) + w * hilly_base(0.0, 0.0)


SLOPES_HALF, SLOPES_CELL, SLOPES_MAX = 150.0, 2.5, 0.265
_slopes_grid = None


def slopes_grid():
    """Heights of the slopes ground at its grid vertices: a ramp rising ~21 % to the
    north-east with two long waves, then cut down until no slope exceeds SLOPES_MAX
    (a slope limiter: each vertex at most its neighbour's height plus the allowed slope
    times their distance), the allowance falling to 0 within 5 m of the origin, which
    leaves a level pad there for the target."""
    global _slopes_grid
    if _slopes_grid is not None:
        return _slopes_grid
    n = int(round(2 * SLOPES_HALF / SLOPES_CELL))
    at = lambda k: -SLOPES_HALF + k * SLOPES_CELL

    def raw(x, y):
        return (0.21 * (0.8 * x + 0.6 * y) + 3.0 * math.sin((x + 0.5 * y) / 26.0 + 0.4)
                + 2.5 * math.cos(y / 30.0 - 0.7))

    def allowed(x, y):
        t = min(max((math.hypot(x, y) - 5.0) / 15.0, 0.0), 1.0)
        return SLOPES_MAX * t * t * (3 - 2 * t)

    z = [[raw(at(i), at(j)) for i in range(n + 1)] for j in range(n + 1)]
    s = [[allowed(at(i), at(j)) for i in range(n + 1)] for j in range(n + 1)]
    changed = True
    while changed:
        changed = False
        for j in range(n + 1):
            for i in range(n + 1):
                for dj in (-1, 0, 1):
                    for di in (-1, 0, 1):
                        if (di or dj) and 0 <= i + di <= n and 0 <= j + dj <= n:
                            lim = (z[j + dj][i + di] + 0.5 * (s[j][i] + s[j + dj][i + di])
                                   * SLOPES_CELL * math.hypot(di, dj))
                            if z[j][i] > lim + 1e-9:
                                z[j][i] = lim
                                changed = True
    _slopes_grid = z
    return z


def slopes_height(x, y):
    """The slopes ground, bilinear between its grid vertices."""
    z = slopes_grid()
    n = len(z) - 1
    fx = min(max((x + SLOPES_HALF) / SLOPES_CELL, 0.0), n - 1e-9)
    fy = min(max((y + SLOPES_HALF) / SLOPES_CELL, 0.0), n - 1e-9)
    i, j = int(fx), int(fy)
    tx, ty = fx - i, fy - j
    return ((1 - ty) * ((1 - tx) * z[j][i] + tx * z[j][i + 1])
            + ty * ((1 - tx) * z[j + 1][i] + tx * z[j + 1][i + 1]))


# ----------------------------------------------------------------------------------
# Writers (compact, deterministic)
# ----------------------------------------------------------------------------------

def num(v):
    s = "%.3f" % v
    s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def obj_text(parts, comment, script="scripts/make_scenes.py"):
    """The OBJ text of named meshes: a comment, the script that wrote it, one object each."""
    lines = ["# " + comment, "# generated by %s; z up, metres" % script]
    base = 1
    for name, m in parts:
        lines.append("o " + name)
        lines += ["v %s %s %s" % tuple(num(c) for c in p) for p in m.v]
        lines += ["f %d %d %d" % (a + base, b + base, c + base) for a, b, c in m.f]
        base += len(m.v)
    return "\n".join(lines) + "\n"


def write_obj(path, parts, comment):
    with open(path, "w", newline="\n") as fh:
        fh.write(obj_text(parts, comment))


def write_ply(path, m, comment, binary):
    head = ["ply", "format %s 1.0" % ("binary_little_endian" if binary else "ascii"),
            "comment " + comment, "comment generated by scripts/make_scenes.py; z up, metres",
            "element vertex %d" % len(m.v), "property float x", "property float y",
            "property float z", "element face %d" % len(m.f),
            "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as fh:
        fh.write(("\n".join(head) + "\n").encode())
        if binary:
            fh.write(b"".join(struct.pack("<3f", *p) for p in m.v))
            fh.write(b"".join(struct.pack("<B3i", 3, *f) for f in m.f))
        else:
            body = ["%s %s %s" % tuple(num(c) for c in p) for p in m.v]
            body += ["3 %d %d %d" % f for f in m.f]
            fh.write(("\n".join(body) + "\n").encode())


def write_glb(path, m, comment):
    """Binary glTF 2.0 with y up (glTF's convention): file (x, y, z) = world (x, z, -y);
    the scene entry says "up": "y" so the loader maps it back."""
    pos = [(x, z, -y) for x, y, z in m.v]
    assert len(pos) < 65536
    vbytes = b"".join(struct.pack("<3f", *p) for p in pos)
    ibytes = b"".join(struct.pack("<3H", *f) for f in m.f)
    pad = (-len(ibytes)) % 4
    bin_chunk = vbytes + ibytes + b"\0" * pad
    f32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in pos]
    lo = [min(p[i] for p in f32) for i in range(3)]
    hi = [max(p[i] for p in f32) for i in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "ladarvr scripts/make_scenes.py",
                  "extras": {"comment": comment}},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "ground"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5123, "count": 3 * len(m.f), "type": "SCALAR"}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(vbytes), "target": 34962},
            {"buffer": 0, "byteOffset": len(vbytes), "byteLength": len(ibytes), "target": 34963}],
        "buffers": [{"byteLength": len(bin_chunk)}],
    }
    js = json.dumps(doc, separators=(",", ":"), sort_keys=True).encode()
    js += b" " * ((-len(js)) % 4)
    total = 12 + 8 + len(js) + 8 + len(bin_chunk)
    with open(path, "wb") as fh:
        fh.write(struct.pack("<4sII", b"glTF", 2, total))
        fh.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
        fh.write(struct.pack("<II", len(bin_chunk), 0x004E4942) + bin_chunk)


def write_ac3d(path, m, name):
    """AC3D (text): one object, triangles as polygon surfaces."""
    lines = ["AC3Db",
             'MATERIAL "foliage" rgb 0.2 0.5 0.2  amb 0.2 0.2 0.2  emis 0 0 0  '
             'spec 0 0 0  shi 0  trans 0',
             "OBJECT world", "kids 1", "OBJECT poly", 'name "%s"' % name,
             "numvert %d" % len(m.v)]
    lines += ["%s %s %s" % tuple(num(c) for c in p) for p in m.v]
    lines.append("numsurf %d" % len(m.f))
    for a, b, c in m.f:
        lines += ["SURF 0x10", "mat 0", "refs 3", "%d 0 0" % a, "%d 0 0" % b, "%d 0 0" % c]
    lines.append("kids 0")
    with open(path, "w", newline="\n") as fh:
        fh.write("\n".join(lines) + "\n")


def write_scene(path, comment, entries):
    doc = {"comment": comment, "meshes": entries}
    text = json.dumps(doc, indent=2)
    # Keep [x, y, z] triples on one line for readability.
    out, buf = [], None
    for line in text.split("\n"):
        s = line.strip()
        if buf is not None:
            buf.append(s)
            if s.startswith("]"):
                out.append(buf[0] + " ".join(buf[1:]).replace("[ ", "[").replace(" ]", "]"))
                buf = None
            continue
        if s.endswith("[") and '"position"' in s:
            buf = [line]
            continue
        out.append(line)
    with open(path, "w", newline="\n") as fh:
        fh.write("\n".join(out) + "\n")


def entry(file, role, x=0.0, y=0.0, z=0.0, yaw=0.0, scale=1.0, up=None, pitch=0.0, roll=0.0):
    e = {"file": file, "role": role}
    if (x, y, z) != (0.0, 0.0, 0.0):
        e["position"] = [round(x, 3), round(y, 3), round(z, 3)]
    if yaw:
        e["yaw_deg"] = round(yaw, 2)
    if round(pitch, 2):
        e["pitch_deg"] = round(pitch, 2)
    if round(roll, 2):
        e["roll_deg"] = round(roll, 2)
    if scale != 1.0:
        e["scale"] = round(scale, 3)
    if up:
        e["up"] = up
    return e


def rotate(x, y, yaw_deg):
    a = math.radians(yaw_deg)
    return x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a)


# ----------------------------------------------------------------------------------
# Scenes
# ----------------------------------------------------------------------------------

def make_common(out):
    d = os.path.join(out, "common")
    os.makedirs(d, exist_ok=True)
    write_obj(os.path.join(d, "tank.obj"), tank(),
              "tank-like target: 7.0 x 3.5 x 2.5 m, barrel along +x, centred on the origin")
    write_obj(os.path.join(d, "truck.obj"), truck(),
              "box truck: 8.0 x 2.5 x 3.4 m, cab along +x, centred on the origin")
    write_obj(os.path.join(d, "apc.obj"), apc(),
              "wheeled APC: 7.6 x 2.9 x 2.6 m, nose along +x, centred on the origin")
    write_obj(os.path.join(d, "van.obj"), van(),
              "panel van: 6.0 x 2.2 x 2.7 m, bonnet along +x, centred on the origin")
    write_obj(os.path.join(d, "house_small.obj"), [("house", house(10.0, 8.0, 5.5, 8.5))],
              "house 10 x 8 m, eaves 5.5 m, ridge 8.5 m (walls from -4 m, below the ground)")
    write_obj(os.path.join(d, "house_large.obj"), [("house", house(16.0, 11.0, 8.0, 12.0))],
              "house 16 x 11 m, eaves 8 m, ridge 12 m (walls from -4 m)")
    write_obj(os.path.join(d, "tower.obj"), [("tower", flat_building(9.0, 9.0, 13.0))],
              "flat-roofed tower 9 x 9 x 13 m plus a 2 m roof structure (walls from -4 m)")
    write_obj(os.path.join(d, "row_building.obj"), [("row", house(30.0, 9.0, 9.0, 12.5))],
              "long row building 30 x 9 m, eaves 9 m, ridge 12.5 m (walls from -4 m)")
    write_ac3d(os.path.join(d, "tree_broadleaf.ac"), broadleaf_tree(random.Random(7)),
               "broadleaf")
    write_ply(os.path.join(d, "tree_conifer.ply"), conifer_tree(), "conifer tree", binary=False)
    write_glb(os.path.join(d, "ground_flat.glb"), grid(150.0, 2.0, flat_height),
              "300 x 300 m ground in 2 m cells, relief under 0.45 m")
    write_ply(os.path.join(d, "ground_hilly.ply"), grid(150.0, 2.5, hilly_height),
              "300 x 300 m hilly ground in 2.5 m cells, ~15 m of relief", binary=True)
    write_ply(os.path.join(d, "ground_slopes.ply"), grid(SLOPES_HALF, SLOPES_CELL, slopes_height),
              "300 x 300 m steep ground in 2.5 m cells, slopes up to 30 %", binary=True)


def ground_entries(kind):
    if kind == "flat":
        return [entry("../common/ground_flat.glb", "ground", up="y")]
    return [entry("../common/ground_hilly.ply", "ground")]


def scatter(rng, n, r_min, r_max, avoid, spacing):
    """n points in the ring r_min..r_max, at least `spacing` from each other and from
    the (x, y, radius) discs in `avoid`."""
    pts = []
    tries = 0
    while len(pts) < n and tries < 100000:
        tries += 1
        r = math.sqrt(rng.uniform(r_min * r_min, r_max * r_max))
        a = rng.uniform(0, 2 * math.pi)
        x, y = r * math.cos(a), r * math.sin(a)
        if any(math.hypot(x - ax, y - ay) < ar for ax, ay, ar in avoid):
            continue
        if any(math.hypot(x - px, y - py) < spacing for px, py in pts):
            continue
        pts.append((x, y))
    return pts


def tree_entries(rng, pts, height):
    out = []
    for x, y in pts:
        kind = "../common/tree_broadleaf.ac" if rng.random() < 0.6 else "../common/tree_conifer.ply"
        out.append(entry(kind, "environment", x, y, height(x, y), yaw=rng.uniform(0, 360),
                         scale=rng.uniform(0.8, 1.25), up="z"))
    return out


def village(rng, height, tank_yaw):
    """The shared layout of demo and hilly: the tank at the origin, a house 1.75 m from
    its left side, a broadleaf tree over its rear, and a village around."""
    ents = [entry("../common/tank.obj", "target", 0, 0, height(0, 0) - 0.05, yaw=tank_yaw)]
    hx, hy = rotate(0.0, 7.5, tank_yaw)                 # house wall 1.75 m from the tank
    ents.append(entry("../common/house_small.obj", "environment", hx, hy, height(hx, hy),
                      yaw=tank_yaw))
    tx, ty = rotate(-2.8, -2.5, tank_yaw)               # canopy over the rear half
    ents.append(entry("../common/tree_broadleaf.ac", "environment", tx, ty, height(tx, ty),
                      yaw=40.0, scale=1.15))
    buildings = [("house_large.obj", -30, 22, 75), ("tower.obj", 34, -26, 10),
                 ("house_small.obj", -24, -34, -12), ("house_large.obj", 12, 44, 5),
                 ("row_building.obj", 45, 25, 90), ("house_small.obj", -52, -4, 30),
                 ("tower.obj", -8, -55, 0), ("house_small.obj", 58, -50, 60),
                 ("house_large.obj", -75, 60, 20), ("house_small.obj", 90, 85, 0),
                 ("house_large.obj", -95, -90, 45)]
    avoid = [(0, 0, 9), (hx, hy, 9)]
    for f, x, y, yaw in buildings:
        ents.append(entry("../common/" + f, "environment", x, y, height(x, y), yaw=yaw))
        avoid.append((x, y, 15 if "row" not in f else 20))
    pts = scatter(rng, 40, 12, 110, avoid, 7.0)
    ents += tree_entries(rng, pts, height)
    return ents


def make_demo(out):
    d = os.path.join(out, "demo")
    os.makedirs(d, exist_ok=True)
    rng = random.Random(2024)
    ents = ground_entries("flat") + village(rng, flat_height, tank_yaw=20.0)
    write_scene(os.path.join(d, "scene.json"),
                "ladarvr demo: a tank at the origin beside a house and half under a tree, in a "
                "village on nearly flat ground (300 x 300 m). Made by scripts/make_scenes.py.",
                ents)


def make_hard(out):
    d = os.path.join(out, "hard")
    os.makedirs(d, exist_ok=True)
    rng = random.Random(99)
    h = flat_height
    ents = ground_entries("flat")
    ents.append(entry("../common/tank.obj", "target", 0, 0, h(0, 0) - 0.05))
    # A street 7 m wide along x between long buildings: 1.75 m each side of the tank.
    for y in (-8.0, 8.0):
        for x in (-16.0, 16.0):
            ents.append(entry("../common/row_building.obj", "environment", x, y, h(x, y)))
    # A tree over the bow, and a dense forest around the block.
    ents.append(entry("../common/tree_broadleaf.ac", "environment", 3.0, 1.0, h(3, 1), yaw=200,
                      scale=1.1))
    avoid = [(x, y, 17) for x in (-16.0, 16.0) for y in (-8.0, 8.0)] + [(0, 0, 6)]
    pts = scatter(rng, 520, 4, 62, avoid, 3.8)
    ents += tree_entries(rng, pts, h)
    write_scene(os.path.join(d, "scene.json"),
                "ladarvr hard scene: the tank in a 7 m street between long buildings, under a "
                "tree, inside a dense forest. Made by scripts/make_scenes.py.", ents)


def make_hilly(out):
    d = os.path.join(out, "hilly")
    os.makedirs(d, exist_ok=True)
    rng = random.Random(5)
    ents = ground_entries("hilly") + village(rng, hilly_height, tank_yaw=-35.0)
    write_scene(os.path.join(d, "scene.json"),
                "ladarvr hilly scene: the demo's village on ground with ~15 m of relief, for "
                "comparing ground filters. Made by scripts/make_scenes.py.", ents)


def make_slopes(out):
    d = os.path.join(out, "slopes")
    os.makedirs(d, exist_ok=True)
    rng = random.Random(31)
    h = slopes_height

    def footing(x, y, radius):
        """The lowest ground under a building's footprint: its walls (which reach 4 m
        below the mesh origin) then meet the ground on the downhill side."""
        return min(h(x + radius * math.cos(a), y + radius * math.sin(a))
                   for a in [k * math.pi / 4 for k in range(8)] + [0.0]) if radius else h(x, y)

    ents = [entry("../common/ground_slopes.ply", "ground"),
            entry("../common/tank.obj", "target", 0, 0, h(0, 0) - 0.05, yaw=15.0)]
    ents.append(entry("../common/tree_broadleaf.ac", "environment", -2.5, -2.0, h(-2.5, -2.0),
                      yaw=80.0, scale=1.1))
    buildings = [("house_small.obj", 14, 6, 20, 6.5), ("house_large.obj", -22, 18, 70, 9.8),
                 ("tower.obj", 30, -20, 15, 6.4), ("house_small.obj", -18, -30, -10, 6.5),
                 ("house_large.obj", 8, 42, 0, 9.8), ("row_building.obj", 48, 28, 35, 15.7),
                 ("house_small.obj", -48, 2, 25, 6.5), ("house_small.obj", 40, -48, 50, 6.5),
                 ("house_large.obj", -60, 50, 10, 9.8), ("tower.obj", -40, -60, 0, 6.4)]
    avoid = [(0, 0, 8)]
    for f, x, y, yaw, radius in buildings:
        ents.append(entry("../common/" + f, "environment", x, y, footing(x, y, radius), yaw=yaw))
        avoid.append((x, y, radius + 5))
    pts = scatter(rng, 45, 9, 110, avoid, 6.5)
    for x, y in pts:
        kind = "../common/tree_broadleaf.ac" if rng.random() < 0.5 else "../common/tree_conifer.ply"
        ents.append(entry(kind, "environment", x, y, h(x, y) - 0.3, yaw=rng.uniform(0, 360),
                          scale=rng.uniform(0.8, 1.25), up="z"))
    write_scene(os.path.join(d, "scene.json"),
                "ladarvr slopes scene: the tank on a small level pad in steep terrain (~27 m of "
                "relief inside the covered disc, slopes up to 30 %), houses and trees on the "
                "slopes, for terrain-following ground filters. Made by scripts/make_scenes.py.", ents)


def make_forest(out):
    d = os.path.join(out, "forest")
    os.makedirs(d, exist_ok=True)
    rng = random.Random(47)
    h = slopes_height

    def slope(x, y):
        gx = (h(x + 0.5, y) - h(x - 0.5, y))
        gy = (h(x, y + 0.5) - h(x, y - 0.5))
        return gx, gy

    # The tank on the first spot of a ring 30 m out whose slope is 12-18 %, its long
    # axis along the contour: the slopes' level pad lies elsewhere.
    tx, ty = 30.0, 0.0
    for k in range(72):
        a = k * math.pi / 36
        x, y = 30.0 * math.cos(a), 30.0 * math.sin(a)
        gx, gy = slope(x, y)
        if 0.12 <= math.hypot(gx, gy) <= 0.18:
            tx, ty = x, y
            break
    gx, gy = slope(tx, ty)
    yaw = math.degrees(math.atan2(gy, gx)) + 90.0
    # The tank rests on the slope, as a vehicle does: the plane that best fits the ground
    # under its 7 x 3.5 m footprint (least squares, in the tank's own axes) gives its pitch
    # and roll, and its bottom sits 5 cm into that plane as in the other scenes.
    ca, sa = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    samples = [(0.25 * i, 0.25 * j) for i in range(-14, 15) for j in range(-7, 8)]
    zs = [h(tx + ca * u - sa * v, ty + sa * u + ca * v) for u, v in samples]
    mean = sum(zs) / len(zs)
    along = sum(u * z for (u, _), z in zip(samples, zs)) / sum(u * u for u, _ in samples)
    across = sum(v * z for (_, v), z in zip(samples, zs)) / sum(v * v for _, v in samples)
    pitch, roll = -math.degrees(math.atan(along)), math.degrees(math.atan(across))
    ents = [entry("../common/ground_slopes.ply", "ground"),
            entry("../common/tank.obj", "target", tx, ty, mean - 0.05, yaw=yaw, pitch=pitch, roll=roll)]
    # Two trees over half the tank, then a forest all round with gaps between crowns.
    for dx, dy in ((2.5, 1.5), (-1.0, 3.0)):
        x, y = tx + dx, ty + dy
        ents.append(entry("../common/tree_broadleaf.ac", "environment", x, y, h(x, y) - 0.3,
                          yaw=rng.uniform(0, 360), scale=1.2, up="z"))
    avoid = [(tx, ty, 4.5), (tx + 2.5, ty + 1.5, 4.0), (tx - 1.0, ty + 3.0, 4.0)]
    pts = [(x + tx, y + ty) for x, y in scatter(rng, 900, 0, 105, [(ax - tx, ay - ty, ar) for ax, ay, ar in avoid], 4.2)]
    for x, y in pts:
        kind = "../common/tree_broadleaf.ac" if rng.random() < 0.5 else "../common/tree_conifer.ply"
        ents.append(entry(kind, "environment", x, y, h(x, y) - 0.3, yaw=rng.uniform(0, 360),
                          scale=rng.uniform(0.8, 1.25), up="z"))
    write_scene(os.path.join(d, "scene.json"),
                "ladarvr forest scene: the slopes' steep ground under a forest canopy, the tank resting "
                "on a 12-18 % slope half hidden under two trees; ground returns come only through the "
                "gaps between crowns. Made by scripts/make_scenes.py.", ents)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(here, "..", "assets"))
    args = ap.parse_args()
    out = os.path.normpath(args.out)
    make_common(out)
    make_demo(out)
    make_hard(out)
    make_hilly(out)
    make_slopes(out)
    make_forest(out)
    total = 0
    for root, _, files in os.walk(out):
        for f in files:
            total += os.path.getsize(os.path.join(root, f))
    print("wrote scenes under %s (%.2f MB)" % (out, total / 1e6))


if __name__ == "__main__":
    main()
