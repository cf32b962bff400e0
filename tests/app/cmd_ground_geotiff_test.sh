#!/bin/sh
# tests/app/cmd_ground_geotiff_test.sh: the DTM as a GeoTIFF (`ground --dtm X.tif`,
# `--dtm-dir` with `--dtm-format tif`, `generate --dtm X.tif`), read by geotiff.js (an
# independent reader, from npm) against the ESRI ASCII grid of the same run.
# Usage: cmd_ground_geotiff_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR (tests/data) NPM_DIR
#  - a survey in UTM (EPSG:32642, WKT and GeoTIFF keys): the same size, corner, cells and
#    heights (to the ASCII grid's millimetre) as the .asc, float 32 compressed with
#    Deflate and the floating-point predictor, nodata -9999, the keys projected, pixel
#    is area, EPSG:32642 in metres; no .prj beside it; the run's line and --json name
#    the code;
#  - a survey in US survey feet whose CRS is GeoTIFF keys (EPSG:2903): that code, units
#    9003, cells of 3.28 ft;
#  - one without a CRS: placed, no keys, and the run's line says so;
#  - two inputs merged over a gap, in tiles: the cells no tile held are nodata in both
#    grids alike;
#  - a folder of tiles with --dtm-dir and --dtm-format tif: one GeoTIFF per input, each
#    with its input's CRS;
#  - scripts/dtm_hillshade.py draws a GeoTIFF as it draws the .asc;
#  - generate --dtm X.tif: the generator's terrain as its .asc, no keys;
#  - --dtm-tiff bigtiff: a BigTIFF (its header's 43, the strips' 64-bit offsets) with the
#    same cells as the .asc, said by the run's line and --json, drawn by dtm_hillshade.py;
#    classic TIFF otherwise; --dtm-dir's grids too; --dtm-tiff without a GeoTIFF grid refused;
#  - a name not .asc, .tif or .tiff: one line naming --dtm, nothing written.
set -eu
bin=$1
dir=$2
data=$3
npm=$4
here=$(dirname "$0")
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
read_tif() { timeout 120 node "$here/geotiff_read.mjs" "$npm/node_modules" "$@"; }

# check JSON EXPECT_PYTHON: the geotiff.js JSON against expectations (a Python expression
# over `t`, the JSON, that must hold).
check() {
    python3 -c "
import json, sys
t = json.loads(sys.argv[1])
assert $2, t
" "$1" || fail "$3: $1"
}

# UTM, metres.
"$bin" ground "$data/real/hexbin-crop.las" --out "$dir/utm.laz" --dtm "$dir/utm.tif" --json >"$dir/json" \
    2>"$dir/err" || fail "ground --dtm utm.tif: $(cat "$dir/err")"
[ ! -e "$dir/utm.prj" ] || fail "a .prj was written beside the GeoTIFF"
"$bin" ground "$data/real/hexbin-crop.las" --out "$dir/utm2.laz" --dtm "$dir/utm.asc" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm utm.asc: $(cat "$dir/err")"
t=$(read_tif "$dir/utm.tif" "$dir/utm.asc") || fail "geotiff.js cannot read utm.tif"
echo "utm: $t"
check "$t" "t['width'] == t['asc']['columns'] and t['height'] == t['asc']['rows']" "the size differs from the .asc"
check "$t" "abs(t['origin'][0] - t['asc']['west']) < 1e-6 and abs(t['origin'][1] - t['asc']['north']) < 1e-6" \
    "the corner differs from the .asc"
check "$t" "t['resolution'][:2] == [t['asc']['cell'], -t['asc']['cell']]" "the cell differs from the .asc"
check "$t" "t['bands'] == 1 and t['bits'] == 32 and t['sample_format'] == 3 and t['array'] == 'Float32Array'" \
    "not one band of float 32"
check "$t" "t['compression'] == 8 and t['predictor'] == 3 and t['strips'] == -(-203 // (65536 // (4 * 295)))" \
    "not Deflate with the floating-point predictor in strips of up to 64 KiB"
