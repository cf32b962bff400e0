#!/bin/sh
# tests/app/cmd_ground_dtm_test.sh: `ladarvr ground --dtm`, the terrain the points were
# classified against as an ESRI ASCII grid, read back with numpy and laspy.
# Usage: cmd_ground_dtm_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR (tests/data)
#  - one run: the grid is the run's raster (--json's size), it covers every point, and
#    each point's height above it, interpolated as the filter does, is the
#    HeightAboveGround the output carries; its CRS is beside it in a .prj (the cloud's
#    WKT record; GeoTIFF keys as WKT; none for an input without a CRS);
#  - a run in tiles gives the grid of the same cells, nearly every cell as one run's;
#  - a survey in feet gets its grid in feet (cells of 1 m given as 3.28 ft);
#  - a folder of tiles (--out-dir) gets a grid per input with --dtm-dir, each the merged
#    run's over the input's bounds;
#  - --dtm with --out-dir, over inputs far apart, or a name not ending in .asc or .tif, or a
#    folder or a link in its place: one
#    line naming --dtm, and neither the cloud nor the grid written; on a full disk the
#    same, the grid being written before the cloud lands.
set -eu
bin=$1
dir=$2
data=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# One run on an ISPRS sample.
"$bin" ground "$data/isprs/samp24.las" --out "$dir/one.laz" --dtm "$dir/one.asc" --json >"$dir/json" 2>"$dir/err" ||
    fail "ground --dtm: $(cat "$dir/err")"
[ -s "$dir/err" ] && fail "ground --dtm printed on stderr: $(cat "$dir/err")"
python3 - "$dir/json" "$dir/one.asc" "$dir/one.laz" <<'PY' || fail "ground --dtm: the grid does not match the run"
import json, sys
import laspy, numpy as np
run = json.load(open(sys.argv[1]))
head = {}
with open(sys.argv[2]) as f:
    for _ in range(6):
        key, value = f.readline().split()
        head[key] = float(value)
z = np.loadtxt(sys.argv[2], skiprows=6, ndmin=2)[::-1]  # row 0 the southernmost
nx, ny, cell = int(head["ncols"]), int(head["nrows"]), head["cellsize"]
assert z.shape == (ny, nx), (z.shape, nx, ny)
assert (nx, ny) == (run["raster"]["nx"], run["raster"]["ny"]), (nx, ny, run["raster"])
assert run["dtm"]["columns"] == nx and run["dtm"]["rows"] == ny and run["dtm"]["cell_m"] == cell, run["dtm"]
assert not (z == -9999).any()
las = laspy.read(sys.argv[3])
x, y, h = np.asarray(las.x), np.asarray(las.y), np.asarray(las.HeightAboveGround)
x0, y0 = head["xllcorner"], head["yllcorner"]
assert x.min() >= x0 - cell and x.max() <= x0 + (nx + 1) * cell, "the points lie beyond the grid in x"
assert y.min() >= y0 - cell and y.max() <= y0 + (ny + 1) * cell, "the points lie beyond the grid in y"
# Bilinear between cell centres, clamped at the edges (TerrainGrid::heightAt).
fx = np.clip((x - x0) / cell - 0.5, 0, nx - 1)
fy = np.clip((y - y0) / cell - 0.5, 0, ny - 1)
i0 = np.minimum(fx.astype(int), max(nx - 2, 0))
j0 = np.minimum(fy.astype(int), max(ny - 2, 0))
i1, j1 = np.minimum(i0 + 1, nx - 1), np.minimum(j0 + 1, ny - 1)
tx, ty = fx - i0, fy - j0
terrain = (1 - ty) * ((1 - tx) * z[j0, i0] + tx * z[j0, i1]) + ty * ((1 - tx) * z[j1, i0] + tx * z[j1, i1])
off = np.abs(np.asarray(las.z) - h - terrain)
assert off.max() < 0.003, "height above the grid differs from HeightAboveGround by %.4f m" % off.max()
print("one run: %d x %d cells, %d points within %.4f m of their height above the grid" % (nx, ny, len(x), off.max()))
PY

