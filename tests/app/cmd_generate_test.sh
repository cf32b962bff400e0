#!/bin/sh
# tests/app/cmd_generate_test.sh: `ladarvr generate` as a user runs it.
# Usage: cmd_generate_test.sh LADARVR_BINARY SCRATCH_DIR
# Bad parameters: exit 1, one error line naming the option, no file left behind.
# A small good run: the JSON summary has the required keys and matches the file; the
# human summary's ground line speaks of the filter that ran (RANSAC, SMRF, CSF, none).
set -eu
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

check_bad() {
    expect=$1
    shift
    status=0
    "$bin" generate --out "$dir/x.pcd" "$@" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq 1 ] || fail "generate $* exited $status, expected 1"
    grep -q -e "$expect" "$dir/err" || fail "generate $*: error does not name $expect: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "generate $*: more than one line: $(cat "$dir/err")"
    left=$(ls -A "$dir" | grep -v -e '^err$' -e '^out$' || true)
    [ -z "$left" ] || fail "generate $* left files behind: $left"
}

check_bad "--alpha-deg" --alpha-deg 88
check_bad "--fov-deg" --fov-deg 0
check_bad "--xres" --xres 0
check_bad "--yres" --yres -4
check_bad "--views" --views 0
check_bad "--views" --views 70000
check_bad "--altitude-m" --altitude-m -300
check_bad "--overlap-m" --overlap-m 1000
check_bad "--band-m" --band-m 0
check_bad "--min-normal-z" --min-normal-z 2
check_bad "--colours" --colours 1
check_bad "--threads" --threads -1
check_bad "--centre" --centre 1,2
check_bad "--roles" --roles tank
check_bad "--format" --format las
check_bad "--format" --format e57
check_bad "--drone-speed-mps" --drone-speed-mps 0
check_bad "--las-target-class" --las-target-class 300
# An --out extension we cannot write is refused (never a PCD under that name).
status=0
"$bin" generate --out "$dir/cloud.e57" --xres 8 --yres 8 --views 1 >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 1 ] || fail "--out cloud.e57 exited $status, expected 1"
grep -q "extension '.e57' is not one of .pcd, .ply, .las, .laz, .copc.laz" "$dir/err" || fail "--out cloud.e57: $(cat "$dir/err")"
[ ! -e "$dir/cloud.e57" ] || fail "--out cloud.e57 wrote a file"
rm -f "$dir/out" "$dir/err"
check_bad "does not exist" --scene "$dir/missing.json"
# Once bad_alloc: a 65536 x 65536 view cannot be whitened within the budget.
check_bad "--memory-mb 512 is too small" --xres 65536 --yres 65536 --views 1

"$bin" generate --out "$dir/ok.pcd" --xres 32 --yres 24 --views 8 --json >"$dir/summary.json" 2>"$dir/err" ||
    fail "good run failed: $(cat "$dir/err")"
python3 - "$dir" <<'EOF'
import json, sys
d = sys.argv[1]
s = json.load(open(d + "/summary.json"))
for key in ("drone_radius_m", "length_sensed_m", "coverage_diameter_m", "rays", "points", "misses",
            "ground_precision", "ground_recall", "seconds", "output", "stage_seconds"):
    assert key in s, key
assert abs(s["drone_radius_m"] - 326.12) < 0.005, s["drone_radius_m"]
assert abs(s["length_sensed_m"] - 68.36) < 0.005, s["length_sensed_m"]
assert s["rays"] == 32 * 24 * 8, s["rays"]
assert s["points"] + s["misses"] == s["rays"]
header = open(d + "/ok.pcd", "rb").read(2000).split(b"DATA")[0].decode()
count = int([l for l in header.splitlines() if l.startswith("POINTS")][0].split()[1])
assert count == s["points"], (count, s["points"])
assert 0.9 < s["ground_precision"] <= 1 and 0.9 < s["ground_recall"] <= 1, s
EOF
cp "$dir/err" "$dir/err.good"
grep -q "drone radius 326.12 m" "$dir/err" || fail "human summary lacks the drone radius: $(cat "$dir/err")"
# The ground line speaks of the filter that ran: planes for RANSAC only.
grep -q "^  ground: [0-9]* points whitened by RANSAC ([0-9]* planes kept, [0-9]* dropped), [0-9]* labelled ground;" \
    "$dir/err" || fail "RANSAC's ground line: $(cat "$dir/err")"
