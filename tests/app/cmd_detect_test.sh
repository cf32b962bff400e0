#!/bin/sh
# tests/app/cmd_detect_test.sh: `ladarvr detect` on a small cloud of the demo scene, as a
# user runs it. Usage: cmd_detect_test.sh LADARVR_BINARY SCRATCH_DIR
#  - the demo's tank (centre at the world origin, turned by 20 deg) is among the candidates
#    with a high score and its yaw, with both the RANSAC and the labels' ground;
#  - on a sparse cloud of the hilly scene the terrain filters (--ground smrf, csf) rank
#    its tank (at the world origin, turned by -35 deg) in the top 3;
#  - the demo written in US survey feet gives the metre cloud's candidates, centres in
#    feet, and their file is refused over a cloud in metres (and the other way round);
#  - bad options and inputs: one line `ladarvr: error: ...`, exit 2 (usage) or 1, no file;
#    a crafted --model (the shipped one with a tree's child out of range and a valid SHA-256)
#    among them, which crashed XGBoost before the model's trees were checked.
set -eu
bin=$1
dir=$2
assets=$(cd "$(dirname "$0")/../../assets" && pwd)
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" generate --out "$dir/demo.pcd" --xres 128 --yres 128 --views 40 >/dev/null 2>&1 ||
    fail "generate failed"

for ground in ransac labels; do
    "$bin" detect "$dir/demo.pcd" --out "$dir/sub/c_$ground.json" --ground "$ground" >"$dir/out" 2>"$dir/err" ||
        fail "detect --ground $ground: $(cat "$dir/err")"
    grep -q "wrote $dir/sub/c_$ground.json" "$dir/out" || fail "no summary line: $(cat "$dir/out")"
    python3 - "$dir/sub/c_$ground.json" <<'PY' || fail "candidates of --ground $ground"
import json, math, sys
cands = json.load(open(sys.argv[1]))["candidates"]
assert cands, "no candidate"
assert [c["id"] for c in cands] == ["c%d" % (k + 1) for k in range(len(cands))], "ids"
assert all(a["score"] >= b["score"] for a, b in zip(cands, cands[1:])), "not best first"
assert all(0.05 <= c["score"] <= 1 for c in cands), "score below --min-score"
tank = [c for c in cands if math.hypot(c["centre"][0], c["centre"][1]) < 2.0]
assert len(tank) == 1, "no candidate at the tank: %s" % cands
t = tank[0]
assert t["score"] > 0.5, t
d = abs(t["yaw_deg"] - 20.0) % 180.0
assert min(d, 180.0 - d) < 5.0, t
assert 2.0 < t["size_m"][2] < 3.0 and 3.0 < t["size_m"][1] < 4.0, t
PY
done

# Hilly ground (18.7 m of relief around the tank): a 30 m RANSAC tile's 3 m band leaves
# the hillsides standing, SMRF's and CSF's terrain follows them (64 x 64 px, 40 views: the
# gun barrel is too sparsely sampled there to lengthen the tank's box, which in denser
# clouds costs it places, docs/detect.md).
"$bin" generate --scene "$assets/hilly/scene.json" --out "$dir/hilly.pcd" --xres 64 --yres 64 --views 40 \
    >/dev/null 2>&1 || fail "generate hilly failed"
for ground in smrf csf; do
    "$bin" detect "$dir/hilly.pcd" --out "$dir/h_$ground.json" --ground "$ground" >"$dir/out" 2>"$dir/err" ||
        fail "detect --ground $ground: $(cat "$dir/err")"
    grep -q "ground ($ground)" "$dir/out" || fail "the summary does not name --ground $ground: $(cat "$dir/out")"
    python3 - "$dir/h_$ground.json" <<'PY' || fail "the hilly tank with --ground $ground"
import json, math, sys
cands = json.load(open(sys.argv[1]))["candidates"]
rank = [k + 1 for k, c in enumerate(cands) if math.hypot(c["centre"][0], c["centre"][1]) < 2.0]
assert rank and rank[0] <= 3, "tank rank %s: %s" % (rank, cands[:4])
t = cands[rank[0] - 1]
d = abs(t["yaw_deg"] + 35.0) % 180.0
assert min(d, 180.0 - d) < 5.0, t
PY
done

# The target size decides the ranking: looking for 60 m long things finds nothing near.
"$bin" detect "$dir/demo.pcd" --out "$dir/big.json" --target-size-m 60 40 20 --ground labels >/dev/null 2>&1 ||
    fail "detect --target-size-m 60 40 20"
python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['candidates']; assert all(x['score'] < 0.5 for x in c), c" \
    "$dir/big.json" || fail "a 60 x 40 x 20 target scored high"

# A survey in US survey feet: the demo cloud written in feet, with 4_6_crop.las's CRS
# (EPSG:2903, GeoTIFF keys), by laspy. Its candidates are the metre cloud's: found in
# metres, their centres in feet, the file saying so; the sizes in metres.
real=$(cd "$(dirname "$0")/../data/real" && pwd)
"$bin" generate --out "$dir/demo.las" --xres 128 --yres 128 --views 40 >/dev/null 2>&1 || fail "generate demo.las"
python3 - "$dir/demo.las" "$real/4_6_crop.las" "$dir/demo_ft.las" <<'PY' || fail "writing the demo in feet"
import sys, laspy, numpy as np
src, crs, out = laspy.read(sys.argv[1]), laspy.read(sys.argv[2]), sys.argv[3]
foot = 1200.0 / 3937.0
header = laspy.LasHeader(point_format=3, version="1.2")
header.vlrs = [v for v in crs.header.vlrs if v.user_id == "LASF_Projection"]
header.offsets = np.array([0.0, 0.0, 0.0])
header.scales = np.array([0.001, 0.001, 0.001])
new = laspy.LasData(header)
new.x, new.y, new.z = src.x / foot, src.y / foot, src.z / foot
for name in ("intensity", "red", "green", "blue"):
    if name in src.point_format.dimension_names:
        new[name] = src[name]
