#!/bin/sh
# tests/bench/detect_families_test.sh: `ladarvr bench detect --families test` end to end
# (seconds; its figures are not checked, only that each part is there and adds up): the
# families held out on the synthetic scenes and on real places (ISPRS sites made scenes,
# trained on one site and evaluated on another), the density bands holding every
# evaluation cloud at each keep fraction, the models kept in --tmp, the section and the
# precision-recall picture written beside --md with the file's other sections kept.
# Usage: detect_families_test.sh LADARVR_BENCH_BINARY SCRATCH_DIR
set -eu
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

printf '# Benchmarks\n\n## Other section\n\nkept as it is\n' >"$dir/BENCHMARKS.md"
(cd "$dir" && "$bin" detect --families test --threads 2 --tmp "$dir/work" --md "$dir/BENCHMARKS.md") \
    >"$dir/out" 2>"$dir/err" || fail "detect --families test: $(tail -5 "$dir/err")"

grep -q "^Test configuration (\`--families test\`" "$dir/out" || fail "no configuration line: $(head -3 "$dir/out")"
# Two tables of families held out (the scenes', the real places'), each pooling 2 clouds.
[ "$(grep -c '^| \*\*all families\*\* | 2 | ' "$dir/out")" -eq 2 ] || fail "not two pooled rows of 2 clouds"
[ "$(grep -c '^| car | 1 | ' "$dir/out")" -eq 2 ] || fail "not two car rows of 1 cloud"
grep -q "Every model trained on CSite3 ([0-9.]* points/m², band under 3) and is evaluated on CSite2 (" "$dir/out" ||
    fail "the real places are not named with their density: $(grep 'Real places as' "$dir/out")"
grep -q "real place CSite3: scene from .*tests/data/real/CSite3_orig-utm.laz" "$dir/err" || fail "CSite3 not made"
[ -f "$dir/work/eval_car_place_CSite2/manifest.jsonl" ] || fail "no evaluation corpus on CSite2"
[ -f "$dir/work/train_car_place_CSite3/manifest.jsonl" ] || fail "no training corpus on CSite3"
[ ! -e "$dir/work/eval_car_place_CSite3" ] && [ ! -e "$dir/work/train_car_place_CSite2" ] ||
    fail "a site is used on both sides"
# The density table: seven bands; every cloud (2 scenes, 2 real places, 2 dense) at five
# keep fractions falls in one, 30 in all.
grep -q "^| points/m² on the target | clouds (scenes / real places / dense) |" "$dir/out" || fail "no density table"
[ "$(grep -c -E '^\| (under 3|3-10|10-30|30-100|100-300|300-1,000|1,000 and more) \| ' "$dir/out")" -eq 7 ] ||
    fail "not seven density bands"
total=$(grep -E '^\| (under 3|3-10|10-30|30-100|100-300|300-1,000|1,000 and more) \| [0-9]' "$dir/out" |
    awk -F'|' '{ split($3, n, " "); s += n[1] } END { print s }')
[ "$total" -eq 30 ] || fail "the density bands hold $total clouds, not 30"
for m in without_car without_tank all; do
    [ -f "$dir/work/models/$m.ldm" ] || fail "no model $m.ldm kept"
done
grep -q "^## Detector on vehicle families it never saw (ladarvr bench detect --families)$" "$dir/BENCHMARKS.md" ||
    fail "no section written"
grep -q "^kept as it is$" "$dir/BENCHMARKS.md" || fail "the other section was not kept"
grep -q "<svg" "$dir/docs/img/detect_families_pr.svg" || fail "no precision-recall picture"
rm -rf "$dir"
echo "bench detect_families_test: all checks passed"