"$bin" generate --out "$dir/white.pcd" --white --xres 8 --yres 8 --views 2 2>"$dir/err" >/dev/null ||
    fail "--white run failed: $(cat "$dir/err")"
grep -q "^  ground: no filter ran (--white), [0-9]* labelled ground;" "$dir/err" || fail "--white's ground line: $(cat "$dir/err")"
! grep -q "planes" "$dir/err" || fail "--white: RANSAC's planes in the summary: $(cat "$dir/err")"
rm -f "$dir/white.pcd"
# --no-skip-rays traces every pixel and writes the same file (the ray skip changes no point).
"$bin" generate --out "$dir/skip.pcd" --roles target --xres 32 --yres 24 --views 8 --json >"$dir/skip.json" \
    2>"$dir/err" || fail "--roles target run failed: $(cat "$dir/err")"
"$bin" generate --out "$dir/noskip.pcd" --roles target --xres 32 --yres 24 --views 8 --no-skip-rays --json \
    >"$dir/noskip.json" 2>"$dir/err" || fail "--no-skip-rays run failed: $(cat "$dir/err")"
cmp -s "$dir/skip.pcd" "$dir/noskip.pcd" || fail "--no-skip-rays wrote a different cloud"
python3 - "$dir" <<'EOF2'
import json, sys
d = sys.argv[1]
on, off = json.load(open(d + "/skip.json")), json.load(open(d + "/noskip.json"))
assert off["rays_traced"] == off["rays"] == 32 * 24 * 8, off
assert 0 < on["rays_traced"] < on["rays"] // 4, on
assert on["points"] == off["points"] > 0, (on, off)
EOF2
# A NaN vertex: by default one error line naming it and no file; with --skip-nonfinite the
# triangle is dropped, the run goes on and a warning gives the count.
nan_scene=$(dirname "$0")/../data/scenes/bad/nan_vertex.json
status=0
"$bin" generate --scene "$nan_scene" --out "$dir/nan.pcd" --views 2 >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 1 ] || fail "NaN vertex accepted without --skip-nonfinite (exit $status)"
grep -qi "nan\|finite" "$dir/err" || fail "NaN vertex error does not say so: $(cat "$dir/err")"
[ "$(wc -l <"$dir/err")" -eq 1 ] || fail "NaN vertex: more than one line: $(cat "$dir/err")"
[ ! -e "$dir/nan.pcd" ] || fail "NaN vertex left an output file"
# A target with one good, one NaN and one zero-area triangle on a 200 m square ground.
cat >"$dir/ground.ply" <<'EOF2'
ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
-100 -100 0
100 -100 0
100 100 0
-100 100 0
3 0 1 2
3 0 2 3
EOF2
cat >"$dir/mixed.ply" <<'EOF2'
ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
element face 3
property list uchar int vertex_indices
end_header
0 0 1
1 0 1
0 1 1
nan 1 1
1 1 1
3 0 1 2
3 0 3 4
3 0 1 1
EOF2
echo '{ "meshes": [ { "file": "ground.ply", "role": "ground" }, { "file": "mixed.ply", "role": "target" } ] }' \
    >"$dir/mixed.json"
status=0
"$bin" generate --scene "$dir/mixed.json" --out "$dir/nan.pcd" --views 2 >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 1 ] || fail "NaN vertex in a mixed mesh accepted without --skip-nonfinite (exit $status)"
[ ! -e "$dir/nan.pcd" ] || fail "NaN vertex left an output file"
"$bin" generate --scene "$dir/mixed.json" --out "$dir/nan.pcd" --xres 16 --yres 16 --views 2 --skip-nonfinite \
    --json >"$dir/nan.json" 2>"$dir/err" || fail "--skip-nonfinite run failed: $(cat "$dir/err")"