check "$t" "t['nodata'] == -9999 and t['asc']['nodata_mismatch'] == 0 and t['asc']['heights'] == t['asc']['cells']" \
    "nodata where the .asc has heights"
check "$t" "t['asc']['largest_difference'] <= 0.0006" "a height differs from the .asc by more than its rounding"
check "$t" "t['geokeys'] == {'GTModelTypeGeoKey': 1, 'GTRasterTypeGeoKey': 1, 'ProjectedCSTypeGeoKey': 32642, 'ProjLinearUnitsGeoKey': 9001}" \
    "the keys are not EPSG:32642 in metres"
check "$t" "t['bigtiff'] is False" "a grid this small is not a classic TIFF"
python3 - "$dir/json" "$dir/utm.tif" <<'PY' || fail "ground --json does not name the GeoTIFF and its code: $(cat "$dir/json")"
import json, os, sys
j = json.load(open(sys.argv[1]))["dtm"]
assert j["path"] == os.path.abspath(sys.argv[2]) and j["crs"] == "EPSG:32642" and j["tiff"] == "classic", j
PY

# The same grid as a BigTIFF: the same cells, keys and strips.
"$bin" ground "$data/real/hexbin-crop.las" --out "$dir/big.laz" --dtm "$dir/big.tif" --dtm-tiff bigtiff --json \
    >"$dir/json" 2>"$dir/err" || fail "ground --dtm-tiff bigtiff: $(cat "$dir/err")"
t=$(read_tif "$dir/big.tif" "$dir/utm.asc") || fail "geotiff.js cannot read big.tif"
echo "bigtiff: $t"
check "$t" "t['bigtiff'] is True" "--dtm-tiff bigtiff did not write a BigTIFF"
check "$t" "t['width'] == 295 and t['height'] == 203 and t['asc']['nodata_mismatch'] == 0 and t['asc']['largest_difference'] <= 0.0006" \
    "the BigTIFF's cells differ from the .asc"
check "$t" "t['geokeys']['ProjectedCSTypeGeoKey'] == 32642 and t['compression'] == 8 and t['predictor'] == 3 and t['strips'] == 4" \
    "the BigTIFF's keys or strips differ from the classic file's"
python3 - "$dir/big.tif" "$dir/json" <<'PY' || fail "big.tif's header or --json: $(cat "$dir/json")"
import json, struct, sys
with open(sys.argv[1], "rb") as f:
    assert struct.unpack("<2sHHH", f.read(8)) == (b"II", 43, 8, 0)
assert json.load(open(sys.argv[2]))["dtm"]["tiff"] == "bigtiff"
PY
"$bin" ground "$data/real/hexbin-crop.las" --out "$dir/big2.laz" --dtm "$dir/big2.tif" --dtm-tiff bigtiff \
    >"$dir/out" 2>"$dir/err" || fail "ground --dtm-tiff bigtiff: $(cat "$dir/err")"
grep -q "^ground: wrote $dir/big2.tif: the terrain as a BigTIFF, 295 x 203 cells of 1 m, its CRS in its GeoTIFF keys (EPSG:32642)$" \
    "$dir/out" || fail "the line does not say BigTIFF: $(cat "$dir/out")"
timeout 120 python3 "$here/../../scripts/dtm_hillshade.py" "$dir/big.tif" --out "$dir/big.png" --width-px 300 \
    >"$dir/out" 2>"$dir/err" || fail "dtm_hillshade.py cannot draw the BigTIFF: $(cat "$dir/err")"
grep -q "(295 x 203 cells)" "$dir/out" || fail "dtm_hillshade.py: $(cat "$dir/out")"
"$bin" ground "$data/real/hexbin-crop.las" --out-dir "$dir/bigeach" --dtm-dir "$dir/biggrids" --dtm-format tif \
    --dtm-tiff bigtiff >"$dir/out" 2>"$dir/err" || fail "ground --dtm-dir --dtm-tiff bigtiff: $(cat "$dir/err")"
t=$(read_tif "$dir/biggrids/hexbin-crop.tif") || fail "geotiff.js cannot read biggrids/hexbin-crop.tif"
check "$t" "t['bigtiff'] is True and t['width'] > 200 and t['geokeys']['ProjectedCSTypeGeoKey'] == 32642" \
    "--dtm-dir's grid with --dtm-tiff bigtiff is not a BigTIFF of the input's cells"
