#!/bin/sh
# tests/app/cmd_ground_tiles_test.sh: `ladarvr ground` on several inputs and in tiles, as a
# user runs it, on real ISPRS reference samples (tests/data/isprs).
# Usage: cmd_ground_tiles_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR
#  - a small forced --tile-m gives every point the class of the untiled run, and --jobs 2
#    writes the bytes of --jobs 1;
#  - two inputs merged into --out and written one per input into --out-dir: the same
#    ground counts; --only-tile writes the one file --out-dir writes for that input, byte
#    for byte, and --jobs 2 the bytes of --jobs 1;
#  - a sample cut into a folder of 3 x 3 tile files, written one per input with
#    --jobs 2: every point gets the class of the untiled run;
#  - PCD and PLY inputs on each of those paths get the classes the LAS inputs get;
#  - a folder as the input: its tiles, the bytes --out-dir writes for them given one by one;
#  - --out-dir refuses two inputs of one name and an output that would replace an input,
#    in one line, writing nothing; --out with inputs of other point formats is refused;
#  - a survey 5 km wide, once refused (its raster over 16.8 M cells), runs in tiles;
#  - --whiten writes RGB (white ground).
set -eu
bin=$1
dir=$2
data=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
field() { sed -n "s/^ *\"$1\": \([0-9.]*\),*$/\1/p" "$2" | head -1; }
# ground_count FILE: its class 2 points (`info --json`).
ground_count() {
    "$bin" info --json "$1" >"$dir/info" 2>"$dir/err" || fail "info $1: $(cat "$dir/err")"
    tr -d ' \n' <"$dir/info" | sed -n 's/.*{"class":2,"name":"ground","points":\([0-9]*\)}.*/\1/p'
}

# same_ground A B: every point of A is ground exactly where it is in B (LAS/LAZ class 2,
# PCD/PLY label 0), in the same order.
same_ground() {
    python3 - "$1" "$2" <<'PY' || fail "$1 and $2 differ in their ground"
import sys
import laspy, numpy as np

def ground(path):
    if path.endswith((".las", ".laz")):
        return np.asarray(laspy.read(path).classification) == 2
    with open(path, "rb") as f:
        data = f.read()
    types = {"float": "<f4", "double": "<f8", "uchar": "u1", "char": "i1", "ushort": "<u2", "short": "<i2",
             "uint": "<u4", "int": "<i4"}
    names, dtype = [], []
    if path.endswith(".ply"):
        end = data.index(b"end_header\n") + len(b"end_header\n")
        for line in data[:end].decode().splitlines():
            w = line.split()
            if w[:1] == ["property"]:
                names.append(w[2])
                dtype.append(types[w[1]])
        label = "scalar_label"
    else:
        end = data.index(b"DATA binary\n") + len(b"DATA binary\n")
        head = {l.split()[0]: l.split()[1:] for l in data[:end].decode().splitlines() if l and l[0] != "#"}
        names = head["FIELDS"]
        dtype = [{"F": "<f", "U": "<u", "I": "<i"}[t] + s for t, s in zip(head["TYPE"], head["SIZE"])]
        label = "label"
    points = np.frombuffer(data[end:], dtype=np.dtype(list(zip(names, dtype))))
    return points[label] == 0

a, b = ground(sys.argv[1]), ground(sys.argv[2])
sys.exit(0 if len(a) == len(b) and len(a) > 0 and (a == b).all() and a.any() else 1)
PY
}
# Tiles of 50 m over samp11 (about 300 m wide): the untiled run's class for every point.
"$bin" ground "$data/samp11.laz" --out "$dir/one.laz" --json >"$dir/one.json" 2>"$dir/err" ||
    fail "untiled: $(cat "$dir/err")"
"$bin" ground "$data/samp11.laz" --out "$dir/tiled1.laz" --tile-m 50 --json >"$dir/tiled.json" 2>"$dir/err" ||
    fail "tiled: $(cat "$dir/err")"
