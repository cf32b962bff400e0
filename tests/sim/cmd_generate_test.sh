#!/bin/sh
# tests/sim/cmd_generate_test.sh: `ladarvr generate` as a user runs it.
# Usage: cmd_generate_test.sh LADARVR_BINARY SCRATCH_DIR
# Bad parameters: exit 1, one error line naming the option, no file left behind.
# A small good run: the JSON summary has the required keys and matches the file.
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
check_bad "does not exist" --scene "$dir/missing.json"

# A destination in a missing directory fails before any work.
status=0
"$bin" generate --out "$dir/nowhere/x.pcd" --views 2 2>"$dir/err" || status=$?
[ "$status" -eq 1 ] || fail "missing output directory accepted"

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
grep -q "drone radius 326.12 m" "$dir/err" || fail "human summary lacks the drone radius: $(cat "$dir/err")"
rm -rf "$dir"
echo "cmd_generate_test: ok"
