#!/bin/sh
# tests/bench/ground_survey_test.sh: `ladarvr bench ground-survey` end to end on a small
# survey (no timing asserted): the survey generated once and reused, `ground` and `index`
# run as the shipped binary, the table printed with both rows and the ratio, BENCHMARKS.md
# left alone with --no-md, the outputs removed, bad options one line naming the option.
# Usage: ground_survey_test.sh LADARVR_BENCH_BINARY LADARVR_BINARY SCRATCH_DIR
set -eu
bench=$1
app=$2
dir=$3
rm -rf "$dir"
mkdir -p "$dir/work"
fail() { echo "FAIL: $*" >&2; exit 1; }

run() {
    (cd "$dir" && "$bench" ground-survey --points 40000 --repeats 1 --warmup 0 --dir "$dir/work" \
        --ladarvr "$app" --no-md "$@") >"$dir/out" 2>"$dir/err" || fail "ground-survey $*: $(cat "$dir/err")"
}

run
grep -q "generating .*survey_20x20.copc.laz" "$dir/err" || fail "no survey generated: $(cat "$dir/err")"
[ -f "$dir/work/survey_20x20.copc.laz" ] || fail "the survey is not kept in the work folder"
grep -q "^## Ground on a survey (ladarvr bench ground-survey)" "$dir/out" || fail "no heading: $(cat "$dir/out")"
grep -q "^| \`ground IN --out OUT.laz --memory-mb 1024\` | [0-9.]* | [0-9.]* | [0-9]* |$" "$dir/out" ||
    fail "no ground row: $(cat "$dir/out")"
grep -q "^| \`index IN --out OUT.copc.laz --memory-mb 1024\` (baseline) | " "$dir/out" || fail "no index row"
grep -q "^ground / index: [0-9.]*x the time" "$dir/out" || fail "no ratio: $(cat "$dir/out")"
grep -q "(40000 points)" "$dir/out" || fail "the survey's count is not 40000: $(cat "$dir/out")"
grep -q "^The last run: \`ground: wrote " "$dir/out" || fail "no summary of ground's run"
[ ! -e "$dir/work/ground.laz" ] && [ ! -e "$dir/work/index.copc.laz" ] || fail "outputs left in the work folder"
[ ! -e "$dir/BENCHMARKS.md" ] || fail "--no-md wrote BENCHMARKS.md"

# The second run reuses the survey; --in takes a file.
run
grep -q "reusing .*survey_20x20.copc.laz" "$dir/err" || fail "the survey was not reused: $(cat "$dir/err")"
run --in "$dir/work/survey_20x20.copc.laz"
grep -q "\`./ladarvr bench ground-survey --in survey_20x20.copc.laz" "$dir/out" || fail "--in not shown"

status=0
"$bench" ground-survey --repeats 0 >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -ne 0 ] || fail "--repeats 0 accepted"
grep -q "^ladarvr: error: bench ground-survey: --repeats 0: allowed \[1, 100\]" "$dir/err" ||
    fail "--repeats 0: $(cat "$dir/err")"
echo "ground-survey: ok"
