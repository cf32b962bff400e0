#!/bin/sh
# tests/app/cmd_cli_test.sh: the command-line conventions of `ladarvr` as a user meets them.
# Usage: cmd_cli_test.sh LADARVR_BINARY SCRATCH_DIR SOURCE_DIR PROJECT_VERSION
#  - --version prints the project's version, exit 0;
#  - usage errors (unknown or missing subcommand, with or without --help, unknown or
#    repeated option, malformed or EMPTY values, a missing argument or either-or option)
#    print one line `ladarvr: error: ...` with a --help hint, exit 2;
#  - numbers beyond what float/double can carry are refused in one short line, exit 1;
#  - output that cannot reach stdout (/dev/full) is one error line, exit 1;
#  - output folders are created (mkdir -p), a file in the way is refused;
#  - `scene info` measures the demo scene; `generate` warns about misplaced targets.
set -eu
bin=$1
dir=$2
src=$3
version=$4
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
small="--xres 16 --yres 16 --views 4"

# run EXPECTED_STATUS ARGS...: runs in $dir/cwd, stdout in $dir/out, stderr in $dir/err.
run() {
    expect=$1
    shift
    rm -rf "$dir/cwd" && mkdir "$dir/cwd"
    status=0
    (cd "$dir/cwd" && "$bin" "$@") >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq "$expect" ] || fail "ladarvr $* exited $status, expected $expect: $(cat "$dir/err")"
}

# one_error PATTERN: stderr is exactly one line, `ladarvr: error: ...` matching PATTERN.
one_error() {
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "not one line: $(cat "$dir/err")"
    grep -q '^ladarvr: error: ' "$dir/err" || fail "no 'ladarvr: error:' prefix: $(cat "$dir/err")"
    grep -q -e "$1" "$dir/err" || fail "error does not match '$1': $(cat "$dir/err")"
    [ "$(wc -c <"$dir/err")" -lt 400 ] || fail "error longer than 400 characters: $(cat "$dir/err")"
    left=$(ls -A "$dir/cwd")
    [ -z "$left" ] || fail "left files behind in the working folder: $left"
}

usage() {  # usage PATTERN ARGS...: exit 2, one line with the hint
    pattern=$1
    shift
    run 2 "$@"
    one_error "$pattern"
    grep -q "(see 'ladarvr.* --help')" "$dir/err" || fail "no --help hint: $(cat "$dir/err")"
}

# --version, --help
run 0 --version
[ "$(cat "$dir/out")" = "ladarvr $version" ] || fail "--version printed '$(cat "$dir/out")', expected 'ladarvr $version'"
run 0 generate --help
grep -q -e '--no-skip-rays  ' "$dir/out" || fail "generate --help lacks a plain --no-skip-rays"
grep -q '{false}' "$dir/out" && fail "generate --help shows a '{false}' default"
grep -q 'Exit status: 0 success; 1 .*2 usage error.*70 internal error' "$dir/out" || fail "no exit statuses in --help"

# Usage errors: exit 2, one line.
usage "unknown subcommand 'frobnicate'; allowed: generate, metric, view, scene, detect, train, corpus, study" frobnicate
usage "a subcommand is required" 
usage "scene: unknown subcommand 'inf'" scene inf
# --help after an unknown subcommand is the same usage error, not the top-level help.
usage "unknown subcommand 'nosuchcommand'; allowed: generate, metric" nosuchcommand --help
usage "unknown subcommand 'nosuchcommand'" nosuchcommand -h
usage "unknown subcommand 'nosuchcommand'" nosuchcommand --version
usage "scene: unknown subcommand 'inf'" scene inf --help
run 0 scene --help
grep -q "info" "$dir/out" || fail "scene --help lacks its subcommands: $(cat "$dir/out")"
run 0 scene info --help
usage "unknown option: --bogus" --bogus
usage "generate: unknown option: --bogus" generate --bogus
usage "generate: unexpected argument: x y" generate x y
usage "generate: --xres is given 2 times; allowed once" generate --xres 2 --xres 3
usage "generate: --xres: '1.5' is not a whole number" generate --xres 1.5
usage "generate: --seed: '-1' is not a whole number >= 0" generate --seed -1
usage "generate: --alpha-deg: 'abc' is not a number" generate --alpha-deg abc
usage "generate: --xres: '99999999999' is out of range" generate --xres 99999999999
# A missing positional names itself and what it takes; an either-or names its options.
usage "detect: missing cloud: the cloud (PCD, PLY, LAS or LAZ) (see" detect
usage "ground: missing in: the input clouds" ground
usage "ground: one of --out, --out-dir is required (see" ground x.las
usage "ground: more than one of --out, --out-dir given; allowed exactly one of them" ground x.las --out a.las --out-dir b

