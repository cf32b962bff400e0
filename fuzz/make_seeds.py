#!/usr/bin/env python3
"""Writes the small seed inputs of the fuzz targets into fuzz/seeds/ (stdlib only,
byte-identical on every run). Seeds are tiny so libFuzzer's mutations stay cheap:
every PCD DATA kind and PLY encoding the reader accepts, with our fields and foreign
layouts (double coordinates, rgba, float colours, list and padding properties). The
detector model seeds are XGBoost's bytes of the shipped assets/detect/model.ldm, cut to
two trees and crafted from that."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CLOUD = os.path.join(HERE, "seeds", "cloud")
SCENE = os.path.join(HERE, "seeds", "scene")
SCRIPT = os.path.join(HERE, "seeds", "script")
REPLAY = os.path.join(HERE, "seeds", "replay")
LAS = os.path.join(HERE, "seeds", "las")
MODEL = os.path.join(HERE, "seeds", "model")
CRS = os.path.join(HERE, "seeds", "las_crs")
CANDIDATES = os.path.join(HERE, "seeds", "candidates")
STUDY = os.path.join(HERE, "seeds", "study")
REPORT = os.path.join(HERE, "seeds", "study_report")
REAL = os.path.join(HERE, "..", "tests", "data", "real")
SHIPPED_MODEL = os.path.join(HERE, "..", "assets", "detect", "model.ldm")

PTS = [(0.0, 0.0, 0.0, 0xFF0000, 0, 0, 10.0), (1.5, -2.0, 0.25, 0x00FF00, 1, 1, 11.5),
       (3.0, 4.0, -1.0, 0x0000FF, 2, 7, 12.25)]


def pcd_header(fields, size, typ, count, n, data, extra=""):
    return ("# .PCD v0.7 - Point Cloud Data file format\n" + extra + "VERSION 0.7\nFIELDS %s\nSIZE %s\nTYPE %s\n"
            "COUNT %s\nWIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA %s\n" %
            (fields, size, typ, count, n, n, data)).encode()


def lzf_literal(raw):
    """LZF stream using literal runs only (<= 32 bytes each): valid for the decoder."""
    out = bytearray()
    for i in range(0, len(raw), 32):
        chunk = raw[i:i + 32]
        out.append(len(chunk) - 1)
        out += chunk
    return bytes(out)


def write(name, data, d=CLOUD):
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def las_file(minor, fmt, points, extra=b"", vlrs=b"", nvlrs=0):
    """An uncompressed LAS 1.<minor> file of point format 3 or 7 (`extra`: the extra
    bytes after each record, described by `vlrs`)."""
    header_size = {2: 227, 3: 235, 4: 375}[minor]
    base = {3: 34, 7: 36}[fmt]
    record = base + len(extra)
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    zs = [p[2] for p in points]
    h = struct.pack("<4sHH16sBB32s32sHHHIIBHI5I", b"LASF", 0, 16 if minor == 4 else 0, b"", 1, minor,
                    b"seed", b"make_seeds.py", 1, 2024, header_size, header_size + len(vlrs), nvlrs, fmt,
                    record, len(points) if fmt < 6 else 0, len(points), 0, 0, 0, 0)
    h += struct.pack("<12d", 0.001, 0.001, 0.001, 5400000.0, 1000000.0, 0.0,
                     max(xs), min(xs), max(ys), min(ys), max(zs), min(zs))
    if minor >= 3:
        h += struct.pack("<Q", 0)
    if minor >= 4:
        h += struct.pack("<QIQ15Q", 0, 0, len(points), len(points), *([0] * 14))
    assert len(h) == header_size
    body = b""
    for i, (x, y, z, cls) in enumerate(points):
        xyz = (round((x - 5400000.0) / 0.001), round((y - 1000000.0) / 0.001), round(z / 0.001))
        if fmt == 3:
            body += struct.pack("<3iHBBbBHd3H", *xyz, 100 * i, 1 | (1 << 3), cls, 0, 0, i, float(i),
                                65535, 0, 257 * i)
        else:
            body += struct.pack("<3iHBBBBhHd3H", *xyz, 100 * i, 1 | (1 << 4), 0, cls, 0, 500 * i, i, float(i),
                                65535, 0, 257 * i)
        body += extra
    return h + vlrs + body


def extra_bytes_vlr(fields):
    """The LAS 1.4 extra bytes VLR for (name, data type) pairs."""
    payload = b"".join(struct.pack("<2sBB32s4s120s32s", b"", t, 0, n.encode(), b"", b"", b"") for n, t in fields)
    return struct.pack("<H16sHH32s", 0, b"LASF_Spec", 4, len(payload), b"extra bytes") + payload


def laz_file(points, extra=b"", vlrs=b"", nvlrs=0, compressor=3, table="ok"):
    """A LAZ 1.4 file of point format 7 whose chunks hold one point each, so no point
    needs the arithmetic coder: each chunk is the raw first point, its count (1) and the
    sizes of its 15 layers (POINT14's 9, RGB14's 1, one per extra byte), of which only
    the first has bytes (4, what its decoder reads when it starts). `table`: "none" (no
    table: LASzip finds the chunks as it reads), "ok" (a table of the right count whose
    coded sizes are left as zeros: LASzip checks each chunk's start against them, so
    only the reader's checks before it pass), or a (count, cut) pair for crafted ones."""
    las = las_file(4, 7, points, extra, vlrs, nvlrs)
    header_size = 375
    data_at = struct.unpack_from("<I", las, 96)[0]
    record = struct.unpack_from("<H", las, 105)[0]
    body = las[data_at:]
    items = [(10, 30, 3), (11, 6, 3)] + ([(14, len(extra), 3)] if extra else [])
    payload = struct.pack("<HHBBHIIqqH", compressor, 0, 3, 4, 3, 0, 1, -1, -1, len(items))
    payload += b"".join(struct.pack("<HHH", *i) for i in items)
    laszip_vlr = struct.pack("<H16sHH32s", 0, b"laszip encoded", 22204, len(payload), b"seed") + payload
    layers = 9 + 1 + len(extra)
    chunks = b""
    for i in range(len(points)):
        chunks += body[i * record:(i + 1) * record] + struct.pack("<I", 1)
        chunks += struct.pack("<%dI" % layers, 4, *([0] * (layers - 1))) + b"\0" * 4
    head = bytearray(las[:data_at] + laszip_vlr)
    struct.pack_into("<I", head, 96, len(head))
    struct.pack_into("<I", head, 100, nvlrs + 1)
    head[104] = 7 | 0x80
    table_at = len(head) + 8 + len(chunks)
    if table == "none":
        return bytes(head) + struct.pack("<q", len(head)) + chunks
    count, cut = (len(points), None) if table == "ok" else table
    out = bytes(head) + struct.pack("<q", table_at) + chunks + struct.pack("<II", 0, count) + b"\0" * 8
    return out[:cut] if cut is not None else out


# XGBoost's UBJSON as it writes it (lengths and counts as 'L', optimized arrays of numbers),
# decoded into tuples that encode back to the same bytes: ("{", [(key, value)]),
# ("[", [items]) (counted), ("$", type, count, raw bytes), ("S", bytes), (marker, raw bytes).
UBJ_SIZES = {"i": 1, "U": 1, "I": 2, "l": 4, "L": 8, "d": 4, "D": 8}


def ubj_length(b, i):
    assert b[i:i + 1] == b"L", "length marker %r at %d" % (b[i:i + 1], i)
    return struct.unpack_from(">q", b, i + 1)[0], i + 9


def ubj_decode(b, i=0):
    m = chr(b[i])
    i += 1
    if m in UBJ_SIZES:
        return (m, b[i:i + UBJ_SIZES[m]]), i + UBJ_SIZES[m]
    if m in "ZTF":
        return (m, b""), i
    if m == "S":
        n, i = ubj_length(b, i)
        return ("S", b[i:i + n]), i + n
    if m == "{":
        members = []
        while b[i:i + 1] != b"}":
            n, i = ubj_length(b, i)
            key = b[i:i + n].decode()
            value, i = ubj_decode(b, i + n)
            members.append((key, value))
        return ("{", members), i + 1
    if m == "[" and b[i:i + 1] == b"$":
        t = chr(b[i + 1])
        assert b[i + 2:i + 3] == b"#"
        n, i = ubj_length(b, i + 3)
        return ("$", t, n, b[i:i + n * UBJ_SIZES[t]]), i + n * UBJ_SIZES[t]
    assert m == "[" and b[i:i + 1] == b"#", "marker %r at %d" % (m, i - 1)
    n, i = ubj_length(b, i + 1)
    items = []
    for _ in range(n):
        item, i = ubj_decode(b, i)
        items.append(item)
    return ("[", items), i


def ubj_encode(v):
    def length(n):
        return b"L" + struct.pack(">q", n)
    m = v[0]
    if m == "{":
        return b"{" + b"".join(length(len(k)) + k.encode() + ubj_encode(x) for k, x in v[1]) + b"}"
    if m == "[":
        return b"[#" + length(len(v[1])) + b"".join(ubj_encode(x) for x in v[1])
    if m == "$":
        return b"[$" + v[1].encode() + b"#" + length(v[2]) + v[3]
    if m == "S":
        return b"S" + length(len(v[1])) + v[1]
    return m.encode() + v[1]


def ubj_get(v, *path):
    for key in path:
        v = v[1][key] if isinstance(key, int) else dict(v[1])[key]
    return v


def ubj_set(v, path, new):
    """v with the value at `path` (keys and list indices) replaced by `new`."""
    if not path:
        return new
    key, rest = path[0], path[1:]
    if isinstance(key, int):
        items = list(v[1])
        items[key] = ubj_set(items[key], rest, new)
        return (v[0], items)
    return (v[0], [(k, ubj_set(x, rest, new) if k == key else x) for k, x in v[1]])


def shipped_model_ubjson():
    """XGBoost's bytes of the shipped detector model (after its 20 + header bytes)."""
    with open(SHIPPED_MODEL, "rb") as f:
        data = f.read()
    assert data[:8] == b"LDVRDET1"
    header = struct.unpack_from("<I", data, 8)[0]
    return data[20 + header:]


def model_seeds():
    """The shipped model's bytes, the same cut to its first two trees (cheap to mutate), and
    crafted ones that crashed or hung XGBoost before the checker: a child out of range, a
    self-loop, a split on a feature out of range, an output group out of range."""
    os.makedirs(MODEL, exist_ok=True)
    full = shipped_model_ubjson()
    model, end = ubj_decode(full)
    assert end == len(full) and ubj_encode(model) == full, "the UBJSON codec does not round-trip"
    write("shipped.ubj", full, MODEL)
    gb = ("learner", "gradient_booster", "model")
    small = ubj_set(model, gb + ("trees",), ("[", ubj_get(model, *gb, "trees")[1][:2]))
    small = ubj_set(small, gb + ("tree_info",), ("[", ubj_get(model, *gb, "tree_info")[1][:2]))
    small = ubj_set(small, gb + ("iteration_indptr",), ("[", ubj_get(model, *gb, "iteration_indptr")[1][:3]))
    small = ubj_set(small, gb + ("gbtree_model_param", "num_trees"), ("S", b"2"))
    write("two_trees.ubj", ubj_encode(small), MODEL)

    def patched(path, k, value):
        typed = ubj_get(small, *path)
        raw = bytearray(typed[3])
        fmt = {"l": ">i", "U": ">B", "d": ">f"}[typed[1]]
        struct.pack_into(fmt, raw, k * struct.calcsize(fmt), value)
        return ubj_encode(ubj_set(small, path, ("$", typed[1], typed[2], bytes(raw))))
    tree0 = gb + ("trees", 0)
    write("crafted_child_out_of_range.ubj", patched(tree0 + ("left_children",), 0, 99), MODEL)
    write("crafted_self_loop.ubj", patched(tree0 + ("left_children",), 0, 0), MODEL)
    write("crafted_split_feature.ubj", patched(tree0 + ("split_indices",), 0, 1000000), MODEL)
    write("crafted_categorical.ubj", patched(tree0 + ("split_type",), 0, 1), MODEL)
    write("crafted_group.ubj", ubj_encode(ubj_set(small, gb + ("tree_info", 0), ("i", b"\x05"))), MODEL)


def main():
    os.makedirs(LAS, exist_ok=True)
    geo = [(5400000.125, 1000000.5, 12.0, 2), (5400001.0, 1000001.25, 14.5, 6), (5400002.5, 999999.0, 3.0, 64)]
    write("asprs_12.las", las_file(2, 3, [(x, y, z, min(c, 31)) for x, y, z, c in geo]), LAS)
    ours = (struct.pack("<fB", 250.5, 1), extra_bytes_vlr([("range", 9), ("label", 1)]), 1)
    write("ours_14.las", las_file(4, 7, geo, *ours), LAS)
    # LAZ, and the crafted files that crashed LASzip before the reader checked what it
    # trusts: compressors that do not suit LAS 1.4 items, a file cut inside the chunk
    # table, a chunk count with its high byte set; and what else the reader refuses.
    write("ours_14.laz", laz_file(geo, *ours, table="none"), LAS)
    write("crafted_compressor1.laz", laz_file(geo, *ours, compressor=1), LAS)
    write("crafted_compressor2.laz", laz_file(geo, *ours, compressor=2), LAS)
    full = laz_file(geo, *ours)
    table_at = struct.unpack_from("<q", full, struct.unpack_from("<I", full, 96)[0])[0]
    write("crafted_table_cut6.laz", full[:table_at + 6], LAS)
    write("crafted_table_cut7.laz", full[:table_at + 7], LAS)
    write("crafted_table_count_high.laz", laz_file(geo, *ours, table=(0x80000003, None)), LAS)
    wrap = bytearray(full)
    first = struct.unpack_from("<I", full, 96)[0] + 8 + struct.unpack_from("<H", full, 105)[0] + 4
    struct.pack_into("<II", wrap, first, 0xFFFFFFFF, 2)  # the layer sizes' 32-bit sum wraps
    write("crafted_layers_wrap.laz", bytes(wrap), LAS)
    fewer = bytearray(full)
    struct.pack_into("<Q", fewer, 247, len(geo) - 1)
    write("crafted_fewer_points.laz", bytes(fewer), LAS)
    fewer = bytearray(las_file(4, 7, geo, *ours))
    struct.pack_into("<Q", fewer, 247, len(geo) - 1)
    write("crafted_fewer_points.las", bytes(fewer), LAS)
    # Two extra bytes VLRs: the first's fields (5 bytes) with the second's size (1 byte).
    two = extra_bytes_vlr([("range", 9), ("label", 1)]) + extra_bytes_vlr([("other", 1)])
    write("crafted_two_extra_vlrs.las", las_file(4, 7, geo, ours[0], two, 2), LAS)
    os.makedirs(CLOUD, exist_ok=True)
    os.makedirs(SCENE, exist_ok=True)
    os.makedirs(SCRIPT, exist_ok=True)
    ours = ("x y z rgb label view range", "4 4 4 4 1 2 4", "F F F F U U F", "1 1 1 1 1 1 1")
    origin = "# ladarvr origin 1000000.5 -2000000.25 30\n"
    # ascii, ours
    body = "".join("%r %r %r %.9g %d %d %r\n" % (x, y, z, struct.unpack("<f", struct.pack("<I", c))[0], l, v, r)
                   for x, y, z, c, l, v, r in PTS)
    write("ours_ascii.pcd", pcd_header(*ours, len(PTS), "ascii", origin) + body.encode())
    # binary, ours
    rec = b"".join(struct.pack("<fffIBHf", x, y, z, c, l, v, r) for x, y, z, c, l, v, r in PTS)
    write("ours_binary.pcd", pcd_header(*ours, len(PTS), "binary", origin) + rec)
    # binary_compressed: SoA columns, LZF literals
    cols = b"".join(b"".join(struct.pack(fmt, p[i]) for p in PTS)
                    for i, fmt in enumerate(["<f", "<f", "<f", "<I", "<B", "<H", "<f"]))
    comp = lzf_literal(cols)
    write("ours_compressed.pcd", pcd_header(*ours, len(PTS), "binary_compressed", origin) +
          struct.pack("<II", len(comp), len(cols)) + comp)
    # xyz only, double coordinates, rgba, padding field with count 3
    rec = b"".join(struct.pack("<dddI", x, y, z, c | 0xFF000000) + b"\0" * 12 for x, y, z, c, *_ in PTS)
    write("foreign_binary.pcd", pcd_header("x y z rgba _", "8 8 8 4 4", "F F F U F", "1 1 1 1 3",
                                           len(PTS), "binary") + rec)
    write("xyz_ascii.pcd", pcd_header("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii") + b"1 2 3\n4 5 6\n")
    # PLY ascii, ours
    ply_props = ("property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
                 "property uchar green\nproperty uchar blue\nproperty uchar label\nproperty ushort view\n"
                 "property float range\n")
    head = "ply\nformat %s 1.0\ncomment ladarvr origin 5 6 7\nelement vertex %d\n" + ply_props + "end_header\n"
    body = "".join("%r %r %r %d %d %d %d %d %r\n" % (x, y, z, c >> 16, (c >> 8) & 255, c & 255, l, v, r)
                   for x, y, z, c, l, v, r in PTS)
    write("ours_ascii.ply", (head % ("ascii", len(PTS))).encode() + body.encode())
    for fmt, e in (("binary_little_endian", "<"), ("binary_big_endian", ">")):
        rec = b"".join(struct.pack(e + "fffBBBBHf", x, y, z, c >> 16, (c >> 8) & 255, c & 255, l, v, r)
                       for x, y, z, c, l, v, r in PTS)
        write("ours_%s.ply" % fmt, (head % (fmt, len(PTS))).encode() + rec)
    # PLY with a face element before the vertices (lists), double coords, float colours
    head = ("ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
            "element vertex 2\nproperty double x\nproperty double y\nproperty double z\n"
            "property float red\nproperty float green\nproperty float blue\nend_header\n")
    data = struct.pack("<B3i", 3, 0, 1, 0) + b"".join(struct.pack("<dddfff", i, 2.0 * i, 3.0, 0.5, 0.25, 1.0)
                                                     for i in range(2))
    write("foreign_faces.ply", head.encode() + data)

    # Scenes: mesh names resolve in tests/data/scenes/basic/ (box.obj, ground.obj).
    write("basic.json", b'{"meshes": [{"file": "ground.obj", "role": "ground"},\n'
          b' {"file": "box.obj", "role": "target", "position": [2, 3, 0], "yaw_deg": 90, "scale": 2},\n'
          b' {"file": "box.obj", "role": "environment", "position": [-5, 0, 0], "up": "y"}]}\n', SCENE)
    write("georef.json", b'{"comment": "far away", "origin": [1e7, -1e6, 12.5],\n'
          b' "meshes": [{"file": "box.obj", "role": "target", "position": [10000002.0, -1000003.0, 12.5]}]}\n', SCENE)
    write("errors.json", b'{"meshes": [{"file": "box.obj", "role": "target", "scale": 1e-30, "up": "z", '
          b'"comment": "x"}, {"file": "nothere.obj", "role": "buildng"}]}\n', SCENE)

    # Viewer scripts: the documented form, and the lines the parser refuses.
    write("keys.txt", b"# frame key\n10 space\n\n25 space   # back\n40 escape\n", SCRIPT)
    write("crlf_tabs.txt", b"0\tspace\r\n7 escape\r\n#\r\n", SCRIPT)
    write("errors.txt", b"5 space now\n-3 space\nten space\n5 jump\n99999999999999999999 escape\n5\n", SCRIPT)

    # Detector models: XGBoost's UBJSON bytes of assets/detect/model.ldm and cuts of it.
    model_seeds()


def replay_seeds():
    """Traces as a study writes them (trace_<N>.csv) for fuzz_view_replay, and the lines
    its reader refuses."""
    os.makedirs(REPLAY, exist_ok=True)
    header = b"t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z\n"
    write("study.csv", header +
          b"0.000000,1.000000,2.000000,30.000000,1.000000000,0.000000000,0.000000000,0.000000000,automatic,1,,,\n"
          b"0.011111,1.000000,2.000000,30.000000,0.707106781,0.707106781,0.000000000,0.000000000,free,2.5,"
          b"10.000000,20.000000,0.500000\n"
          b"0.011111,1.500000,2.000000,30.000000,0.707106781,0.000000000,0.707106781,0.000000000,free,2.5,,,\n",
          REPLAY)
    write("head_only_crlf.csv", b"t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz\r\n"
          b"0,1,2,3,1,0,0,0\r\n0.5,1,2,3,1.0005,0,0,0", REPLAY)
    write("extra_column.csv", header[:-1] + b",note\n0,1,2,3,1,0,0,0,free,2,,,,anything\n", REPLAY)
    write("errors_time.csv", header + b"0,1,2,3,1,0,0,0,free,1,,,\n1e300,1,2,3,1,0,0,0,free,1,,,\n", REPLAY)
    write("errors_back.csv", header + b"1,1,2,3,1,0,0,0,free,1,,,\n0.5,1,2,3,1,0,0,0,free,1,,,\n", REPLAY)
    write("errors_values.csv", header + b"0,1,2,1e300,2,0,0,0,walk,0,4,,6\n", REPLAY)


def las_vlrs(path):
    """The (user id, record id, payload) of a LAS file's VLRs (its header is read as far
    as they go: a LAZ file's are not compressed)."""
    with open(path, "rb") as f:
        data = f.read(1 << 16)
    header_size, = struct.unpack_from("<H", data, 94)
    count, = struct.unpack_from("<I", data, 100)
    at, out = header_size, []
    for _ in range(count):
        user = data[at + 2:at + 18].rstrip(b"\0")
        record, length = struct.unpack_from("<HH", data, at + 18)
        out.append((user, record, data[at + 54:at + 54 + length]))
        at += 54 + length
    return out


def crs_input(wkt=None, keys=b"", doubles=b"", ascii=b""):
    """fuzz_las_crs's input: byte 0 even and a WKT payload, or odd and the GeoTIFF
    records behind their two lengths."""
    if wkt is not None:
        return b"\0" + wkt
    return b"\1" + struct.pack("<HH", len(keys), len(doubles)) + keys + doubles + ascii


def geokeys(*keys):
    """A GeoKeyDirectory of (key, location, count, value) entries."""
    out = struct.pack("<4H", 1, 1, 0, len(keys))
    for k in keys:
        out += struct.pack("<4H", *k)
    return out


def crs_seeds():
    """fuzz_las_crs: the CRS records of tests/data/real's files (WKT, GeoTIFF keys with
    their doubles and ASCII), and crafted ones: WKT 2 with units on the axes, a compound
    CRS, user-defined units, keys pointing outside their records."""
    os.makedirs(CRS, exist_ok=True)
    for name in sorted(os.listdir(REAL)):
        if not name.endswith((".las", ".laz")):
            continue
        records = {(u, r): p for u, r, p in las_vlrs(os.path.join(REAL, name))}
        stem = name.rsplit(".", 1)[0]
        if (b"LASF_Projection", 2112) in records:
            write(stem + "_wkt.bin", crs_input(records[(b"LASF_Projection", 2112)]), CRS)
        if (b"LASF_Projection", 34735) in records:
            write(stem + "_geotiff.bin", crs_input(None, records[(b"LASF_Projection", 34735)],
                                                   records.get((b"LASF_Projection", 34736), b""),
                                                   records.get((b"LASF_Projection", 34737), b"")), CRS)
    write("wkt2_axes.bin", crs_input(
        b'PROJCRS["WGS 84 / UTM zone 32N",BASEGEOGCRS["WGS 84",DATUM["World Geodetic System 1984",'
        b'ELLIPSOID["WGS 84",6378137,298.257223563,LENGTHUNIT["metre",1]]],'
        b'PRIMEM["Greenwich",0,ANGLEUNIT["degree",0.0174532925199433]]],CONVERSION["UTM zone 32N",'
        b'METHOD["Transverse Mercator",ID["EPSG",9807]]],CS[Cartesian,2],'
        b'AXIS["(E)",east,ORDER[1],LENGTHUNIT["US survey foot",0.304800609601219]],'
        b'AXIS["(N)",north,ORDER[2],LENGTHUNIT["US survey foot",0.304800609601219]],ID["EPSG",32632]]'), CRS)
    write("wkt1_compound.bin", crs_input(
        b'COMPD_CS["NAD83 + NAVD88",PROJCS["NAD83 / UTM 15N",GEOGCS["NAD83",DATUM["NAD83",'
        b'SPHEROID["GRS 1980",6378137,298.257222101]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],'
        b'PROJECTION["Transverse_Mercator"],UNIT["metre",1,AUTHORITY["EPSG","9001"]],AUTHORITY["EPSG","26915"]],'
        b'VERT_CS["NAVD88",VERT_DATUM["NAVD88",2005],UNIT["foot",0.3048],AUTHORITY["EPSG","8228"]]]\0'), CRS)
    write("wkt_unit_code_angle.bin", crs_input(b'PROJCS["x",UNIT["metre",1,AUTHORITY["EPSG","9102"]]]'), CRS)
    write("geotiff_user_units.bin", crs_input(
        None, geokeys((1024, 0, 1, 1), (3072, 0, 1, 32767), (3073, 34737, 9, 0), (3076, 0, 1, 32767),
                      (3077, 34736, 1, 0), (4099, 0, 1, 9003)),
        struct.pack("<d", 0.3048006096), b"My grid|\0"), CRS)
    write("geotiff_outside.bin", crs_input(
        None, geokeys((1024, 0, 1, 2), (2048, 0, 1, 4326), (2049, 34737, 200, 5), (3077, 34736, 1, 7)),
        b"", b"WGS 84|"), CRS)
    write("geotiff_vertical_only.bin", crs_input(None, geokeys((4096, 0, 1, 5703), (4099, 0, 1, 9001))), CRS)


def candidates_seeds():
    """Candidates files as `ladarvr detect` writes them and as a researcher might, for
    fuzz_candidates_file, and values its reader refuses."""
    os.makedirs(CANDIDATES, exist_ok=True)
    write("detect.json", b'{\n  "candidates": [\n    {\n      "centre": [12.5, -3.25, 1.0],\n'
          b'      "id": "c1",\n      "score": 0.8,\n      "size_m": [4.5, 2.0, 1.75],\n      "yaw_deg": 30.0\n'
          b'    },\n    {\n      "centre": [1e6, 2e6, 150.0],\n      "id": "c2",\n      "score": 0.0,\n'
          b'      "size_m": [0.5, 0.5, 0.5],\n      "yaw_deg": -720.0\n    }\n  ]\n}\n', CANDIDATES)
    write("hand.json", b'{"candidates": [{"id": "tank \\u00e9", "centre": [0, 0, 0], "size_m": [7, 3.5, 2.5],'
          b' "score": 1}]}', CANDIDATES)
    write("empty.json", b'{"candidates": []}', CANDIDATES)
    write("errors.json", b'{"candidates": [{"id": "a", "centre": [1, 2], "size_m": [0, 1, 1], "score": 1.5},'
          b' {"id": "a", "centre": [1e300, 0, 0], "size_m": [1, 1, 1], "score": 0.5, "colour": 1}]}', CANDIDATES)


def study_seeds():
    """Plans and designs as docs/study.md gives them, for fuzz_study_file, and values their
    readers refuse."""
    os.makedirs(STUDY, exist_ok=True)
    write("plan.json", b'{"trials": [{"scene": "../assets/demo/scene.json", "time_limit_s": 120, "name": "village"},\n'
          b'            {"cloud": "clouds/hilly.pcd", "candidates": "clouds/hilly_candidates.json"}],\n'
          b' "shuffle_seed": 1,\n "hit_radius_m": 1.0,\n "orbit": {"radius_m": 60, "height_m": 40, "period_s": 60},\n'
          b' "generate": {"xres": 128, "yres": 128, "views": 100, "ground": "smrf"}, "comment": "x"}\n', STUDY)
    write("plan_minimal.json", b'{"trials": [{"cloud": "a.laz", "time_limit_s": 0, "name": "a\\nb"}]}', STUDY)
    write("plan_errors.json", b'{"trials": [{"cloud": "a.pcd", "scene": "s.json", "time_limit_s": -1}],'
          b' "shuffle_seed": -2, "generate": {"ground": "lidar", "xres": 0.5}}', STUDY)
    write("design.json", b'{"conditions": [{"name": "edl", "colour": "height", "eye_dome": true, "candidates": true},\n'
          b'                {"name": "plain", "colour": "file", "eye_dome": false, "candidates": false,\n'
          b'                 "time_limit_s": 90, "start": "free", "tools": ["zoom", "cut"], "cut": true,'
          b' "cut_radius_m": 10}],\n'
          b' "practice": [{"cloud": "clouds/practice.pcd"}],\n'
          b' "blocks": [{"name": "easy", "trials": [{"cloud": "clouds/a.pcd", "candidates": "clouds/a_c.json"}]},\n'
          b'            {"name": "hard", "trials": [{"scene": "scenes/b.json"}]}],\n'
          b' "break_s": 60,\n "order": "latin",\n "participants": ["P01", "P02", "P03", "P04"],\n'
          b' "orbit": {"radius_m": 60, "height_m": 40, "period_s": 60}}\n', STUDY)
    write("design_questionnaires.json", b'{"conditions": [{"name": "a", "detector": "baseline"}, {"name": "b",'
          b' "detector": "model.ldm"}, {"name": "c", "colour": "above-ground"}],'
          b' "blocks": [{"trials": [{"cloud": "x.laz"}]}, {"name": "picked", "corpus": "corpus", "select": "metric<0.3",'
          b' "count": 3, "seed": 2, "time_limit_s": 60}], "order": "random", "seed": 7,'
          b' "participants": ["P1", "P2", "P3"], "questionnaires": {"ssq": true, "tlx": true,'
          b' "likert": [{"id": "confident", "statement": "I was confident.", "points": 5, "when": "after_condition"}],'
          b' "text": [{"id": "remarks", "question": "Anything else?", "when": "post"}]}}', STUDY)
    write("design_corpus_only.json", b'{"conditions": [{"name": "a"}, {"name": "b"}], "order": "permutation",'
          b' "blocks": [{"corpus": "c", "select": "metric>0.2", "count": 2}], "break_s": 30,'
          b' "participants": ["P1", "P2"]}', STUDY)
    write("design_errors.json", b'{"conditions": [{"name": "-a"}, {"name": "a", "colour": "hue", "tools": ["pen"]}],'
          b' "blocks": [], "order": "random", "participants": ["P1", "P1"]}', STUDY)


def study_report_seeds():
    """A design session's trials.csv (first byte 0) and questionnaires.csv (first byte 1)
    as `ladarvr study` writes them, for fuzz_study_report, and rows its reader refuses."""
    os.makedirs(REPORT, exist_ok=True)
    base = (b"trial,cloud,decision,designated_x,designated_y,designated_z,target_distance_m,hit,"
            b"time_to_first_designation_s,time_to_decision_s,designations,mode_switches,seconds_in_free_mode,"
            b"visibility_metric,participant,condition,block,practice")
    judged = base + b",name,candidates_shown,designation_hit,box_hit"
    write("trials_judged.csv", b"\0" + judged + b"\n"
          b"1,practice.pcd,confirm,1.000000,2.000000,0.500000,0.200000,1,1.500000,2.500000,1,0,0.000000,,P01,a,,1,"
          b"practice,0,,\n"
          b"2,\"clouds/a,b.pcd\",no_target,,,,,,,4.000000,0,2,1.250000,0.400000,P01,a,easy,0,\"a \"\"b\"\"\",3,0,1\n"
          b"3,scenes/b.json,timeout,,,,7.100000,0,,120.000000,0,0,0.000000,0.910000,P01,b,hard,0,b,1,0,0\r\n",
          REPORT)
    write("trials_base.csv", b"\0" + base + b"\n1,demo.pcd,quit,,,,,,,0.5,0,0,0,,P01,a,first,0", REPORT)
    write("trials_errors.csv", b"\0" + base + b"\n1,demo.pcd,maybe,1,2,,x,2,,-1,0,0,0,1.5,P01,a,,0\n", REPORT)
    write("trials_csv_errors.csv", b"\0" + base + b"\n1,a\"b,\"c\"d\n\n\"unclosed\n", REPORT)
    ssq = [b"general_discomfort", b"fatigue", b"headache", b"eyestrain", b"difficulty_focusing",
           b"salivation_increasing", b"sweating", b"nausea", b"difficulty_concentrating", b"fullness_of_head",
           b"blurred_vision", b"dizziness_eyes_open", b"dizziness_eyes_closed", b"vertigo", b"stomach_awareness",
           b"burping"]
    tlx = [b"mental", b"physical", b"temporal", b"performance", b"effort", b"frustration"]
    rows = b"participant,condition,instrument,occasion,item,response,time_s\n"
    for i, item in enumerate(ssq):
        rows += b"P1,,ssq,pre," + item + b"," + str(i % 4).encode() + b",1.5\n"
    for i, item in enumerate(tlx):
        rows += b"P1,a,tlx,after_condition," + item + b"," + str(5 * i).encode() + b",60\n"
    rows += b"P1,a,likert,after_condition,liked,4,61\nP1,,likert,pre,ready,7,2\nP1,b,likert,post,overall,11,90\n"
    rows += b"P1,b,text,post,remarks,\"fine, \"\"thanks\"\"\",91\n"
    for i, item in enumerate(ssq):
        rows += b"P1,b,ssq,post," + item + b",3,92\n"
    write("questionnaires.csv", b"\1" + rows, REPORT)
    write("questionnaires_errors.csv", b"\1participant,condition,instrument,occasion,item,response,time_s\n"
          b"P1,c,tlx,after_condition,mental,52,1\nP2,,ssq,pre,itching,4,1e300\n", REPORT)


if __name__ == "__main__":
    main()
    replay_seeds()
    crs_seeds()
    candidates_seeds()
    study_seeds()
    study_report_seeds()