# Its CRS beside it: the sample's WKT record (UTM 32N), as the cloud written holds it.
[ -s "$dir/one.prj" ] || fail "ground --dtm: no .prj beside the grid"
python3 - "$dir/one.prj" "$dir/one.laz" <<'PY' || fail "ground --dtm: the .prj is not the cloud's CRS"
import sys
import laspy
prj = open(sys.argv[1]).read()
assert 'UTM zone 32N' in prj and '32632' in prj, prj[:200]
las = laspy.read(sys.argv[2])
record = [v for v in las.header.vlrs if v.record_id == 2112]
assert record and record[0].string.rstrip('\0') == prj, "the .prj is not the cloud's WKT record"
PY

# In tiles (150 m): the same cells, nearly every one as one run's.
"$bin" ground "$data/isprs/samp53.laz" --out "$dir/whole.laz" --dtm "$dir/whole.asc" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm samp53: $(cat "$dir/err")"
grep -q "^ground: wrote $dir/whole.asc: the terrain, [0-9]* x [0-9]* cells of 1 m, no CRS (the input has none)$" "$dir/out" ||
    fail "ground --dtm: no line for the grid: $(cat "$dir/out")"
"$bin" ground "$data/isprs/samp53.laz" --out "$dir/tiles.laz" --dtm "$dir/tiles.asc" --tile-m 150 >"$dir/out" \
    2>"$dir/err" || fail "ground --dtm --tile-m: $(cat "$dir/err")"
grep -q " tiles, largest raster " "$dir/out" || fail "ground --tile-m 150 did not run in tiles: $(cat "$dir/out")"
python3 - "$dir/whole.asc" "$dir/tiles.asc" <<'PY' || fail "ground --dtm: the tiles' grid differs from one run's"
import sys
import numpy as np
heads = [open(p).readlines()[:6] for p in sys.argv[1:]]
assert heads[0] == heads[1], heads
a, b = (np.loadtxt(p, skiprows=6) for p in sys.argv[1:])
assert not (b == -9999).any()
near = np.abs(a - b) <= 0.01
print("tiles: %.4f of %d cells within 1 cm of one run's" % (near.mean(), a.size))
assert near.mean() >= 0.999
PY

# In feet: 1 m cells are 3.28 ft; the heights are the file's, in feet.
"$bin" ground "$data/real/4_6_crop.las" --out "$dir/feet.laz" --dtm "$dir/feet.asc" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm feet: $(cat "$dir/err")"
python3 - "$dir/feet.asc" "$dir/feet.laz" <<'PY' || fail "ground --dtm feet: the grid is not in feet"
import sys
import laspy, numpy as np
cell = float(open(sys.argv[1]).readlines()[4].split()[1])
assert abs(cell - 1 / 0.3048006096) < 1e-5, cell
z = np.loadtxt(sys.argv[1], skiprows=6)
las = laspy.read(sys.argv[2])
ground = np.asarray(las.z)[np.asarray(las.classification) == 2]
assert abs(np.median(z) - np.median(ground)) < 10, (np.median(z), np.median(ground))
PY

# A survey in feet whose CRS is GeoTIFF keys gets them as WKT; one without a CRS no .prj,
# and the run's line says so.
grep -q "US survey foot" "$dir/feet.prj" || fail "ground --dtm feet: the .prj does not say feet: $(head -c 300 "$dir/feet.prj")"
"$bin" ground "$data/real/sample_c.las" --out "$dir/nocrs.laz" --dtm "$dir/nocrs.asc" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm sample_c: $(cat "$dir/err")"
[ ! -e "$dir/nocrs.prj" ] || fail "ground --dtm wrote a .prj for an input without a CRS"
grep -q "^ground: wrote $dir/nocrs.asc: the terrain, .*, no CRS (the input has none)$" "$dir/out" ||
    fail "ground --dtm sample_c: $(cat "$dir/out")"

