#!/bin/sh
# tests/app/cmd_info_test.sh: `ladarvr info` as a user runs it, on the real surveys of
# tests/data/real (their README's figures). Usage: cmd_info_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR
#  - the text output: grouped `key: value` lines, one section per file;
#  - --json: one object for one file, an array for several, parsed here and checked
#    against the README (counts, classes, CRS and units, colour depth);
#  - a file with 8-bit colours in its 16-bit RGB fields, written by laspy, reported so;
#  - a file with a scale per axis and an extra bytes field whose descriptor states its
#    scale, offset, no-data value, minimum and maximum: all of them reported;
#  - a COPC file written by `ladarvr index`: its nodes as `index --check` counts them;
#  - stray returns: FSite8's one return 560 m above the rest (laspy finds the heights
#    without it), none in hexbin; in feet (4_6_crop.las with one return added by laspy),
#    the gap that parts a stray is 20 m in feet: 50 ft above the rest is not one, 80 ft is;
#  - a header whose bounds are zeros (hexbin-crop.las's, changed here): a line says they do
#    not hold the points and where the points lie; none for the real files as they are;
#  - a bar per file on a terminal (script's pseudo-terminal), nothing on stderr otherwise;
#  - a folder: its LAS/LAZ files in name order; one without them refused in one line;
#  - a truncated file and a VLR longer than the bytes before the points: one line
#    `ladarvr: error: info: FILE: ...`, exit 1, nothing on stdout; no file: usage, exit 2.
set -eu
bin=$1
dir=$2
data=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# Text: the figures a reader looks for, aligned after their keys.
"$bin" info "$data/4_6_crop.las" >"$dir/out" 2>"$dir/err" || fail "info 4_6_crop.las: $(cat "$dir/err")"
[ -s "$dir/err" ] && fail "info printed on stderr: $(cat "$dir/err")"
head -1 "$dir/out" | grep -qx "$data/4_6_crop.las" || fail "the section does not start with the file: $(head -1 "$dir/out")"
for want in '  format:            LAS 1.2' '  point format:      3 (34-byte records)' '  points:            23875' \
    '  CRS:               EPSG:2903, projected (GeoTIFF keys)' '  horizontal units:  US survey foot (EPSG:9003)' \
    '  vertical units:    US survey foot (EPSG:9003)' '  colour:            all 0 (the RGB fields hold no colour)' \
    '      1 unclassified                      14872   62.3 %' '      2 ground                             9003   37.7 %'; do
    grep -qxF -e "$want" "$dir/out" || fail "no line '$want' in: $(cat "$dir/out")"
done
grep -q '^  density:  *0.597 points per square US survey foot (6.43 points/m²) of the XY bounds$' "$dir/out" ||
    fail "density not in the file's units: $(grep density "$dir/out")"

# Several files: one section each, in order.
"$bin" info "$data/hexbin-crop.las" "$data/FSite8_orig-utm.laz" "$data/sample_c.las" >"$dir/out" 2>"$dir/err" ||
    fail "info of three files: $(cat "$dir/err")"
[ "$(grep -c '^  format:' "$dir/out")" = 3 ] || fail "not three sections: $(cat "$dir/out")"
grep -q '^  density:  *0.65 points/m² of the XY bounds$' "$dir/out" || fail "hexbin's density in m²"
grep -q '^  density: .* per square unit of the XY bounds (the file states no units)$' "$dir/out" ||
    fail "sample_c's density does not say its units are unknown"
grep -qxF '  stray returns:     1 apart from the rest by an empty gap: 1 above 328.86; z without them 241.67 to 328.86' \
    "$dir/out" || fail "FSite8's stray return: $(grep stray "$dir/out")"
[ "$(grep -c '^  stray returns:     none (no heights far apart from the rest)$' "$dir/out")" = 2 ] ||
    fail "hexbin and sample_c hold no stray returns: $(grep stray "$dir/out")"
[ ! -s "$dir/err" ] || fail "info wrote to stderr that is not a terminal: $(cat "$dir/err")"

