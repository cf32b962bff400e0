#!/usr/bin/env bash
# tests/safety/cli_messages_test.sh: what `ladarvr` echoes of hostile values, and how it
# reads numbers typed on the command line.
# Usage: cli_messages_test.sh LADARVR_BINARY SCRATCH_DIR
# Every error is one line on stderr: control bytes (a newline, ESC[2J that clears the
# terminal) shown as \xNN, a value of any length capped with its middle cut so the end
# (what is allowed) stays. Floating-point options take decimal notation only, as the
# integer options and the files do; an option that would change nothing is refused.
set -euo pipefail
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
esc=$(printf '\033')
small=(--xres 8 --yres 8 --views 2)                 # quick runs where main accepted a value
fast=(--views 2 --width 16 --height 16 --no-exact)

# Runs the CLI expecting exit status $1 and one stderr line containing $2 (fixed text),
# with no control byte and at most 2,100 bytes.
one_line() {
    local want=$1 expect=$2
    shift 2
    local status=0
    "$bin" "$@" >"$dir/out.txt" 2>"$dir/err.txt" || status=$?
    [ "$status" -eq "$want" ] || fail "${*:1:3}... exited $status, expected $want: $(head -c 600 "$dir/err.txt")"
    grep -q -F -e "$expect" "$dir/err.txt" || fail "${*:1:3}...: error does not say '$expect': $(head -c 600 "$dir/err.txt")"
    [ "$(wc -l <"$dir/err.txt")" -eq 1 ] || fail "${*:1:3}...: not one line: $(head -c 600 "$dir/err.txt" | cat -A)"
    ! LC_ALL=C grep -q '[[:cntrl:]]' "$dir/err.txt" || fail "${*:1:3}...: a control byte reached stderr: $(cat -A "$dir/err.txt" | head -c 600)"
    [ "$(wc -c <"$dir/err.txt")" -le 2100 ] || fail "${*:1:3}...: a $(wc -c <"$dir/err.txt")-byte error line"
}

# --- control bytes and long values in what an error quotes ---
one_line 1 "metric: --rasterizer 'gpu\\x1b[2J\\x0aok': allowed compute, raster" \
    metric --rasterizer "gpu${esc}[2J
ok" --out "$dir/m"
one_line 2 "unknown subcommand 'gen\\x1b[2J'" "gen${esc}[2J"
one_line 2 "unknown option: --x\\x1b[31m\\x07" generate "--x${esc}[31m$(printf '\a')"
# 100,000 characters: the start and the end of the message stay, the middle is cut.
long=$(head -c 100000 /dev/zero | tr '\0' a)
one_line 1 "': allowed compute, raster" metric --rasterizer "$long" --out "$dir/m"
grep -q -F "metric: --rasterizer 'aaa" "$dir/err.txt" || fail "the start of a long message was lost"
grep -q -F "a ... a" "$dir/err.txt" || fail "a long message was not cut in the middle: $(head -c 300 "$dir/err.txt")"
# Valid UTF-8 is text and is kept; a byte that is not UTF-8 is escaped.
one_line 1 "--rasterizer 'gpü\\xff'" metric --rasterizer "gpü$(printf '\377')" --out "$dir/m"

# --- floating-point options: decimal notation only ---
one_line 2 "generate: --altitude-m: '0x10' is not a number" generate "${small[@]}" --altitude-m 0x10 --out "$dir/g.pcd"
one_line 2 "metric: --radius-m: '0x1p4' is not a number" metric "${fast[@]}" --radius-m 0x1p4 --out "$dir/m"
one_line 2 "generate: --altitude-m: 'inf' is not a number" generate "${small[@]}" --altitude-m inf --out "$dir/g.pcd"
one_line 2 "generate: --altitude-m: 'nan' is not a number" generate "${small[@]}" --altitude-m nan --out "$dir/g.pcd"
one_line 2 "generate: --altitude-m: '1e999' is beyond the range of a double" generate "${small[@]}" --altitude-m 1e999 --out "$dir/g.pcd"
one_line 2 "generate: --altitude-m: '.' is not a number" generate "${small[@]}" --altitude-m . --out "$dir/g.pcd"
one_line 2 "generate: --altitude-m: ' 16' is not a number" generate "${small[@]}" --altitude-m " 16" --out "$dir/g.pcd"
[ ! -e "$dir/g.pcd" ] || fail "a refused generate wrote its output"
# x,y,z options: exactly three decimal numbers.
for bad in 1,2,3,junk 1,2,3, 1,2 0x1,2,3 "1, 2,3" 1,2,nan ,1,2,3; do
    one_line 1 "metric: --look-at '$bad': allowed three finite numbers x,y,z (world metres)" \
        metric "${fast[@]}" --look-at "$bad" --out "$dir/m"
    one_line 1 "generate: --centre '$bad': allowed three finite numbers x,y,z (world metres)" \
        generate "${small[@]}" --centre "$bad" --out "$dir/g.pcd"
done
[ ! -e "$dir/m" ] && [ ! -e "$dir/g.pcd" ] || fail "a refused run wrote its output"
# Decimal forms that are numbers still are.
"$bin" generate "${small[@]}" --altitude-m +3e2 --alpha-deg 45. --centre=-1.5,.5,2E0 \
    --out "$dir/ok.pcd" >/dev/null 2>"$dir/err.txt" || fail "decimal notation refused: $(cat "$dir/err.txt")"

# --- an option that changes nothing on its own is refused, not ignored ---
one_line 2 "metric: --trace-step-s requires --trace" metric "${fast[@]}" --trace-step-s 0.5 --out "$dir/m"
one_line 2 "metric: --trace-step-s: 'nan' is not a number" metric "${fast[@]}" --trace-step-s nan --out "$dir/m"
[ ! -e "$dir/m" ] || fail "a refused metric run wrote its output"

# --- candidate boxes far outside any world frame ---
cands() { printf '{"candidates": [{"id": "c1", "centre": %s, "size_m": %s, "score": 0.5}]}\n' "$1" "$2" >"$dir/c.json"; }
cands "[1e300, 0, 0]" "[1, 1, 1]"
one_line 1 "candidates[0].centre[0] is 1e+300; allowed: [x, y, z] in world metres, each in [-1000000000, 1000000000]" \
    view --no-xr --candidates "$dir/c.json" --frames 1
cands "[0, 0, 0]" "[1, 1e300, 1]"
one_line 1 "candidates[0].size_m[1] is 1e+300; allowed:" view --no-xr --candidates "$dir/c.json" --frames 1
echo "safety.cli_messages: all cases passed"