status=0
"$bin" ground "$data/real/hexbin-crop.las" --out "$dir/big3.laz" --dtm "$dir/big3.asc" --dtm-tiff classic \
    >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 1 ] || fail "--dtm-tiff with an ASCII grid exited $status"
[ "$(cat "$dir/err")" = "ladarvr: error: ground: --dtm-tiff classic: allowed only with a GeoTIFF grid (--dtm NAME.tif, or --dtm-dir with --dtm-format tif)" ] ||
    fail "--dtm-tiff with an ASCII grid: $(cat "$dir/err")"
[ ! -e "$dir/big3.laz" ] && [ ! -e "$dir/big3.asc" ] || fail "--dtm-tiff with an ASCII grid wrote something"
"$bin" ground "$data/real/hexbin-crop.las" --out "$dir/utm3.laz" --dtm "$dir/utm3.TIFF" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm utm3.TIFF: $(cat "$dir/err")"
grep -q "^ground: wrote $dir/utm3.TIFF: the terrain, 295 x 203 cells of 1 m, its CRS in its GeoTIFF keys (EPSG:32642)$" \
    "$dir/out" || fail "no line for the GeoTIFF: $(cat "$dir/out")"

# US survey feet, the CRS from GeoTIFF keys.
"$bin" ground "$data/real/4_6_crop.las" --out "$dir/feet.laz" --dtm "$dir/feet.tif" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm feet.tif: $(cat "$dir/err")"
t=$(read_tif "$dir/feet.tif") || fail "geotiff.js cannot read feet.tif"
echo "feet: $t"
check "$t" "t['geokeys']['ProjectedCSTypeGeoKey'] == 2903 and t['geokeys']['ProjLinearUnitsGeoKey'] == 9003" \
    "the keys are not EPSG:2903 in US survey feet"
check "$t" "abs(t['resolution'][0] - 1 / 0.3048006096) < 1e-6" "the cells are not 1 m in feet"

# No CRS: placed, no keys.
"$bin" ground "$data/real/sample_c.las" --out "$dir/none.laz" --dtm "$dir/none.tif" >"$dir/out" 2>"$dir/err" ||
    fail "ground --dtm none.tif: $(cat "$dir/err")"
grep -q "^ground: wrote $dir/none.tif: the terrain, .*, no CRS (the input has none)$" "$dir/out" ||
    fail "the line does not say the GeoTIFF has no CRS: $(cat "$dir/out")"
t=$(read_tif "$dir/none.tif") || fail "geotiff.js cannot read none.tif"
check "$t" "t['geokeys'] is None and t['width'] > 0" "keys written for an input without a CRS"

# Two inputs merged, in tiles: the cells no tile held are nodata, as in the .asc.
"$bin" ground "$data/isprs/samp41.laz" "$data/isprs/samp42.laz" --out "$dir/m.laz" --dtm "$dir/m.tif" \
    --tile-m 120 >"$dir/out" 2>"$dir/err" || fail "ground --dtm m.tif: $(cat "$dir/err")"
"$bin" ground "$data/isprs/samp41.laz" "$data/isprs/samp42.laz" --out "$dir/m2.laz" --dtm "$dir/m.asc" \
    --tile-m 120 >"$dir/out" 2>"$dir/err" || fail "ground --dtm m.asc: $(cat "$dir/err")"
t=$(read_tif "$dir/m.tif" "$dir/m.asc") || fail "geotiff.js cannot read m.tif"
echo "merged: $(echo "$t" | python3 -c 'import json,sys; print(json.load(sys.stdin)["asc"])')"
check "$t" "t['asc']['nodata_mismatch'] == 0 and t['asc']['largest_difference'] <= 0.0006" \
    "the merged GeoTIFF differs from its .asc"
check "$t" "t['asc']['heights'] < t['asc']['cells']" "the merged grid has no cell without a tile (nothing tested)"