[ "$(field tiles "$dir/tiled.json")" -gt 10 ] || fail "not tiled: $(cat "$dir/tiled.json")"
[ -z "$(field tiles "$dir/one.json")" ] || fail "the untiled run says tiles: $(cat "$dir/one.json")"
same_ground "$dir/tiled1.laz" "$dir/one.laz"
"$bin" ground "$data/samp11.laz" --out "$dir/tiled2.laz" --tile-m 50 --jobs 2 >/dev/null 2>"$dir/err" ||
    fail "tiled --jobs 2: $(cat "$dir/err")"
cmp -s "$dir/tiled1.laz" "$dir/tiled2.laz" || fail "--jobs 2 wrote other bytes than --jobs 1"

# Two inputs: merged into one output, and one output each.
cp "$data/samp54.laz" "$dir/a.laz"
cp "$data/samp24.laz" "$dir/b.laz"
"$bin" ground "$dir/a.laz" "$dir/b.laz" --out "$dir/merged.laz" --json >"$dir/merged.json" 2>"$dir/err" ||
    fail "merged: $(cat "$dir/err")"
"$bin" ground "$dir/a.laz" "$dir/b.laz" --out-dir "$dir/each" --json >"$dir/each.json" 2>"$dir/err" ||
    fail "--out-dir: $(cat "$dir/err")"
[ -f "$dir/each/a.laz" ] && [ -f "$dir/each/b.laz" ] || fail "--out-dir wrote: $(ls "$dir/each")"
merged=$(ground_count "$dir/merged.laz")
each=$(($(ground_count "$dir/each/a.laz") + $(ground_count "$dir/each/b.laz")))
[ "$merged" = "$each" ] || fail "merged ground $merged, one output each $each"
"$bin" ground "$dir/a.laz" "$dir/b.laz" --out-dir "$dir/jobs" --jobs 2 >/dev/null 2>"$dir/err" ||
    fail "--out-dir --jobs 2: $(cat "$dir/err")"
cmp -s "$dir/each/a.laz" "$dir/jobs/a.laz" && cmp -s "$dir/each/b.laz" "$dir/jobs/b.laz" ||
    fail "--out-dir --jobs 2 wrote other bytes than --jobs 1"
"$bin" ground "$dir/a.laz" "$dir/b.laz" --out-dir "$dir/only" --only-tile 1 >/dev/null 2>"$dir/err" ||
    fail "--only-tile: $(cat "$dir/err")"
[ ! -e "$dir/only/a.laz" ] || fail "--only-tile 1 wrote input 0's output"
cmp -s "$dir/each/b.laz" "$dir/only/b.laz" || fail "--only-tile 1 wrote other bytes than --out-dir"

# A folder of tile files: samp42 cut into 3 x 3 LAS files at its x and y terciles, each
# classified with the others as its buffer, two at a time. Every point gets the class of
# the untiled run (the station roofs, one raised-segment patch that a file's buffer cuts,
# need the file fitted again over the whole patch).
mkdir -p "$dir/folder"
python3 - "$data/samp42.laz" "$dir/folder" <<'PY' || fail "cutting samp42 into tile files"
import sys
import laspy, numpy as np
f = laspy.read(sys.argv[1])
x, y = np.asarray(f.x), np.asarray(f.y)
ix = np.digitize(x, np.quantile(x, [1 / 3, 2 / 3]))
iy = np.digitize(y, np.quantile(y, [1 / 3, 2 / 3]))
for i in range(3):
    for j in range(3):
        o = laspy.LasData(f.header)
        o.points = f.points[(ix == i) & (iy == j)]
        o.write(f"{sys.argv[2]}/t{i}{j}.las")
PY
"$bin" ground "$data/samp42.laz" --out "$dir/folder-one.las" >/dev/null 2>"$dir/err" ||
    fail "samp42 untiled: $(cat "$dir/err")"
"$bin" ground "$dir/folder"/t*.las --out-dir "$dir/folder-out" --jobs 2 >/dev/null 2>"$dir/err" ||
    fail "a folder of tile files: $(cat "$dir/err")"
python3 - "$dir/folder-one.las" "$dir/folder-out" <<'PY' ||
import collections, glob, sys
import laspy, numpy as np

