#!/bin/sh
# tests/bench/ground_isprs_selector_test.sh: `ladarvr bench ground-isprs --selector` on two
# small ISPRS samples of two sites (samp24, samp41; each scored by trees learned on the
# other): the table of configurations and the per-sample table printed, with the default
# set's figures, the oracle's and the selector's for both samples; BENCHMARKS.md left alone;
# --samples outside the 15 and a single site refused in one line.
# Usage: ground_isprs_selector_test.sh LADARVR_BENCH_BINARY SCRATCH_DIR
set -eu
bench=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

(cd "$dir" && "$bench" ground-isprs --selector --samples samp24,samp41) >"$dir/out" 2>"$dir/err" ||
    fail "--selector: $(cat "$dir/err")"
grep -q "^| configuration | mean type I | mean type II | mean total error | mean kappa | samples past CSF" "$dir/out" ||
    fail "no configuration table: $(cat "$dir/out")"
grep -q "^| \`ladarvr ground\` (the default set) | [0-9.]* | [0-9.]* | [0-9.]* | [0-9.]* | " "$dir/out" ||
    fail "no row of the default set: $(cat "$dir/out")"
grep -q "^| oracle, each tile's best of 3 sets (.*), 50 m tiles | " "$dir/out" || fail "no oracle row"
grep -q "^| selector, 3 sets (.*), 50 m tiles, pairwise trees | " "$dir/out" || fail "no selector row"
grep -q "^| sample | \`ladarvr ground\` | oracle | selector | per patch | CSF published |$" "$dir/out" ||
    fail "no per-sample table: $(cat "$dir/out")"
grep -q "^| samp24 | [0-9.]* ([0-9.]*) | [0-9.]* ([0-9.]*) | [0-9.]* ([0-9.]*) | [0-9.]* ([0-9.]*) | 2.87 |$" "$dir/out" || fail "no samp24 row"
grep -q "^| samp41 | [0-9.]* ([0-9.]*) | [0-9.]* ([0-9.]*) | [0-9.]* ([0-9.]*) | [0-9.]* ([0-9.]*) | 5.14 |$" "$dir/out" || fail "no samp41 row"
# `ladarvr ground`'s figure for samp24 as the main table gives it.
grep -q "^| samp24 | 4.14 (89.6) | " "$dir/out" || fail "samp24's default-set figure is not 4.14: $(grep samp24 "$dir/out")"
[ "$(grep -c "^| samp[0-9]" "$dir/out")" -eq 2 ] || fail "not two sample rows"
[ ! -e "$dir/BENCHMARKS.md" ] || fail "--selector wrote BENCHMARKS.md"

# usage STATUS PATTERN ARGS...: one line naming what is allowed.
usage() {
    expect=$1
    pattern=$2
    shift 2
    status=0
    (cd "$dir" && "$bench" ground-isprs "$@") >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq "$expect" ] || fail "$*: exit $status, expected $expect: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "$*: not one line: $(cat "$dir/err")"
    grep -q -e "$pattern" "$dir/err" || fail "$*: error does not match '$pattern': $(cat "$dir/err")"
}
usage 1 "--samples: 'samp99' is not an ISPRS sample; allowed samp11" --selector --samples samp24,samp99
usage 1 "--selector: the samples come from 1 site; allowed samples of at least two sites" --selector \
    --samples samp21,samp24
usage 2 "--samples requires --selector" --samples samp24,samp41
rm -rf "$dir"