# On a terminal (script's pseudo-terminal), a bar per file ends at 100 % on its own line.
script -qec "'$bin' info '$data/hexbin-crop.las' '$data/FSite8_orig-utm.laz'" /dev/null >"$dir/tty" </dev/null ||
    fail "info on a terminal: $(cat "$dir/tty")"
tr '\r' '\n' <"$dir/tty" >"$dir/tty.lines"
for f in hexbin-crop.las FSite8_orig-utm.laz; do
    grep -q "^info: $f \[#*\] 100% " "$dir/tty.lines" || fail "no bar at 100 % for $f on a terminal: $(cat "$dir/tty.lines")"
done
grep -q '^  format:            LAZ 1.2' "$dir/tty.lines" || fail "the report is missing on a terminal"

# Header bounds that do not hold the points: hexbin-crop.las's set to zeros.
python3 - "$data/hexbin-crop.las" "$dir/zeroed.las" <<'PY' || fail "could not write zeroed.las"
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
struct.pack_into("<6d", b, 179, 0, 0, 0, 0, 0, 0)
open(sys.argv[2], "wb").write(bytes(b))
PY
"$bin" info "$dir/zeroed.las" "$data/hexbin-crop.las" >"$dir/out" 2>"$dir/err" || fail "info zeroed.las: $(cat "$dir/err")"
[ "$(grep -c '^  header bounds:' "$dir/out")" = 1 ] || fail "not one header bounds line: $(grep bounds "$dir/out")"
grep -qxF '  header bounds:     do not hold the points, which lie in x 393775.823 to 394069.238, y 3689071.943 to 3689273.095, z 3107.86270 to 3209.32050' \
    "$dir/out" || fail "zeroed.las's header bounds: $(grep 'header bounds' "$dir/out")"
"$bin" info --json "$dir/zeroed.las" | python3 -c "import json, sys; sys.exit(0 if json.load(sys.stdin)['las']['header_bounds_hold_points'] is False else 1)" ||
    fail "--json: header_bounds_hold_points is not false for zeroed.las"

# Stray returns in feet: one return 50 ft above 4_6_crop.las's highest, then 80 ft.
for rise in 50 80; do
    python3 - "$data/4_6_crop.las" "$dir/rise$rise.las" "$rise" <<'PY' || fail "laspy could not add a return"
import sys
import laspy
import numpy as np
las = laspy.read(sys.argv[1])
top = int(np.argmax(las.z))
las.points = las.points[np.r_[np.arange(len(las.points)), top]]
z = np.asarray(las.z)
z[-1] += float(sys.argv[3])
las.z = z
las.write(sys.argv[2])
PY
    "$bin" info "$dir/rise$rise.las" >"$dir/out" 2>"$dir/err" || fail "info rise$rise.las: $(cat "$dir/err")"
    line=$(grep '^  stray returns:' "$dir/out")
    case $rise in
        50) [ "$line" = '  stray returns:     none (no heights far apart from the rest)' ] ||
                fail "50 ft above is within 20 m: $line" ;;
        80) [ "$line" = '  stray returns:     1 apart from the rest by an empty gap: 1 above 7139.70; z without them 7077.92 to 7139.70' ] ||
                fail "80 ft above is past 20 m: $line" ;;
    esac
done

# --json, against the README's figures.
"$bin" info --json "$data/4_6_crop.las" "$data/sample_c.las" "$data/hexbin-crop.las" "$data/warsaw_small.las" \
    "$data/mvk-thin.las" "$data/FSite8_orig-utm.laz" >"$dir/all.json" 2>"$dir/err" || fail "info --json: $(cat "$dir/err")"
