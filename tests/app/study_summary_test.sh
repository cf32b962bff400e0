#!/bin/sh
# tests/app/study_summary_test.sh SOURCE_DIR SCRATCH_DIR: scripts/study_summary.py on a
# small hand-made trials.csv (its header is StudyLog::trialsHeader(), study/src/study_log.cpp;
# the study's headless tests run the script on a real one too): hit rate and median time to
# decision per cloud, exactly, a quit's hit of 0 left out of the hit rate; several folders
# pooled, or summarised each on its own (--each); files that are not a trials.csv, a file
# given twice and a command line without one give one line on stderr (nothing on stdout)
# and exit 2; --help goes to stdout.
set -eu
src=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir/study"
fail() { echo "FAIL: $*" >&2; exit 1; }
summary="python3 $src/scripts/study_summary.py"

header="trial,cloud,decision,designated_x,designated_y,designated_z,target_distance_m,hit,time_to_first_designation_s,time_to_decision_s,designations,mode_switches,seconds_in_free_mode,visibility_metric"
cat >"$dir/study/trials.csv" <<CSV
$header
1,a.pcd,confirm,0.2,0.1,1.0,0.3,1,4.0,10.0,1,0,0,0.41
2,b.pcd,no_target,,,,,,,30.0,0,2,12.5,
3,a.pcd,confirm,25.0,3.0,2.0,25.1,0,8.5,20.0,3,1,6.0,0.41
4,a.pcd,timeout,,,,,0,,120.0,0,0,0,0.41
5,b.pcd,quit,,,,,,,5.0,0,0,0,
6,a.pcd,quit,,,,,0,,7.5,0,0,0,0.41
CSV
cat >"$dir/expected" <<'OUT'
cloud  trials  decided  timeouts  quits    hit_rate  median_s
a.pcd       4        2         1      1  0.33 (1/3)      15.0
b.pcd       2        1         0      1         n/a      30.0
all         6        3         1      2  0.33 (1/3)      20.0
OUT
# The folder or the file itself.
$summary "$dir/study" >"$dir/out" || fail "study_summary on the folder"
diff "$dir/expected" "$dir/out" || fail "unexpected summary (above)"
$summary "$dir/study/trials.csv" >"$dir/out" || fail "study_summary on the file"
diff "$dir/expected" "$dir/out" || fail "unexpected summary for the file (above)"

bad() {  # bad PATTERN CSV_TEXT: exit 2, one line matching PATTERN
    printf '%s\n' "$2" >"$dir/bad.csv"
    status=0
    $summary "$dir/bad.csv" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq 2 ] || fail "exit $status for: $2"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "not one line: $(cat "$dir/err")"
    grep -q -e "^study_summary: error: .*$1" "$dir/err" || fail "'$1' not in: $(cat "$dir/err")"
}
bad "missing column hit" "trial,cloud,decision,time_to_decision_s
1,a.pcd,confirm,3"
bad "line 3, column decision: 'maybe'" "$header
1,a.pcd,confirm,0,0,0,0.3,1,4.0,10.0,1,0,0,
2,a.pcd,maybe,0,0,0,0.3,1,4.0,10.0,1,0,0,"
bad "line 2, column time_to_decision_s: 'soon'" "$header
1,a.pcd,confirm,0,0,0,0.3,1,4.0,soon,1,0,0,"
bad "line 2, column hit: '2'" "$header
1,a.pcd,confirm,0,0,0,0.3,2,4.0,10,1,0,0,"
bad "no trials" "$header"
status=0; $summary "$dir/missing.csv" 2>"$dir/err" >/dev/null || status=$?; [ "$status" -eq 2 ] || fail "a missing file: exit $status"
grep -q "missing.csv" "$dir/err" || fail "missing file: $(cat "$dir/err")"

# Several folders: their trials pooled, clouds matched by name.
mkdir -p "$dir/study2"
cat >"$dir/study2/trials.csv" <<CSV
$header
1,b.pcd,confirm,,,,,,,12.0,1,0,0,
2,c.pcd,confirm,0.2,0.1,1.0,0.3,1,3.0,6.0,1,0,0,0.2
CSV
cat >"$dir/expected2" <<'OUT'
cloud  trials  decided  timeouts  quits    hit_rate  median_s
a.pcd       4        2         1      1  0.33 (1/3)      15.0
b.pcd       3        2         0      1         n/a      21.0
c.pcd       1        1         0      0  1.00 (1/1)       6.0
all         8        5         1      2  0.50 (2/4)      12.0
OUT
$summary "$dir/study" "$dir/study2" >"$dir/out" 2>"$dir/err" || fail "study_summary on two folders: $(cat "$dir/err")"
diff "$dir/expected2" "$dir/out" || fail "unexpected pooled summary (above)"
[ ! -s "$dir/err" ] || fail "stderr on a good run: $(cat "$dir/err")"

# --each: one table per folder, in the order given, each under its name.
{
    echo "$dir/study2:"
    cat <<'OUT'
cloud  trials  decided  timeouts  quits    hit_rate  median_s
b.pcd       1        1         0      0         n/a      12.0
c.pcd       1        1         0      0  1.00 (1/1)       6.0
all         2        2         0      0  1.00 (1/1)       9.0
OUT
    echo
    echo "$dir/study:"
    cat "$dir/expected"
} >"$dir/expected_each"
$summary --each "$dir/study2" "$dir/study" >"$dir/out" 2>"$dir/err" || fail "study_summary --each: $(cat "$dir/err")"
diff "$dir/expected_each" "$dir/out" || fail "unexpected --each summary (above)"

# usage_error STATUS PATTERN ARGS...: one line on stderr matching PATTERN, stdout empty.
usage_error() {
    pattern=$1
    shift
    status=0
    $summary "$@" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq 2 ] || fail "study_summary $*: exit $status, expected 2"
    [ ! -s "$dir/out" ] || fail "study_summary $*: printed on stdout: $(cat "$dir/out")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "study_summary $*: not one line: $(cat "$dir/err")"
    grep -q -e "^study_summary: error: .*$pattern" "$dir/err" || fail "'$pattern' not in: $(cat "$dir/err")"
}
usage_error "no trials.csv given; usage: study_summary.py DIR"
usage_error "no trials.csv given; usage: study_summary.py DIR" --each
usage_error "missing.csv" --each "$dir/study" "$dir/missing.csv"
usage_error "the same trials.csv as $dir/study" "$dir/study" "$dir/study/trials.csv"
usage_error "unknown option --bogus" "$dir/study" --bogus
status=0
$summary --help >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 0 ] || fail "--help: exit $status"
grep -q "study_summary.py DIR1 DIR2" "$dir/out" || fail "--help: no usage on stdout: $(cat "$dir/out")"
[ ! -s "$dir/err" ] || fail "--help: stderr: $(cat "$dir/err")"
echo "study_summary: ok"