# Every option refuses an empty value (CLI11 alone reads '' as 0).
usage "generate: --alpha-deg: the value is empty" generate --alpha-deg ''
usage "generate: --alpha-deg: the value is missing" generate --alpha-deg=
usage "generate: --alpha-deg: the value is missing" generate --alpha-deg
usage "generate: --threads: the value is empty" generate --threads ''
usage "generate: --centre: the value is empty" generate --centre ''
usage "generate: --roles: the value is empty" generate --roles ''
usage "generate: --out: the value is empty" generate --out ''
usage "generate: --scene: the value is empty" generate --scene ''
usage "metric: --altitude-m: the value is empty" metric --altitude-m ''
usage "metric: --look-at: the value is empty" metric --look-at ''
usage "metric: --out: the value is empty" metric --out ''
usage "view: cloud: the value is empty" view ''
usage "view: --screenshot: the value is empty" view --screenshot ''
usage "scene info: scene: the value is empty" scene info ''

# Output that cannot reach stdout (a full disk) fails the run in one line, exit 1:
# --version's one line, and `scene info`'s lines, more than stdio's buffer holds.
for args in "--version" "scene info"; do
    status=0
    # shellcheck disable=SC2086 # the words of $args are the arguments
    "$bin" $args >/dev/full 2>"$dir/err" || status=$?
    [ "$status" -eq 1 ] || fail "$args >/dev/full exited $status, expected 1"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "$args >/dev/full: not one line: $(cat "$dir/err")"
    grep -qx "ladarvr: error: stdout: write failed: No space left on device; the output is incomplete" \
        "$dir/err" || fail "$args >/dev/full: $(cat "$dir/err")"
done

# The benchmarks are their own program (tests/bench/cli_test.sh): not in --help, and
# `ladarvr bench` says where they are.
run 0 --help
grep -q "^ *bench " "$dir/out" && fail "--help lists bench: $(cat "$dir/out")"
run 2 bench generate --quick
one_error "bench: the benchmarks are not part of this program; run './ladarvr bench WHAT' in the source checkout"

# Numbers beyond float / double range: exit 1, one short line naming the option.
run 1 generate --out x.pcd --altitude-m 1e12
one_error "altitude_m (--altitude-m) = 1e+12: allowed (0, 10000000\]"
run 1 generate --out x.pcd --overlap-m -1e300
one_error "overlap_m (--overlap-m) = -1e+300: allowed \[-10000000, 10000000\]"
run 1 generate --out x.pcd --centre 1e300,0,0
one_error "centre (--centre) = 1e+300,0,0: allowed x,y,z in \[-1000000000, 1000000000\]"
run 1 generate --out x.pcd --centre 2e7,0,0
one_error "the drone flies .* m from the scene's origin around C .*allowed <= 10000000 m"
run 1 generate --out x.pcd --alpha-deg 86 --altitude-m 1e6
one_error "drone radius .* = .*: allowed <= 10000000 m"
run 1 generate --out x.pcd --memory-mb 1e308
one_error "--memory-mb = 1e+308: allowed \[1, 1048576\]"

# A mesh placed at 1e308 (JSON allows it; double holds it; nothing downstream could).
mkdir -p "$dir/far"
cat >"$dir/far/scene.json" <<EOF
{ "meshes": [ { "file": "$src/tests/data/scenes/basic/box.obj", "role": "target", "position": [1e308, 0, 0] } ] }
EOF
run 1 generate --scene "$dir/far/scene.json" --out x.pcd
one_error "meshes\[0\] ('.*box.obj'): 'position' element 0 is 1e+308; allowed: \[-1000000000, 1000000000\] (world metres)"
cat >"$dir/far/scene.json" <<EOF
{ "meshes": [ { "file": "$src/tests/data/scenes/basic/ground.obj", "role": "ground" },
              { "file": "$src/tests/data/scenes/basic/box.obj", "role": "target", "position": [5e7, 0, 0] } ] }
EOF
run 1 scene info "$dir/far/scene.json"
one_error "meshes\[1\] ('.*box.obj'): vertex 0 lies 50000000 m from the origin .*allowed: within 10000000 m"

# Output folders are created like mkdir -p; a file where a folder should be is refused.
run 0 generate --out "$dir/made/a/b/x.pcd" $small
[ -s "$dir/made/a/b/x.pcd" ] || fail "generate --out into new folders wrote no file"
: >"$dir/made/file"
run 1 generate --out "$dir/made/file/x.pcd" $small
one_error "generate: --out '.*/made/file/x.pcd': '.*/made/file' exists and is not a folder"
[ -f "$dir/made/file" ] || fail "the file in the way was replaced"
run 1 metric --out "$dir/made/file/metric" --views 1
one_error "metric: --out '.*/made/file/metric': '.*/made/file' exists and is not a folder"
run 1 view --no-xr --screenshot "$dir/made/file/shot.png"
one_error "view: --screenshot '.*/made/file/shot.png': '.*/made/file' exists and is not a folder"
run 1 view --no-xr --log-json "$dir/made/file/log.json"
one_error "view: --log-json '.*/made/file/log.json': '.*/made/file' exists and is not a folder"