"$bin" info --json "$data/warsaw_small.las" >"$dir/one.json" || fail "info --json of one file"
python3 - "$dir/all.json" "$dir/one.json" "$data/FSite8_orig-utm.laz" <<'PY' || fail "the JSON of info --json"
import json, sys
files = json.load(open(sys.argv[1]))
assert isinstance(files, list) and len(files) == 6, "not an array of 6"
one = json.load(open(sys.argv[2]))
assert isinstance(one, dict) and one["file"].endswith("warsaw_small.las"), "one file: not one object"
by = {f["file"].rsplit("/", 1)[1]: f for f in files}
def classes(f): return {c["class"]: c["points"] for c in f["las"]["classes"]}
crop = by["4_6_crop.las"]
assert crop["format"] == "LAS" and crop["version"] == "1.2" and crop["las"]["point_format"] == 3
assert crop["points"] == 23875 and crop["las"]["legacy_points"] == 23875
assert classes(crop) == {1: 14872, 2: 9003}, classes(crop)
crs = crop["las"]["crs"]
assert crs["epsg"] == 2903 and crs["source"] == "geotiff", crs
assert crs["horizontal_unit"]["name"] == "US survey foot" and crs["horizontal_unit"]["epsg"] == 9003, crs
assert abs(crs["horizontal_unit"]["metres"] - 1200 / 3937) < 1e-15, crs
assert crs["vertical_unit"]["name"] == "US survey foot", crs
assert crop["las"]["colour"] == "zero"
d = crop["las"]["density"]
assert d["unit"] == "US survey foot" and abs(d["points_per_m2"] * (1200 / 3937) ** 2 - d["points_per_unit2"]) < 1e-9, d
sample = by["sample_c.las"]
assert sample["points"] == 14408 and sorted(classes(sample)) == [2, 3, 4, 5, 6, 11, 14, 31], classes(sample)
assert classes(sample)[6] == 12525
assert sample["las"]["crs"]["source"] is None and sample["las"]["crs"]["horizontal_unit"] is None
assert sample["las"]["colour"] == "16-bit" and max(sample["las"]["rgb_max"]) > 255
assert sample["las"]["density"]["unit"] is None and sample["las"]["density"]["points_per_m2"] is None
hexbin = by["hexbin-crop.las"]
assert hexbin["points"] == 38367 and classes(hexbin) == {1: 3049, 2: 35318}
assert hexbin["las"]["crs"]["epsg"] == 32642 and hexbin["las"]["crs"]["name"] == "WGS 84 / UTM zone 42N"
assert hexbin["las"]["crs"]["horizontal_unit"]["name"] == "metre"
assert hexbin["las"]["colour"] == "none" and hexbin["las"]["rgb_max"] is None
warsaw = by["warsaw_small.las"]
assert warsaw["points"] == 3000 and sorted(classes(warsaw)) == [0, 2, 3, 4, 5]
assert warsaw["las"]["classes"][0]["name"] == "never classified"
assert warsaw["las"]["crs"]["source"] is None and "holds no CRS" in warsaw["las"]["crs"]["problem"]
mvk = by["mvk-thin.las"]
assert mvk["points"] == 6280 and sorted(classes(mvk)) == [1, 2, 4, 5, 9, 12]
site = by["FSite8_orig-utm.laz"]
assert site["format"] == "LAZ" and site["las"]["compressed"] and site["points"] == 345966
import laspy
z = laspy.read(sys.argv[3]).z
strays = site["las"]["stray_returns"]
assert strays["below"] == 0 and strays["above"] == 1 and (z > 500).sum() == 1, strays
assert abs(strays["z_without"][1] - z[z < 500].max()) < 1e-3 and abs(strays["z_without"][0] - z.min()) < 1e-3, strays
h = by["hexbin-crop.las"]["las"]["stray_returns"]
assert h["below"] == 0 and h["above"] == 0, h
assert [round(v, 5) for v in h["z_without"]] == [3107.8627, 3209.3205], h
assert classes(site) == {0: 345966}
assert site["las"]["crs"]["epsg"] == 32632 and site["las"]["crs"]["horizontal_unit"]["name"] == "metre"
for f in files:
    assert len(f["bounds"]["min"]) == 3 and all(a <= b for a, b in zip(f["bounds"]["min"], f["bounds"]["max"]))
    assert not f["las"]["copc"] and f["las"]["copc_nodes"] is None
    assert f["las"]["header_bounds_hold_points"] is True, f["file"]
PY