grep -q "warning: .*skipped 1 zero-area and 1 non-finite" "$dir/err" ||
    fail "--skip-nonfinite: no warning with the counts: $(cat "$dir/err")"
python3 - "$dir" <<'EOF2'
import json, sys
s = json.load(open(sys.argv[1] + "/nan.json"))
assert s["skipped_nonfinite_triangles"] == 1, s
assert s["skipped_zero_area_triangles"] == 1, s
assert s["rays"] == 16 * 16 * 2 and s["points"] > 0, s
EOF2
# A clean scene gives no warning and zero counts.
! grep -q "warning" "$dir/err.good" || fail "warning on a clean scene: $(cat "$dir/err.good")"
python3 -c "import json,sys; s=json.load(open(sys.argv[1])); assert s['skipped_nonfinite_triangles']==0 and s['skipped_zero_area_triangles']==0, s" "$dir/summary.json"

# The ground warning for the terrain-following filters: with options that make the
# terrain miss the ground (recall low: SMRF calling nearly every cell an object and no
# tolerance, a cloth that falls for one step only) it names the filter and what to try;
# with the defaults under a noisy sensor (recall high) there is none.
for m in smrf csf; do
    thin="--csf-iterations 1"
    [ $m = csf ] || thin="--smrf-slope 0.0001 --smrf-window-m 60 --smrf-threshold-m 0 --smrf-scalar 0"
    "$bin" generate --out "$dir/g.pcd" --xres 48 --yres 48 --views 16 --ground $m $thin --json >"$dir/g.json" 2>"$dir/g.err" || fail "generate --ground $m: $(cat "$dir/g.err")"
    grep -q "warning: generate: ground: $(echo $m | tr a-z A-Z) whitened only .*--$m-threshold-m" "$dir/g.err" ||
        fail "no ground warning for --ground $m with a thin threshold: $(cat "$dir/g.err")"
    # The summary line names the filter that ran and what it found, not RANSAC's planes.
    what="SMRF's terrain"
    [ $m = smrf ] || what="CSF's cloth"
    grep -q "^  ground: [0-9]* points found on $what and whitened, [0-9]* labelled ground;" "$dir/g.err" ||
        fail "--ground $m: the ground line does not name $what: $(cat "$dir/g.err")"
    ! grep -q "planes" "$dir/g.err" || fail "--ground $m: RANSAC's planes in the summary: $(cat "$dir/g.err")"
    python3 -c "import json,sys; s=json.load(open(sys.argv[1])); assert s['ground_recall'] < 0.8 and s['ground_advice'], s" \
        "$dir/g.json" || fail "--ground $m thin threshold: recall or advice"
    "$bin" generate --out "$dir/g.pcd" --xres 48 --yres 48 --views 16 --sensor livox-avia --ground $m \
        --json >"$dir/g.json" 2>"$dir/g.err" || fail "generate --ground $m: $(cat "$dir/g.err")"
    ! grep -q "warning: generate: ground" "$dir/g.err" || fail "ground warning with the defaults: $(cat "$dir/g.err")"
    python3 -c "import json,sys; s=json.load(open(sys.argv[1])); assert s['ground_recall'] >= 0.8 and not s['ground_advice'], s" \
        "$dir/g.json" || fail "--ground $m defaults: recall or advice"
done

# With a noisy sensor the terrain filters' clouds (views corrected, robust levels) are the
# same bytes whatever the thread count.
for m in smrf csf; do
    for t in 1 3; do
        "$bin" generate --out "$dir/t$t.pcd" --xres 48 --yres 48 --views 16 --sensor livox-avia --ground $m \
            --threads $t 2>"$dir/t.err" || fail "generate --threads $t: $(cat "$dir/t.err")"
    done
    cmp -s "$dir/t1.pcd" "$dir/t3.pcd" || fail "--ground $m --sensor livox-avia: --threads 1 and 3 differ"
done

rm -rf "$dir"
echo "cmd_generate_test: ok"
