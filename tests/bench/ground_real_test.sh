#!/bin/sh
# tests/bench/ground_real_test.sh BENCH LADARVR SCRATCH: `ladarvr bench ground-real` on
# tests/data/real's five files whose producer classified the ground: a row per file and
# the means, BENCHMARKS.md left alone with --no-md; sample_c's SMRF total error is the one
# `ladarvr ground --json` gives for the same file (the bench classifies as the command
# does); a file whose producer classified no ground, or a cloud without a producer's
# classes, is one line naming it.
set -eu
bench=$1
app=$2
dir=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
data=$(cd "$(dirname "$0")/../data/real" && pwd)

(cd "$dir" && "$bench" ground-real --no-md) >"$dir/out" 2>"$dir/err" || fail "ground-real: $(cat "$dir/err")"
cat "$dir/out"
grep -q "^## Ground against the producers' classes (ladarvr bench ground-real)" "$dir/out" || fail "no heading"
for f in 4_6_crop.las sample_c.las hexbin-crop.las mvk-thin.las warsaw_small.las; do
    grep -q "^| $f | .* |$" "$dir/out" || fail "no row for $f"
done
grep -q "^| 4_6_crop.las | US survey feet .* |$" "$dir/out" || fail "4_6_crop.las not in feet"
grep -q "^| mean | | | | | " "$dir/out" || fail "no mean row"
[ ! -e "$dir/BENCHMARKS.md" ] || fail "--no-md wrote BENCHMARKS.md"

# The command's counts on sample_c (every point of it decided by its producer).
"$app" ground "$data/sample_c.las" --out "$dir/c.las" --json >"$dir/json" 2>"$dir/err" || fail "ground: $(cat "$dir/err")"
field() { sed -n "s/^ *\"$1\": \([0-9.]*\),*$/\1/p" "$dir/json" | head -1; }
total=$(awk -v n="$(field points)" -v f="$(field ground_points)" -v l="$(field input_ground_points)" \
    -v k="$(field input_ground_points_kept)" 'BEGIN { printf "%.2f", 100 * ((l - k) + (f - k)) / n }')
row=$(grep "^| sample_c.las | " "$dir/out")
[ "$(echo "$row" | awk -F'|' '{ gsub(/ /, "", $9); print $9 }')" = "$total" ] ||
    fail "sample_c: the bench's SMRF total is not the command's $total %: $row"

# A survey whose producer left every point unclassified (class 0).
if "$bench" ground-real --no-md --in "$data/CSite2_orig-utm.laz" >"$dir/out" 2>"$dir/err"; then
    fail "a survey without ground classes accepted"
fi
grep -q "CSite2_orig-utm.laz: its producer classified no point as ground (class 2); allowed " "$dir/err" ||
    fail "unclear refusal: $(cat "$dir/err")"
# A cloud without a producer's classes (PLY).
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n' \
    >"$dir/plain.ply"
if "$bench" ground-real --no-md --in "$dir/plain.ply" >"$dir/out" 2>"$dir/err"; then fail "a PLY cloud accepted"; fi
grep -q "plain.ply: holds no producer's classes (a cloud of ours, or not LAS/LAZ/COPC); allowed " "$dir/err" ||
    fail "unclear refusal of a PLY cloud: $(cat "$dir/err")"
echo "ground_real_test: ok"