# scripts/dtm_hillshade.py draws the GeoTIFF as it draws the .asc (the same relief, the
# cells without a tile white in both).
for g in m.tif m.asc; do
    timeout 120 python3 "$here/../../scripts/dtm_hillshade.py" "$dir/$g" --out "$dir/$g.png" --width-px 400 \
        >/dev/null 2>"$dir/err" || fail "dtm_hillshade.py $g: $(cat "$dir/err")"
done
python3 - "$dir/m.tif.png" "$dir/m.asc.png" <<'PY' || fail "dtm_hillshade.py draws the GeoTIFF otherwise than the .asc"
import sys
import numpy as np
from PIL import Image
a, b = (np.asarray(Image.open(p).convert("RGB"), dtype=np.int16) for p in sys.argv[1:])
assert a.shape == b.shape, (a.shape, b.shape)
# Float 32 against millimetres moves the shading's slopes a little on a few pixels.
d = np.abs(a - b)
assert d.mean() < 0.05 and np.percentile(d, 99.9) <= 2, (d.mean(), np.percentile(d, 99.9))
assert (a == 255).all(axis=2).sum() > 100, "no white (no-tile) cells drawn"
PY

# A folder of tiles: one GeoTIFF per input, each with its input's CRS (samp24.las has
# UTM 32N, samp23.laz none).
"$bin" ground "$data/isprs/samp23.laz" "$data/isprs/samp24.las" --out-dir "$dir/each" --dtm-dir "$dir/grids" \
    --dtm-format tif >"$dir/out" 2>"$dir/err" || fail "ground --dtm-dir --dtm-format tif: $(cat "$dir/err")"
t=$(read_tif "$dir/grids/samp24.tif") || fail "geotiff.js cannot read samp24.tif"
check "$t" "t['geokeys']['ProjectedCSTypeGeoKey'] == 32632" "samp24.tif is not in UTM 32N"
t=$(read_tif "$dir/grids/samp23.tif") || fail "geotiff.js cannot read samp23.tif"
check "$t" "t['geokeys'] is None and t['width'] > 100" "samp23.tif has keys or no cells"
[ -z "$(ls "$dir/grids" | grep -v '\.tif$')" ] || fail "--dtm-dir wrote more than the GeoTIFFs: $(ls "$dir/grids")"

# The generator's terrain.
small="--xres 16 --yres 16 --views 2 --ground smrf"
"$bin" generate $small --format pcd --out "$dir/g.pcd" --dtm "$dir/g.tif" >"$dir/out" 2>"$dir/err" ||
    fail "generate --dtm g.tif: $(cat "$dir/err")"
"$bin" generate $small --format pcd --out "$dir/g2.pcd" --dtm "$dir/g.asc" >"$dir/out" 2>"$dir/err" ||
    fail "generate --dtm g.asc: $(cat "$dir/err")"
t=$(read_tif "$dir/g.tif" "$dir/g.asc") || fail "geotiff.js cannot read g.tif"
check "$t" "t['geokeys'] is None and t['asc']['nodata_mismatch'] == 0 and t['asc']['largest_difference'] <= 0.0006" \
    "generate's GeoTIFF differs from its .asc"
check "$t" "abs(t['origin'][0] - t['asc']['west']) < 1e-6 and abs(t['origin'][1] - t['asc']['north']) < 1e-6" \
    "generate's GeoTIFF corner differs from its .asc"

# A name of another kind: one line, nothing written.
status=0
"$bin" ground "$data/real/sample_c.las" --out "$dir/bad.laz" --dtm "$dir/bad.png" >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 1 ] || fail "ground --dtm bad.png exited $status"
[ "$(cat "$dir/err")" = "ladarvr: error: ground: --dtm $dir/bad.png: allowed a name ending in .asc (an ESRI ASCII grid) or .tif, .tiff (a GeoTIFF)" ] ||
    fail "ground --dtm bad.png: $(cat "$dir/err")"
[ ! -e "$dir/bad.laz" ] && [ ! -e "$dir/bad.png" ] || fail "ground --dtm bad.png wrote something"
echo "cmd_ground_geotiff: ok"