# A folder of tiles (--out-dir): --dtm-dir writes each input's grid over its own bounds,
# under its name; each is the merged run's grid where they overlap, and each point's
# height above it is the HeightAboveGround of its output away from the grid's edges.
"$bin" ground "$data/isprs/samp41.laz" "$data/isprs/samp42.laz" --out "$dir/merged.laz" --dtm "$dir/merged.asc" \
    >"$dir/out" 2>"$dir/err" || fail "ground --dtm merged: $(cat "$dir/err")"
"$bin" ground "$data/isprs/samp41.laz" "$data/isprs/samp42.laz" --out-dir "$dir/each" --dtm-dir "$dir/grids" \
    >"$dir/out" 2>"$dir/err" || fail "ground --dtm-dir: $(cat "$dir/err")"
[ "$(grep -c "^ground: wrote $dir/grids/samp4[12].asc: the terrain, " "$dir/out")" = 2 ] ||
    fail "ground --dtm-dir: not one line per grid: $(cat "$dir/out")"
python3 - "$dir/merged.asc" "$dir/grids" "$dir/each" <<'PY' || fail "ground --dtm-dir: a grid differs from the merged run's"
import sys
import laspy, numpy as np
def grid(path):
    head = dict(line.split() for line in open(path).readlines()[:6])
    z = np.loadtxt(path, skiprows=6, ndmin=2)[::-1]
    return float(head["xllcorner"]), float(head["yllcorner"]), float(head["cellsize"]), z
mx, my, cell, mz = grid(sys.argv[1])
for name in ("samp41", "samp42"):
    x0, y0, c, z = grid("%s/%s.asc" % (sys.argv[2], name))
    assert c == cell and not (z == -9999).any()
    i, j = int(round((x0 - mx) / cell)), int(round((y0 - my) / cell))
    ny, nx = z.shape
    assert i >= 0 and j >= 0 and j + ny <= mz.shape[0] and i + nx <= mz.shape[1], (name, i, j, z.shape, mz.shape)
    near = np.abs(z - mz[j:j + ny, i:i + nx]) <= 0.01
    las = laspy.read("%s/%s.laz" % (sys.argv[3], name))
    names = list(las.point_format.dimension_names)
    h = np.asarray(las["HeightAboveGround" if "HeightAboveGround" in names else "height_above_ground_m"])
    x, y = np.asarray(las.x), np.asarray(las.y)
    # The cells whose centres lie in the input's bounds (its header's), no more.
    lo, hi = las.header.mins, las.header.maxs
    for first, count, a, b in ((x0 + c / 2, nx, lo[0], hi[0]), (y0 + c / 2, ny, lo[1], hi[1])):
        last = first + (count - 1) * c
        assert a <= first < a + c and b - c < last <= b + 1e-6, (name, first, last, a, b)
    fx, fy = (x - x0) / c - 0.5, (y - y0) / c - 0.5
    inside = (fx >= 1) & (fx <= nx - 2) & (fy >= 1) & (fy <= ny - 2)
    fx, fy, x, y, h = fx[inside], fy[inside], x[inside], y[inside], h[inside]
    i0, j0 = fx.astype(int), fy.astype(int)
    tx, ty = fx - i0, fy - j0
    t = (1 - ty) * ((1 - tx) * z[j0, i0] + tx * z[j0, i0 + 1]) + ty * ((1 - tx) * z[j0 + 1, i0] + tx * z[j0 + 1, i0 + 1])
    off = np.abs(np.asarray(las.z)[inside] - h - t)
    print("%s: %d x %d cells, %.4f within 1 cm of the merged grid; %d points within %.4f m" %
          (name, nx, ny, near.mean(), inside.sum(), off.max()))
    assert near.mean() >= 0.999 and off.max() < 0.003
PY

