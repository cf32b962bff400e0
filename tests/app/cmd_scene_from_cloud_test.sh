#!/bin/sh
# tests/app/cmd_scene_from_cloud_test.sh: `ladarvr scene from-cloud` as a user runs it on
# the real surveys of tests/data/real, then `scene info` and `generate` on the folder.
# Usage: cmd_scene_from_cloud_test.sh LADARVR_BINARY SCRATCH_DIR REAL_DATA_DIR ASSETS_DIR
#  - the folder holds the scene, the terrain, the boxes, the vehicle and the record; the
#    vehicle sits on the ground (`scene info` warns of nothing); `generate` flies it and
#    labels target points;
#  - a survey in feet is converted (stderr says so); --coarsen says in one line what it did;
#    a vehicle of one family is drawn from scripts/make_vehicles.py's list; a glTF vehicle
#    with y up (Debian's assimp-testmodels milk truck, whose buffers are other files) is
#    written as target.obj, z up, and stands on the ground upright;
#  - bad options, too many boxes and a geographic CRS give one line and no folder; the
#    survey is never overwritten; a second run replaces the folder whole.
set -eu
bin=$1
dir=$2
real=$3
assets=$4
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" scene from-cloud "$real/hexbin-crop.las" --out "$dir/hex" --vehicle "$assets/common/van.obj" --seed 2 \
    >"$dir/out" 2>"$dir/err" || fail "from-cloud: $(cat "$dir/err")"
[ -s "$dir/err" ] && fail "from-cloud printed on stderr: $(cat "$dir/err")"
grep -q "^scene from-cloud: wrote $dir/hex: 38367 points, 35318 ground (class 2), terrain .* boxes of 0.5 m, offset .*, vehicle at " \
    "$dir/out" || fail "summary line: $(cat "$dir/out")"
[ "$(ls "$dir/hex" | tr '\n' ' ')" = "environment.obj from_cloud.json ground.obj scene.json target.obj " ] ||
    fail "folder: $(ls "$dir/hex")"
"$bin" scene info "$dir/hex/scene.json" --json >"$dir/info" 2>"$dir/err" || fail "scene info: $(cat "$dir/err")"
tr -d ' \n' <"$dir/info" | grep -q '"warnings":\[\]' || fail "scene info warns: $(cat "$dir/info")"
"$bin" generate --scene "$dir/hex/scene.json" --out "$dir/hex.pcd" --views 4 --xres 32 --yres 32 --json \
    >"$dir/json" 2>"$dir/err" || fail "generate: $(cat "$dir/err")"
target=$(sed -n 's/^ *"target_above_terrain": \([0-9]*\),*$/\1/p' "$dir/json")
[ -n "$target" ] && [ "$target" -gt 0 ] || fail "generate: no target points: $(cat "$dir/json")"

# The same survey again with a coarser voxel: the folder is replaced whole.
"$bin" scene from-cloud "$real/hexbin-crop.las" --out "$dir/hex" --voxel-m 2 >"$dir/out" 2>"$dir/err" ||
    fail "from-cloud again: $(cat "$dir/err")"
[ "$(ls "$dir/hex" | tr '\n' ' ')" = "environment.obj from_cloud.json ground.obj scene.json " ] ||
    fail "folder replaced: $(ls "$dir/hex")"
grep -q '"voxel_m": 2.0000' "$dir/hex/from_cloud.json" || fail "record: $(cat "$dir/hex/from_cloud.json")"

# Feet: converted, said on stderr.
"$bin" scene from-cloud "$real/4_6_crop.las" --out "$dir/feet" >"$dir/out" 2>"$dir/err" ||
    fail "from-cloud feet: $(cat "$dir/err")"
[ "$(cat "$dir/err")" = "scene from-cloud: coordinates in US survey feet (0.3048006 m): converted to metres" ] ||
    fail "feet: stderr: $(cat "$dir/err")"

# --coarsen past --max-boxes: one line on stderr.
"$bin" scene from-cloud "$real/hexbin-crop.las" --out "$dir/coarse" --max-boxes 500 --coarsen >"$dir/out" \
    2>"$dir/err" || fail "from-cloud --coarsen: $(cat "$dir/err")"
[ "$(wc -l <"$dir/err")" = 1 ] && grep -q "^scene from-cloud: more than --max-boxes 500 boxes at --voxel-m 0.5: coarsened to 8 m voxels ([0-9]* boxes)$" \
    "$dir/err" || fail "coarsen line: $(cat "$dir/err")"

# A vehicle drawn from scripts/make_vehicles.py's list, of one family: copied as the target.
python3 "$assets/../scripts/make_vehicles.py" --out "$dir/veh" --per-family 1 --families car,tank >/dev/null ||
    fail "make_vehicles.py"
"$bin" scene from-cloud "$real/hexbin-crop.las" --out "$dir/fam" --vehicle "$dir/veh/vehicles.json" --family tank \
    >"$dir/out" 2>"$dir/err" || fail "from-cloud --family: $(cat "$dir/err")"
[ "$(cat "$dir/err")" = "scene from-cloud: vehicle $dir/veh/tank_00.obj (tank) drawn from the list" ] ||
    fail "--family: stderr: $(cat "$dir/err")"
