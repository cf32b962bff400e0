#!/bin/sh
# tests/app/study_summary_test.sh SOURCE_DIR SCRATCH_DIR: scripts/study_summary.py on a
# small hand-made trials.csv (its header is StudyLog::trialsHeader(), study/src/study_log.cpp;
# the study's headless tests run the script on a real one too): hit rate and median time to
# decision per cloud, exactly, a quit's hit of 0 left out of the hit rate; files that are
# not a trials.csv give one line and exit 2.
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
echo "study_summary: ok"
