#!/bin/sh
# tests/app/sensor_options_test.sh: the sensor options of `ladarvr generate`.
# Usage: sensor_options_test.sh LADARVR_BINARY SCRATCH_DIR
# Bad values: exit 1, one line naming the option and the allowed range, no file left.
# A preset's value is overridden by the option given explicitly, in either order.
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
    grep -q -F -e "$expect" "$dir/err" || fail "generate $*: error does not say $expect: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "generate $*: more than one line: $(cat "$dir/err")"
    left=$(ls -A "$dir" | grep -v -e '^err$' -e '^out$' || true)
    [ -z "$left" ] || fail "generate $* left files behind: $left"
}

check_bad "(--range-noise-m) = -1: allowed [0, 100] metres" --range-noise-m -1
check_bad "(--pose-noise-m) = 1000: allowed [0, 100] metres" --pose-noise-m 1000
check_bad "(--attitude-noise-deg) = 11: allowed [0, 10] degrees" --attitude-noise-deg 11
check_bad "(--max-range-m) = -5: allowed [0, 10000000]" --max-range-m -5
check_bad "(--min-intensity) = 70000: allowed [0, 65535]" --min-intensity 70000
check_bad "(--beam-divergence-mrad) = -0.5: allowed [0, 100] mrad" --beam-divergence-mrad -0.5
check_bad "(--footprint-quality) = 0: allowed [1, 5]" --footprint-quality 0
check_bad "(--max-returns) = 16: allowed [1, 15]" --max-returns 16
check_bad "--returns: 'second' is not one of first, last, strongest, all" --returns second
check_bad "--sensor 'lidar' is not one of ideal, riegl-vux1uav, livox-avia" --sensor lidar
# A bad explicit value is refused even where the preset's own is fine.
check_bad "(--range-noise-m) = -1" --sensor livox-avia --range-noise-m -1

# livox-avia's 450 m range loses the far edge of the paper's footprint (ranges up to
# 452 m); --max-range-m 0 lifts the limit, whichever comes first on the line.
misses() {
    name=$1
    shift
    "$bin" generate --out "$dir/$name.pcd" --views 4 --xres 32 --yres 32 --white --json "$@" 2>/dev/null |
        sed -n 's/^  "misses": \([0-9]*\),$/\1/p'
}
preset=$(misses a --sensor livox-avia)
after=$(misses b --sensor livox-avia --max-range-m 0)
before=$(misses c --max-range-m 0 --sensor livox-avia)
[ -n "$preset" ] && [ -n "$after" ] || fail "no misses in the JSON summary"
[ "$preset" -gt "$after" ] || fail "--max-range-m 0 did not override livox-avia's range ($preset vs $after misses)"
[ "$after" -eq "$before" ] || fail "the override depends on the order of the options ($after vs $before)"
echo "sensor options: ok ($preset misses with the preset, $after without its range limit)"