def points(path):
    f = laspy.read(path)
    mm = lambda a: np.round(np.asarray(a) * 1000).astype(np.int64).tolist()
    return zip(mm(f.x), mm(f.y), mm(f.z), (np.asarray(f.classification) == 2).tolist())

one = collections.Counter(points(sys.argv[1]))
tiles = collections.Counter()
for path in glob.glob(sys.argv[2] + "/*.las"):
    tiles.update(points(path))
sys.exit(0 if sum(one.values()) > 40000 and one == tiles else 1)
PY
    fail "the folder of samp42's tile files and its untiled run differ in their ground"
# The folder itself as the input: its .las files in name order, the same bytes; a file
# of another kind in it is left out, and a folder without tiles is refused in one line.
printf 'not a cloud\n' >"$dir/folder/notes.txt"
"$bin" ground "$dir/folder" --out-dir "$dir/folder-given" --jobs 2 --json >"$dir/folder.json" 2>"$dir/err" ||
    fail "a folder as the input: $(cat "$dir/err")"
for t in "$dir/folder-out"/*.las; do
    cmp -s "$t" "$dir/folder-given/$(basename "$t")" || fail "the folder given wrote other bytes for $(basename "$t")"
done
[ "$(ls "$dir/folder-given" | wc -l)" = 9 ] || fail "the folder given wrote: $(ls "$dir/folder-given")"
python3 - "$dir/folder.json" "$dir/folder" <<'PY' || fail "the folder's inputs are not its tiles in name order"
import json, sys
runs = json.load(open(sys.argv[1]))
assert [r["in"] for r in runs] == ["%s/t%d%d.las" % (sys.argv[2], i, j) for i in range(3) for j in range(3)], runs
PY
mkdir -p "$dir/no-tiles"
cp "$dir/folder/notes.txt" "$dir/no-tiles/"

# PCD and PLY inputs through every path (one input, tiles with --jobs 2, two merged,
# --out-dir, --only-tile): each point gets the class the LAS inputs get it on the same
# path. The clouds are written by ground itself from the LAS samples, so they hold the
# LAS reader's points in its frame (their "ladarvr origin" comment).
for ext in pcd ply; do
    for name in a b; do
        "$bin" ground "$dir/$name.laz" --out "$dir/$name.$ext" >/dev/null 2>"$dir/err" ||
            fail "writing $name.$ext: $(cat "$dir/err")"
    done
done
run() { "$bin" ground "$@" >/dev/null 2>"$dir/err" || fail "ground $*: $(cat "$dir/err")"; }
run "$dir/a.laz" --out "$dir/one-las.las"
run "$dir/a.pcd" --out "$dir/one-pcd.pcd"
run "$dir/a.ply" --out "$dir/one-ply.ply"
same_ground "$dir/one-pcd.pcd" "$dir/one-las.las"
same_ground "$dir/one-ply.ply" "$dir/one-las.las"
run "$dir/a.laz" --out "$dir/tiled-las.las" --tile-m 40 --jobs 2
run "$dir/a.pcd" --out "$dir/tiled-pcd.pcd" --tile-m 40 --jobs 2
run "$dir/a.ply" --out "$dir/tiled-ply.ply" --tile-m 40 --jobs 2
same_ground "$dir/tiled-pcd.pcd" "$dir/tiled-las.las"
same_ground "$dir/tiled-ply.ply" "$dir/tiled-las.las"
run "$dir/a.pcd" "$dir/b.pcd" --out "$dir/merged-pcd.ply"
run "$dir/a.ply" "$dir/b.ply" --out "$dir/merged-ply.pcd"
same_ground "$dir/merged-pcd.ply" "$dir/merged.laz"
same_ground "$dir/merged-ply.pcd" "$dir/merged.laz"
for ext in pcd ply; do
    run "$dir/a.$ext" "$dir/b.$ext" --out-dir "$dir/each-$ext" --jobs 2
    run "$dir/a.$ext" "$dir/b.$ext" --out-dir "$dir/only-$ext" --only-tile 1
    for name in a b; do same_ground "$dir/each-$ext/$name.$ext" "$dir/each/$name.laz"; done
    same_ground "$dir/only-$ext/b.$ext" "$dir/each/b.laz"
done

# Refusals: one line, nothing written.
bad() {
    want=$1
    shift
    if "$bin" ground "$@" >"$dir/out" 2>"$dir/err"; then fail "ground $* succeeded"; fi
    [ "$(wc -l <"$dir/err")" = 1 ] || fail "ground $*: not one line: $(cat "$dir/err")"
    grep -qF -e "$want" "$dir/err" || fail "ground $*: no '$want' in: $(cat "$dir/err")"
    return 0
}
mkdir -p "$dir/twin"
cp "$data/samp24.laz" "$dir/twin/a.laz"
bad "two inputs are named 'a.laz'; allowed inputs of distinct names" "$dir/a.laz" "$dir/twin/a.laz" --out-dir "$dir/bad"
[ ! -e "$dir/bad" ] || fail "a refused --out-dir left $dir/bad"
before=$(cksum <"$dir/a.laz")
bad "allowed" "$dir/a.laz" "$dir/b.laz" --out-dir "$dir"
[ "$(cksum <"$dir/a.laz")" = "$before" ] || fail "--out-dir replaced its input"
bad "--only-tile 2: allowed [0, 1]" "$dir/a.laz" "$dir/b.laz" --out-dir "$dir/bad" --only-tile 2
bad "--only-tile" "$dir/a.laz" --out "$dir/bad.laz" --only-tile 0
bad "have different point formats" "$dir/a.laz" "$dir/merged.laz" --out "$dir/bad.laz"
[ ! -e "$dir/bad.laz" ] || fail "a refused merge left $dir/bad.laz"
bad "--jobs 0: allowed [1, 256]" "$dir/a.laz" --out "$dir/bad.laz" --jobs 0
bad "ground: input '$dir/no-tiles' is a folder that holds no .las or .laz file; allowed: cloud files, or folders of LAS/LAZ tiles" \
    "$dir/no-tiles" --out-dir "$dir/bad"
[ ! -e "$dir/bad" ] || fail "a refused folder left $dir/bad"

# A survey 5 km wide: two patches of samp54 5 km apart (a PLY written here); one raster of
# 1 m cells over it is 25 M cells, more than the filter's 16.8 M, so it runs in tiles.
python3 - "$dir/wide.ply" <<'PY'
import random, sys
random.seed(1)
pts = []
for at in (0.0, 5000.0):
    for j in range(80):
        for i in range(80):
            box = 30 <= i < 50 and 30 <= j < 50
            pts.append((at + 0.5 * i + random.uniform(-0.2, 0.2), at + 0.5 * j + random.uniform(-0.2, 0.2),
                        5.0 if box else 0.0))
with open(sys.argv[1], "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n" % len(pts))
    for p in pts:
        f.write("%.3f %.3f %.3f\n" % p)
PY
"$bin" ground "$dir/wide.ply" --out "$dir/wide-out.ply" --json >"$dir/wide.json" 2>"$dir/err" ||
    fail "the 5 km survey: $(cat "$dir/err")"
[ "$(field tiles "$dir/wide.json")" -ge 2 ] || fail "the 5 km survey: $(cat "$dir/wide.json")"
[ "$(field ground_points "$dir/wide.json")" = 12000 ] || fail "the 5 km survey's ground: $(cat "$dir/wide.json")"

# --whiten: RGB written, the ground white.
"$bin" ground "$data/samp54.laz" --out "$dir/white.las" --whiten >/dev/null 2>"$dir/err" || fail "--whiten: $(cat "$dir/err")"
"$bin" info --json "$dir/white.las" >"$dir/info" 2>"$dir/err" || fail "info: $(cat "$dir/err")"
tr -d ' \n' <"$dir/info" | grep -q '"Red"' || fail "--whiten wrote no colours: $(cat "$dir/info")"
echo "cmd_ground_tiles: ok"