# 8-bit colours in 16-bit fields, as some producers write them (laspy writes the file).
python3 - "$dir/eight.las" <<'PY' || fail "laspy could not write the 8-bit colour file"
import sys
import laspy
import numpy as np
las = laspy.create(point_format=3, file_version="1.2")
n = 1000
las.x = np.arange(n) * 0.1
las.y = np.arange(n) % 37 * 0.5
las.z = np.zeros(n)
las.red = np.arange(n) % 256
las.green = (np.arange(n) * 3) % 200
las.blue = np.full(n, 17)
las.classification = np.full(n, 2)
las.write(sys.argv[1])
PY
"$bin" info "$dir/eight.las" >"$dir/out" 2>"$dir/err" || fail "info eight.las: $(cat "$dir/err")"
grep -qxF '  colour:            8-bit values in 16-bit fields (every value <= 255)' "$dir/out" ||
    fail "8-bit colours not reported: $(grep colour "$dir/out")"
grep -qxF '  largest RGB:       255 199 17' "$dir/out" || fail "largest RGB: $(grep 'largest RGB' "$dir/out")"
"$bin" info --json "$dir/eight.las" | python3 -c '
import json, sys
f = json.load(sys.stdin)
assert f["las"]["colour"] == "8-bit" and f["points"] == 1000, f["las"]["colour"]' || fail "8-bit colours in --json"

# Extra bytes descriptors: every value they state, and the scale on each axis (laspy
# writes the file; the no-data value, minimum and maximum are set in its descriptor).
python3 - "$dir/extra.las" <<'PY' || fail "laspy could not write the extra bytes file"
import struct, sys
import laspy
import numpy as np
las = laspy.create(point_format=6, file_version="1.4")
las.header.scales = np.array([0.00025, 0.00025, 0.0001])
las.add_extra_dim(laspy.ExtraBytesParams(name="Deviation", type=np.int16, description="deviation in tenths",
                                         scales=[0.1], offsets=[2.5]))
las.add_extra_dim(laspy.ExtraBytesParams(name="Amplitude", type=np.float32))
las.x = np.arange(10) * 0.5
las.y = np.zeros(10)
las.z = np.zeros(10)
las.Deviation = np.arange(10) * 0.1 + 2.5
las.write(sys.argv[1])
b = bytearray(open(sys.argv[1], "rb").read())
at = b.index(b"Deviation\0") - 4
b[at + 3] |= 1 | 2 | 4
struct.pack_into("<qqq", b, at + 40, -32768, 0, 0)
struct.pack_into("<q", b, at + 64, -300)
struct.pack_into("<q", b, at + 88, 300)
open(sys.argv[1], "wb").write(b)
PY
"$bin" info "$dir/extra.las" >"$dir/out" 2>"$dir/err" || fail "info extra.las: $(cat "$dir/err")"
grep -qxF '  scale:             0.00025 0.00025 0.0001' "$dir/out" || fail "scale per axis: $(grep scale: "$dir/out")"
grep -qxF '  extra bytes:       Deviation (int16; scale 0.1, offset 2.5, no data -32768, min -300, max 300), Amplitude (float32)' \
    "$dir/out" || fail "extra bytes: $(grep 'extra bytes' "$dir/out")"
"$bin" info --json "$dir/extra.las" | python3 -c '
import json, sys
e = json.load(sys.stdin)["las"]["extra_bytes"]
assert e[0] == {"name": "Deviation", "type": "int16", "bytes": 2, "description": "deviation in tenths", "scale": 0.1,
                "offset": 2.5, "no_data": -32768, "min": -300, "max": 300}, e[0]
assert e[1]["name"] == "Amplitude" and e[1]["scale"] is None and e[1]["no_data"] is None, e[1]' ||
    fail "extra bytes in --json"

# COPC: the nodes `index --check` counts.
"$bin" index "$data/hexbin-crop.las" --out "$dir/hexbin.copc.laz" --node-points 5000 >/dev/null 2>"$dir/err" ||
    fail "index: $(cat "$dir/err")"