cmp -s "$dir/veh/tank_00.obj" "$dir/fam/target.obj" || fail "--family: the target is not tank_00.obj"

# A glTF with y up whose buffers are other files: its triangles written as target.obj, z up.
truck=/usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf
"$bin" scene from-cloud "$real/hexbin-crop.las" --out "$dir/truck" --vehicle "$truck" --vehicle-up y \
    >"$dir/out" 2>"$dir/err" || fail "from-cloud glTF: $(cat "$dir/err")"
[ "$(ls "$dir/truck" | tr '\n' ' ')" = "environment.obj from_cloud.json ground.obj scene.json target.obj " ] ||
    fail "glTF folder: $(ls "$dir/truck")"
"$bin" scene info "$dir/truck/scene.json" --json >"$dir/info" 2>"$dir/err" || fail "scene info glTF: $(cat "$dir/err")"
tr -d ' \n' <"$dir/info" | grep -q '"warnings":\[\]' || fail "scene info warns (glTF): $(cat "$dir/info")"
# Upright: the truck is about 2.8 m high and longer than wide (lying on its side it would be
# 2.8 m wide and 2.3 m high).
python3 - "$dir/truck/from_cloud.json" <<'PY' || fail "glTF record: $(cat "$dir/truck/from_cloud.json")"
import json, sys
v = json.load(open(sys.argv[1]))["vehicle"]
assert v["up"] == "y" and v["file"] == "target.obj", v
length, width, height = v["size_m"]
assert length > 4.5 and 2.5 < width < length and 2.7 < height < 3.0, v["size_m"]
PY
"$bin" generate --scene "$dir/truck/scene.json" --out "$dir/truck.pcd" --views 4 --xres 32 --yres 32 --json \
    >"$dir/json" 2>"$dir/err" || fail "generate glTF: $(cat "$dir/err")"

# Refusals: one line, no folder.
bad() {
    want=$1
    shift
    if "$bin" scene from-cloud "$@" >"$dir/out" 2>"$dir/err"; then fail "from-cloud $* succeeded"; fi
    [ "$(wc -l <"$dir/err")" = 1 ] || fail "from-cloud $*: not one line: $(cat "$dir/err")"
    grep -qF -e "$want" "$dir/err" || fail "from-cloud $*: no '$want' in: $(cat "$dir/err")"
    [ -e "$dir/bad" ] && fail "from-cloud $* left $dir/bad"
    return 0
}
bad "--voxel-m is 0; allowed (0.05, 100] metres" "$real/hexbin-crop.las" --out "$dir/bad" --voxel-m 0
bad "--vehicle-up needs --vehicle" "$real/hexbin-crop.las" --out "$dir/bad" --vehicle-up y
bad "--ground-from 'x' is not one of auto, classes, filter" "$real/hexbin-crop.las" --out "$dir/bad" --ground-from x
bad "allowed at most --max-boxes 10: raise --voxel-m or --max-boxes, or give --coarsen" "$real/hexbin-crop.las" \
    --out "$dir/bad" --max-boxes 10
bad "--vehicle-at needs --vehicle" "$real/hexbin-crop.las" --out "$dir/bad" --vehicle-at 1,2
bad "no room at --vehicle-at" "$real/hexbin-crop.las" --out "$dir/bad" --vehicle "$assets/common/van.obj" \
    --vehicle-at 393923,3689173 --max-slope 0
bad "no-such.las" "$real/no-such.las" --out "$dir/bad"
bad "no vehicle of --family 'boat'; allowed a family the list holds" "$real/hexbin-crop.las" --out "$dir/bad" \
    --vehicle "$dir/veh/vehicles.json" --family boat
bad "--family needs --vehicle naming a vehicles.json list" "$real/hexbin-crop.las" --out "$dir/bad" --family tank
python3 - "$real/hexbin-crop.las" "$dir/degrees.las" <<'PY'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
at = data.find(b'PROJCS["WGS 84 / UTM zone 42N"')
end = data.find(b"\0", at)
wkt = (b'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
       b'UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],AUTHORITY["EPSG","4326"]]')
assert at > 0 and end - at > len(wkt)
data[at:end] = wkt + bytes(end - at - len(wkt))
open(sys.argv[2], "wb").write(data)
PY
bad "its CRS 'WGS 84' (EPSG:4326) is geographic" "$dir/degrees.las" --out "$dir/bad"

# The survey is never overwritten: an output folder holding it, or named as it, is refused.
mkdir -p "$dir/in"
cp "$real/hexbin-crop.las" "$dir/in/survey.las"
before=$(cksum <"$dir/in/survey.las")
if "$bin" scene from-cloud "$dir/in/survey.las" --out "$dir/in" >"$dir/out" 2>"$dir/err"; then
    fail "from-cloud replaced the folder holding its survey"
fi
if "$bin" scene from-cloud "$dir/in/survey.las" --out "$dir/in/survey.las" >"$dir/out" 2>"$dir/err"; then
    fail "from-cloud replaced its survey"
fi
[ "$(cksum <"$dir/in/survey.las")" = "$before" ] || fail "the survey changed"
echo "cmd_scene_from_cloud: ok"
