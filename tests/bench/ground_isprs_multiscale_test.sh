#!/bin/sh
# tests/bench/ground_isprs_multiscale_test.sh: `ladarvr bench ground-isprs --multiscale` on two
# small ISPRS samples (samp24, samp41): the table has its header, `ladarvr ground`'s row (samp24
# at 4.14 % as the main table gives it), one row per variant with every figure a percentage,
# the published CSF row; a second run prints the same table; BENCHMARKS.md is left alone;
# --multiscale with --selector is refused in one line.
# Usage: ground_isprs_multiscale_test.sh LADARVR_BENCH_BINARY SCRATCH_DIR
set -eu
bench=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

for run in 1 2; do
    (cd "$dir" && "$bench" ground-isprs --multiscale --samples samp24,samp41) >"$dir/out$run" 2>"$dir/err$run" ||
        fail "--multiscale: $(cat "$dir/err$run")"
done
out="$dir/out1"
grep -q "^| variant | mean type I | mean type II | mean total error | mean kappa | samples past CSF + 1 | samp24 | samp41 |$" "$out" ||
    fail "no table header: $(cat "$out")"
grep -q "^| \`ladarvr ground\` (SMRF) | [0-9.]* | [0-9.]* | [0-9.]* | [0-9.]* | [0-9 a-z]* | 4.14 | 5.06 |$" "$out" ||
    fail "no row of \`ladarvr ground\` with samp24 4.14 and samp41 5.06: $(grep ladarvr "$out")"
grep -q "^| MCC, lambda 1 m, tolerance 0.3 m " "$out" || fail "no MCC row"
grep -q "^| pyramid 32-1 m, tolerance 0.3 m + 0.05 x cell " "$out" || fail "no pyramid row"
grep -q "^| SMRF, then MCC's test on its ground " "$out" || fail "no row of MCC on SMRF's answer"
grep -q "^| SMRF, ground given back by the pyramid " "$out" || fail "no row of the pyramid on SMRF's answer"
grep -q "^| CSF published | | | 4.00 | | | 2.87 | 5.14 |$" "$out" || fail "no CSF row"
# Every row: four means, then the two samples' totals, each a percentage (kappa may be
# negative in principle, but not for any of these filters on these samples).
rows=$(grep -c "^| [A-Z\`p].* | [0-9.]* | [0-9.]* | [0-9.]* | [0-9.]* | [0-9 a-z]* | [0-9.]* | [0-9.]* |$" "$out")
[ "$rows" -ge 15 ] || fail "fewer than 15 rows of figures: $rows"
awk -F'|' '/^\| [A-Z`p]/ && $3 ~ /[0-9]/ {
    for (c = 3; c <= NF - 1; ++c) {
        if (c == 7) continue
        v = $c + 0
        if (v < 0 || v > 100) { print "out of range: " $0; exit 1 }
    }
}' "$out" || fail "a figure outside 0-100"
cmp -s "$dir/out1" "$dir/out2" || fail "two runs differ: $(diff "$dir/out1" "$dir/out2")"
[ ! -e "$dir/BENCHMARKS.md" ] || fail "--multiscale wrote BENCHMARKS.md"

status=0
(cd "$dir" && "$bench" ground-isprs --multiscale --selector) >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 2 ] || fail "--multiscale --selector: exit $status, expected 2"
[ "$(wc -l <"$dir/err")" -eq 1 ] || fail "--multiscale --selector: not one line: $(cat "$dir/err")"
grep -q -E -e "--(selector|multiscale) excludes --(selector|multiscale)" "$dir/err" || fail "--multiscale --selector: $(cat "$dir/err")"
rm -rf "$dir"