new.write(out)
PY
# SMRF's terrain and the trained detector see the same metres in both (RANSAC's tiles are
# laid from the cloud's local origin, which the reader puts elsewhere in feet).
for how in "--ground smrf" "--model $assets/detect/model.ldm"; do
"$bin" detect "$dir/demo.las" --out "$dir/c_m.json" $how >/dev/null 2>"$dir/err" ||
    fail "detect demo.las $how: $(cat "$dir/err")"
"$bin" detect "$dir/demo_ft.las" --out "$dir/c_ft.json" $how >"$dir/out" 2>"$dir/err" ||
    fail "detect demo_ft.las $how: $(cat "$dir/err")"
grep -q "coordinates in US survey feet (0.3048006 m): detected in metres" "$dir/out" ||
    fail "no units line: $(cat "$dir/out")"
python3 - "$dir/c_m.json" "$dir/c_ft.json" <<'PY' || fail "candidates of the survey in feet, $how"
import json, math, sys
metres, feet = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
foot = 1200.0 / 3937.0
assert "units" not in metres, metres.keys()
assert sorted(feet["units"]) == ["horizontal_m", "vertical_m"], feet["units"]
assert all(abs(v - foot) < 1e-12 for v in feet["units"].values()), feet["units"]
def tank(cands, unit):
    near = [c for c in cands if math.hypot(c["centre"][0] * unit, c["centre"][1] * unit) < 2.0]
    assert len(near) == 1, cands
    return near[0]
m, f = tank(metres["candidates"], 1.0), tank(feet["candidates"], foot)
assert f["score"] > 0.5, f
assert all(abs(a - b) < 0.05 for a, b in zip(m["size_m"], f["size_m"])), (m, f)
assert all(abs(a - b * foot) < 0.05 for a, b in zip(m["centre"], f["centre"])), (m, f)
assert abs(m["score"] - f["score"]) < 0.01, (m, f)
PY
done

# one_error STATUS PATTERN ARGS...: exit STATUS, one line matching PATTERN, no output file.
one_error() {
    expect=$1 pattern=$2
    shift 2
    rm -f "$dir/bad.json"
    status=0
    "$bin" "$@" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq "$expect" ] || fail "ladarvr $* exited $status, expected $expect: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "not one line: $(cat "$dir/err")"
    grep -q -e "^ladarvr: error: .*$pattern" "$dir/err" || fail "'$pattern' not in: $(cat "$dir/err")"
    [ ! -e "$dir/bad.json" ] || fail "ladarvr $* left $dir/bad.json"
}
one_error 2 "--ground" detect "$dir/demo.pcd" --out "$dir/bad.json" --ground foo
one_error 2 "--target-size-m" detect "$dir/demo.pcd" --out "$dir/bad.json" --target-size-m 7 3.5
one_error 2 "--out" detect "$dir/demo.pcd"
one_error 1 "--min-score = 2: allowed \[0, 1\]" detect "$dir/demo.pcd" --out "$dir/bad.json" --min-score 2
one_error 1 "--target-size-m = -7" detect "$dir/demo.pcd" --out "$dir/bad.json" --target-size-m -7 3.5 2.5
one_error 1 "--smrf-slope" detect "$dir/demo.pcd" --out "$dir/bad.json" --ground smrf --smrf-slope 0
one_error 1 "--csf-rigidness" detect "$dir/demo.pcd" --out "$dir/bad.json" --ground csf --csf-rigidness 4
one_error 1 "--cluster-tolerance-m" detect "$dir/demo.pcd" --out "$dir/bad.json" --cluster-tolerance-m 0.1
one_error 1 "missing.pcd" detect "$dir/missing.pcd" --out "$dir/bad.json"
one_error 1 "name the same file" detect "$dir/demo.pcd" --out "$dir/demo.pcd"
python3 - "$assets/detect/model.ldm" "$dir/crafted.ldm" <<'PY' || fail "crafting a model"
import hashlib, struct, sys
data = bytearray(open(sys.argv[1], "rb").read())
model_at = 20 + struct.unpack_from("<I", data, 8)[0]
old = hashlib.sha256(data[model_at:]).hexdigest().encode()
key = b"L" + struct.pack(">q", 13) + b"left_children"
at = data.index(key, model_at) + len(key) + 13  # tree 0's left child of node 0, after "[$l#L" and the count
struct.pack_into(">i", data, at, 99)
data[:model_at] = bytes(data[:model_at]).replace(old, hashlib.sha256(data[model_at:]).hexdigest().encode())
open(sys.argv[2], "wb").write(data)
PY
one_error 1 "--model $dir/crafted.ldm: tree 0 node 0: left child 99: allowed -1 (a leaf) or 1\.\.16" \
    detect "$dir/demo.pcd" --model "$dir/crafted.ldm" --out "$dir/bad.json"
# Candidates found in feet drawn over a cloud in metres would stand elsewhere: refused
# before a window opens (and the other way round).
one_error 1 "view: --candidates $dir/c_ft.json: centres in units of 0.3048006096 m; the cloud is in metres" \
    view "$dir/demo.pcd" --candidates "$dir/c_ft.json" --frames 1
one_error 1 "view: --candidates $dir/c_m.json: centres in metres; the cloud is in US survey feet" \
    view "$dir/demo_ft.las" --candidates "$dir/c_m.json" --frames 1
echo "cmd_detect: ok"