# scene info on the demo scene: the tank (7.0 x 3.5 x 2.5 m, its barrel 3.6 m beyond the
# bow, yawed 20 deg: a 10.60 x 5.68 x 2.50 m box) standing on the 300 x 300 m ground.
run 0 scene info
grep -q "55 meshes, 96162 triangles" "$dir/out" || fail "scene info: counts: $(head -1 "$dir/out")"
grep -q "^target: size 10.60 x 5.68 x 2.50 m" "$dir/out" || fail "scene info: target size: $(cat "$dir/out")"
grep -q "warning" "$dir/out" && fail "scene info warns about the demo scene: $(cat "$dir/out")"
run 0 scene info "$src/assets/demo/scene.json" --json
python3 - "$dir/out" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
assert len(s["meshes"]) == 55 and s["triangles"] == 96162, (len(s["meshes"]), s["triangles"])
ground = s["meshes"][0]
assert ground["role"] == "ground" and ground["file"].endswith("ground_flat.glb"), ground
assert abs(ground["size_m"][0] - 300) < 1e-3 and abs(ground["size_m"][1] - 300) < 1e-3, ground
tank = s["meshes"][1]
assert tank["role"] == "target" and tank["triangles"] == 112 and tank["position"] == [0, 0, -0.05], tank
t = s["target"]
for got, want in zip(t["size_m"], (10.60, 5.68, 2.50)):
    assert abs(got - want) < 0.01, t
assert abs(t["bottom_z_world"] + 0.05) < 1e-4, t
# Nearly flat ground (relief < 0.45 m): the tank's tracks sit within 0.2 m of it.
assert -0.2 < t["height_above_ground_m"] < 0.2, t
assert abs(t["bottom_z_world"] - t["ground_z_world"] - t["height_above_ground_m"]) < 1e-9, t
assert s["warnings"] == [], s["warnings"]
EOF

# generate's warnings: one line each on stderr, exit 0. Ground: 20 x 20 m at z = 0.
# scene NAME TARGET_JSON_EXTRA: a scene with the basic ground and the unit box as target.
scene() {
    mkdir -p "$dir/$1"
    cat >"$dir/$1/scene.json" <<EOF
{ "meshes": [ { "file": "$src/tests/data/scenes/basic/ground.obj", "role": "ground" },
              { "file": "$src/tests/data/scenes/basic/box.obj", "role": "target", $2 } ] }
EOF
}
# warns SCENE PATTERN [ARGS]: generate on it exits 0 and warns with PATTERN.
warns() {
    s=$1
    pattern=$2
    shift 2
    run 0 generate --scene "$dir/$s/scene.json" --out "$dir/$s/x.pcd" $small "$@"
    grep -q "^ladarvr: warning: generate: .*$pattern" "$dir/err" || fail "$s: no warning '$pattern': $(cat "$dir/err")"
}
# A box modelled in millimetres: 1000 m wide, covering the whole ground.
scene millimetres '"position": [-500, -500, 0], "scale": 1000'
warns millimetres "the target is 1000.00 m x 1000.00 m x 1000.00 m, larger than 30 m: is the mesh in millimetres"
grep -q "rays missed" "$dir/err" && fail "millimetres: a miss warning although every ray hits the box"
# 5 km above the ground: the default orbit (C on the ground under it) sees nothing of it.
scene high '"position": [-0.5, -0.5, 5000]'
warns high "the target floats 5000.00 m above the ground under its centre"
run 0 scene info "$dir/high/scene.json" --json
python3 - "$dir/out" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
assert abs(s["target"]["height_above_ground_m"] - 5000) < 1e-6, s["target"]
assert len(s["warnings"]) == 1 and "floats 5000.00 m" in s["warnings"][0], s["warnings"]
EOF
scene sunk '"position": [-0.5, -0.5, -3]'
warns sunk "the target sinks 3.00 m below the ground under its centre"
scene off '"position": [100, 0, 0]'
warns off "no ground mesh lies under the target's centre"
# Most rays miss: the 20 m ground under an orbit whose footprint is ~70 m long.
scene small '"position": [-0.5, -0.5, 0]'
warns small "of 1024 rays missed the scene (more than half)"
grep -q "warning: .*target" "$dir/err" && fail "small: a target warning for a well-placed target: $(cat "$dir/err")"
# ... but not when only the target is cast (misses expected), nor on the demo scene.
run 0 generate --scene "$dir/small/scene.json" --out "$dir/small/t.pcd" $small --roles target
grep -q "rays missed" "$dir/err" && fail "--roles target warned: $(cat "$dir/err")"
run 0 generate --out "$dir/demo.pcd" $small
grep -q "warning" "$dir/err" && fail "the demo scene warned: $(cat "$dir/err")"
echo "cmd_cli_test: all checks passed"
