#!/bin/sh
# tests/bench/cli_test.sh: the benchmark programs' executable as `./ladarvr bench` runs it.
# Usage: cli_test.sh LADARVR_BENCH_BINARY SCRATCH_DIR
#  - --help lists every benchmark and reads as `ladarvr bench`;
#  - usage errors print one line `ladarvr: error: bench ...` naming `ladarvr bench ... --help`, exit 2;
#  - `all --dry-run` runs each step as this same executable, without a `bench` word.
set -eu
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# run EXPECTED_STATUS ARGS...: stdout in $dir/out, stderr in $dir/err.
run() {
    expect=$1
    shift
    status=0
    (cd "$dir" && "$bin" "$@") >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq "$expect" ] || fail "ladarvr-bench $* exited $status, expected $expect: $(cat "$dir/err")"
}

# usage PATTERN ARGS...: exit 2, one line `ladarvr: error: PATTERN` with the --help hint.
usage() {
    pattern=$1
    shift
    run 2 "$@"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "$*: not one line: $(cat "$dir/err")"
    grep -q -e "^ladarvr: error: $pattern" "$dir/err" || fail "$*: error does not match '$pattern': $(cat "$dir/err")"
    grep -q "(see 'ladarvr bench.* --help')" "$dir/err" || fail "$*: no --help hint: $(cat "$dir/err")"
}

run 0 --help
grep -q "ladarvr bench" "$dir/out" || fail "--help does not read as 'ladarvr bench': $(cat "$dir/out")"
for what in generate metric view peers fuzz all mutants detect corpus index; do
    grep -q "^  $what  " "$dir/out" || fail "--help does not list $what: $(cat "$dir/out")"
done
run 0 generate --help
grep -q -e "--quick" "$dir/out" || fail "generate --help lacks --quick"
grep -q -e "--only" "$dir/out" || fail "generate --help lacks --only"

usage "bench: a subcommand is required; allowed: generate, metric, view, peers, fuzz, all, mutants, detect, corpus"
usage "bench: unknown subcommand 'frobnicate'" frobnicate
usage "bench generate: --threads: the value is empty" generate --threads ''
usage "bench generate: unknown option: --bogus" generate --bogus
usage "bench all: unknown option: --bogus" all --bogus

# bench all's steps are child processes of this executable, given the benchmark's own words.
run 0 all --dry-run --quick --only generate,peers
exe=$(cd "$(dirname "$bin")" && pwd -P)/$(basename "$bin")
[ "$(wc -l <"$dir/out")" -eq 2 ] || fail "all --dry-run --only generate,peers: not 2 steps: $(cat "$dir/out")"
grep -q "^bench all: \[1/2\] $exe generate --quick --md 'BENCHMARKS.md'$" "$dir/out" ||
    fail "all --dry-run: step 1 is not '$exe generate ...': $(cat "$dir/out")"
grep -q "^bench all: \[2/2\] $exe peers --quick --md 'BENCHMARKS.md'$" "$dir/out" ||
    fail "all --dry-run: step 2 is not '$exe peers ...': $(cat "$dir/out")"
run 1 all --dry-run --only bogus
grep -q "^ladarvr: error: bench all: --only 'bogus': allowed a list of generate, metric, view, peers, detect, fuzz$" \
    "$dir/err" || fail "all --only bogus: $(cat "$dir/err")"
[ -e "$dir/BENCHMARKS.md" ] && fail "a dry run wrote BENCHMARKS.md"
# bench detect --families takes small, full or test, checked before any corpus is built.
run 1 detect --families bogus
grep -q "^ladarvr: error: bench detect: --families = 'bogus': allowed small, full or test$" "$dir/err" ||
    fail "detect --families bogus: $(cat "$dir/err")"
# bench ground-isprs --map takes a PNG name other than the --md file, checked before any sample
# is read, and not with the modes that stop before the main table.
run 1 ground-isprs --map errors.txt
grep -q "^ladarvr: error: bench ground-isprs: --map 'errors.txt': allowed a file name ending in .png$" "$dir/err" ||
    fail "ground-isprs --map errors.txt: $(cat "$dir/err")"
run 1 ground-isprs --map notes.png --md notes.png
grep -q "^ladarvr: error: bench ground-isprs: --map 'notes.png' is the --md file; allowed another file$" "$dir/err" ||
    fail "ground-isprs --map = --md: $(cat "$dir/err")"
usage "bench ground-isprs: --map excludes --selector" ground-isprs --map errors.png --selector
[ -e "$dir/errors.png" ] || [ -e "$dir/notes.png" ] && fail "a refused --map wrote a picture"
echo "bench cli_test: all checks passed"