# Refusals: one line naming --dtm, nothing written.
bad() {
    want=$1
    shift
    rm -rf "$dir/bad.laz" "$dir/bad.asc" "$dir/outs"
    if "$bin" ground "$@" >"$dir/out" 2>"$dir/err"; then fail "ground $* succeeded"; fi
    [ "$(wc -l <"$dir/err")" = 1 ] || fail "ground $*: not one line: $(cat "$dir/err")"
    grep -qF -e "$want" "$dir/err" || fail "ground $*: no '$want' in: $(cat "$dir/err")"
    [ -e "$dir/bad.laz" ] && fail "ground $* left $dir/bad.laz"
    [ -e "$dir/outs" ] && fail "ground $* made $dir/outs"
    return 0
}
bad "ground: --dtm: allowed with --out (one DTM of every input); with --out-dir, --dtm-dir DIR writes one per input" \
    "$data/isprs/samp24.las" --out-dir "$dir/outs" --dtm "$dir/bad.asc"
bad "ground: --dtm $dir/bad.grd: allowed a name ending in .asc" \
    "$data/isprs/samp24.las" --out "$dir/bad.laz" --dtm "$dir/bad.grd"
bad "ground: --dtm: the inputs lie far apart" \
    "$data/isprs/samp11.laz" "$data/isprs/samp71.laz" --out "$dir/bad.laz" --dtm "$dir/bad.asc"
mkdir -p "$dir/folder.asc"
bad "folder.asc" "$data/isprs/samp24.las" --out "$dir/bad.laz" --dtm "$dir/folder.asc"
[ -d "$dir/folder.asc" ] || fail "the folder in --dtm's place is gone"
# A symbolic link where the grid's CRS would go: refused before any work, the link kept.
: >"$dir/target"
ln -s target "$dir/linked.prj"
bad "linked.prj: is a symbolic link" "$data/isprs/samp24.las" --out "$dir/bad.laz" --dtm "$dir/linked.asc"
[ -L "$dir/linked.prj" ] && [ ! -s "$dir/target" ] && [ ! -e "$dir/linked.asc" ] ||
    fail "ground --dtm wrote through the .prj's link, or wrote the grid"

# A full disk under --dtm: the grid is written before the cloud lands, so the run stops
# with one line and neither lands, and no temporary is left in either folder.
mkdir -p "$dir/full"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=16k tmpfs "$dir/full" 2>/dev/null; then
    status=0
    "$bin" ground "$data/isprs/samp24.las" --out "$dir/full.laz" --dtm "$dir/full/dtm.asc" >"$dir/out" 2>"$dir/err" ||
        status=$?
    listed=$(ls -A "$dir/full")
    umount "$dir/full"
    [ "$status" -eq 1 ] || fail "ground --dtm on a full disk: exit $status"
    [ "$(wc -l <"$dir/err")" = 1 ] && grep -q "No space left on device" "$dir/err" ||
        fail "ground --dtm on a full disk: $(cat "$dir/err")"
    [ ! -e "$dir/full.laz" ] || fail "the cloud landed although --dtm could not be written"
    [ -z "$listed" ] || fail "a full disk under --dtm left: $listed"
    leftover=$(find "$dir" -maxdepth 1 -name '.*' ! -name '.' | head -1)
    [ -z "$leftover" ] || fail "a temporary was left: $leftover"
    # Room for the heights' scratch (4 bytes a cell) but not for the grid (6 bytes a cell
    # at least): refused before the grid is written, nothing left either.
    mount -t tmpfs -o size=48k tmpfs "$dir/full"
    status=0
    "$bin" ground "$data/isprs/samp24.las" --out "$dir/full.laz" --dtm "$dir/full/dtm.asc" >"$dir/out" 2>"$dir/err" ||
        status=$?
    listed=$(ls -A "$dir/full")
    umount "$dir/full"
    [ "$status" -eq 1 ] && grep -q "MiB free, but the grid may need" "$dir/err" ||
        fail "ground --dtm with no room for the grid: exit $status: $(cat "$dir/err")"
    [ ! -e "$dir/full.laz" ] && [ -z "$listed" ] || fail "ground --dtm with no room for the grid left files"
else
    echo "cmd_ground_dtm: mounting a tmpfs needs root: the full-disk case is skipped"
fi
echo "cmd_ground_dtm: ok"