nodes=$("$bin" index --check "$dir/hexbin.copc.laz" | sed -n 's/.*valid COPC (\([0-9]*\) nodes with points.*/\1/p')
[ -n "$nodes" ] && [ "$nodes" -gt 1 ] || fail "index --check gave no node count"
"$bin" info "$dir/hexbin.copc.laz" >"$dir/out" 2>"$dir/err" || fail "info of the COPC file: $(cat "$dir/err")"
grep -qxF "  COPC:              yes, $nodes nodes with points" "$dir/out" || fail "COPC nodes: $(grep COPC "$dir/out")"
grep -qxF '  format:            COPC 1.4' "$dir/out" || fail "COPC format: $(grep format: "$dir/out")"
grep -qxF '  points:            38367' "$dir/out" || fail "COPC points: $(grep points: "$dir/out")"
# One node: said in the singular.
"$bin" index "$data/warsaw_small.las" --out "$dir/one.copc.laz" >/dev/null 2>"$dir/err" || fail "index: $(cat "$dir/err")"
"$bin" index --check "$dir/one.copc.laz" | grep -q "valid COPC (1 node with points, 3000 points)" ||
    fail "index --check of one node: $("$bin" index --check "$dir/one.copc.laz")"
"$bin" info "$dir/one.copc.laz" | grep -qxF "  COPC:              yes, 1 node with points" ||
    fail "info of one node: $("$bin" info "$dir/one.copc.laz" | grep COPC)"

# Bad input: one line, exit 1, nothing on stdout.
refused() {
    file=$1
    want=$2
    status=0
    "$bin" info "$data/sample_c.las" "$file" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" = 1 ] || fail "info $file: exit $status, expected 1"
    [ -s "$dir/out" ] && fail "info $file printed on stdout: $(head -3 "$dir/out")"
    [ "$(wc -l <"$dir/err")" = 1 ] || fail "info $file: not one line: $(cat "$dir/err")"
    grep -qxF -e "$want" "$dir/err" || fail "info $file said '$(cat "$dir/err")', expected '$want'"
}
head -c 300000 "$data/4_6_crop.las" >"$dir/cut.las"
refused "$dir/cut.las" "ladarvr: error: info: $dir/cut.las: truncated: the header says 23875 points of 34 bytes but only 299540 bytes of point data follow"
python3 - "$data/4_6_crop.las" "$dir/long_vlr.las" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
first = struct.unpack_from("<H", b, 94)[0]
second = first + 54 + struct.unpack_from("<H", b, first + 20)[0]
struct.pack_into("<H", b, second + 20, 60000)  # VLR 1 claims 60000 bytes
open(sys.argv[2], "wb").write(b)
PY
refused "$dir/long_vlr.las" "ladarvr: error: info: $dir/long_vlr.las: VLR 1 runs into the point data"
refused "$dir/absent.las" "ladarvr: error: info: $dir/absent.las: file does not exist"
# A folder: its .las/.laz files in name order (a file of another kind left out); one
# without them refused.
mkdir -p "$dir/tiles" "$dir/no-tiles"
cp "$data/warsaw_small.las" "$data/hexbin-crop.las" "$dir/tiles/"
printf 'notes\n' >"$dir/tiles/README.txt"
cp "$dir/tiles/README.txt" "$dir/no-tiles/"
"$bin" info "$dir/tiles" --json >"$dir/out" 2>"$dir/err" || fail "info FOLDER: $(cat "$dir/err")"
python3 - "$dir/out" "$dir/tiles" <<'PY' || fail "info FOLDER: not its two files in name order: $(cat "$dir/out")"
import json, sys
files = json.load(open(sys.argv[1]))
assert [f["file"] for f in files] == [sys.argv[2] + "/hexbin-crop.las", sys.argv[2] + "/warsaw_small.las"], files
assert [f["points"] for f in files] == [38367, 3000], [f["points"] for f in files]
PY
refused "$dir/no-tiles" "ladarvr: error: info: input '$dir/no-tiles' is a folder that holds no .las or .laz file; allowed: cloud files, or folders of LAS/LAZ tiles"
status=0
"$bin" info >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" = 2 ] || fail "info without a file: exit $status, expected 2"
grep -q "^ladarvr: error: info: missing files: the cloud files (a folder gives its .las/.laz files in name order) (see 'ladarvr info --help')$" "$dir/err" ||
    fail "info without a file said: $(cat "$dir/err")"
echo "cmd_info: ok"
