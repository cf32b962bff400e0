#!/bin/sh
# tests/app/cmd_metric_trace_test.sh: `ladarvr metric --trace` as a researcher runs it on a
# study's trace. Usage: cmd_metric_trace_test.sh LADARVR_BINARY SCRATCH_DIR
#  - three samples looking at the demo's tank and one looking away: the report has one view
#    per sample kept, the target is in view in three, summary.json says the views are poses;
#  - --trace-step-s subsamples in time; orbit options conflict with --trace (exit 2);
#  - a malformed trace: one line naming the line and column, exit 1, no report;
#  - the scene: a trace_<N>.csv in a study's folder is measured on the scene its trial ran
#    (study.json's plan), and --scene naming another is refused; a trace whose scene is not
#    known (no study folder, or a cloud file's trial) needs --scene: refused in one line
#    naming it, never measured on the demo scene.
set -eu
bin=$1
dir=$2
assets=$(cd "$(dirname "$0")/../../assets" && pwd)
demo=$assets/demo/scene.json
hilly=$assets/hilly/scene.json
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# Head poses (world) from eye and look-at points: -z of the head towards the target.
python3 - "$dir/trace_1.csv" <<'PY'
import math, sys

def quat(eye, at):
    f = [a - e for a, e in zip(at, eye)]
    n = math.sqrt(sum(c * c for c in f)); f = [c / n for c in f]
    back = [-c for c in f]
    up0 = (0.0, 0.0, 1.0)
    r = [up0[1] * back[2] - up0[2] * back[1], up0[2] * back[0] - up0[0] * back[2], up0[0] * back[1] - up0[1] * back[0]]
    n = math.sqrt(sum(c * c for c in r)); r = [c / n for c in r]
    u = [back[1] * r[2] - back[2] * r[1], back[2] * r[0] - back[0] * r[2], back[0] * r[1] - back[1] * r[0]]
    m = [[r[0], u[0], back[0]], [r[1], u[1], back[1]], [r[2], u[2], back[2]]]  # columns right, up, back
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = 2 * math.sqrt(1 + tr)
        return (s / 4, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s)
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0, 0.0, 0.0, 0.0]
    q[0] = (m[k][j] - m[j][k]) / s
    q[1 + i] = s / 4
    q[1 + j] = (m[j][i] + m[i][j]) / s
    q[1 + k] = (m[k][i] + m[i][k]) / s
    return tuple(q)

rows = ["t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,mode,scale,hit_x,hit_y,hit_z"]
poses = [((60, 0, 40), (0, 0, 1)), ((0, 60, 40), (0, 0, 1)), ((-60, 0, 40), (0, 0, 1)), ((60, 0, 40), (120, 0, 40))]
for k, (eye, at) in enumerate(poses):
    q = quat(eye, at)
    rows.append("%g,%g,%g,%g,%.12f,%.12f,%.12f,%.12f,automatic,1,,," % ((0.5 * k,) + eye + q))
open(sys.argv[1], "w").write("\n".join(rows) + "\n")
PY

"$bin" metric --trace "$dir/trace_1.csv" --scene "$demo" --out "$dir/m" --no-exact --width 64 --height 64 \
    --trace-step-s 0 >"$dir/out" 2>"$dir/err" || fail "metric --trace: $(cat "$dir/err")"
grep -q "4 of 4 samples used .*target in view in 3;" "$dir/out" || fail "summary: $(cat "$dir/out")"
[ "$(wc -l <"$dir/m/views.csv")" -eq 5 ] || fail "views.csv: $(cat "$dir/m/views.csv")"
grep -q '"views_from": "poses"' "$dir/m/summary.json" || fail "summary.json: views_from"

"$bin" metric --trace "$dir/trace_1.csv" --scene "$demo" --out "$dir/m2" --no-exact --width 64 --height 64 \
    --trace-step-s 1 >"$dir/out" 2>"$dir/err" || fail "metric --trace-step-s 1: $(cat "$dir/err")"
grep -q "2 of 4 samples used" "$dir/out" || fail "step: $(cat "$dir/out")"

# A study's folder: trial 1 ran the hilly scene, trial 2 a cloud file (the plan's order
# reversed, as a shuffle would). The traces are the one above. Measured on the hilly
# scene, not the demo's: the target is less visible there.
mkdir -p "$dir/study"
printf 'not read here\n' >"$dir/study/c.pcd"
printf '{"trials": [{"cloud": "c.pcd"}, {"scene": "%s"}]}\n' "$hilly" >"$dir/study/plan.json"
printf '{"plan": "%s", "order": [1, 0]}\n' "$dir/study/plan.json" >"$dir/study/study.json"
cp "$dir/trace_1.csv" "$dir/study/trace_1.csv"
cp "$dir/trace_1.csv" "$dir/study/trace_2.csv"
"$bin" metric --trace "$dir/study/trace_1.csv" --out "$dir/m3" --no-exact --width 64 --height 64 --trace-step-s 0 \
    >"$dir/out" 2>"$dir/err" || fail "metric --trace of a study's trial: $(cat "$dir/err")"
grep -q "generating P1, P2, P3 from $hilly" "$dir/err" || fail "not the trial's scene: $(cat "$dir/err")"
grep -q "is trial 1 of $dir/study/study.json, recorded on the scene $hilly" "$dir/err" || fail "which scene: $(cat "$dir/err")"
grep -q "4 of 4 samples used" "$dir/out" || fail "study trace summary: $(cat "$dir/out")"
[ "$(tail -n +2 "$dir/m3/views.csv")" != "$(tail -n +2 "$dir/m/views.csv")" ] || fail "the same views as on the demo scene"

one_error() {  # one_error STATUS PATTERN ARGS...
    expect=$1 pattern=$2
    shift 2
    status=0
    "$bin" "$@" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq "$expect" ] || fail "ladarvr $* exited $status, expected $expect: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "not one line: $(cat "$dir/err")"
    grep -q -e "^ladarvr: error: .*$pattern" "$dir/err" || fail "'$pattern' not in: $(cat "$dir/err")"
    [ ! -e "$dir/bad" ] || fail "ladarvr $* left a report"
}
one_error 2 "excludes" metric --trace "$dir/trace_1.csv" --views 10 --out "$dir/bad"
sed '3s/^0.5,0,60/0.5,0,6x0/' "$dir/trace_1.csv" >"$dir/trace_bad.csv"
one_error 1 "trace_bad.csv: line 3, column head_y: '6x0' is not a finite number" \
    metric --trace "$dir/trace_bad.csv" --scene "$demo" --out "$dir/bad"
one_error 1 "missing.csv" metric --trace "$dir/missing.csv" --out "$dir/bad"
one_error 1 "trace-step-s" metric --trace "$dir/trace_1.csv" --trace-step-s -1 --out "$dir/bad"
one_error 1 "trace_1.csv: the scene it was recorded on is not known .*; give --scene" \
    metric --trace "$dir/trace_1.csv" --out "$dir/bad"
one_error 1 "metric: --scene $demo: --trace $dir/study/trace_1.csv is trial 1 of \
$dir/study/study.json, recorded on the scene $hilly; allowed: that scene, or no --scene" \
    metric --trace "$dir/study/trace_1.csv" --scene "$demo" --out "$dir/bad"
one_error 1 "trace_2.csv is trial 2 of $dir/study/study.json, which ran on the cloud file $dir/study/c.pcd, not a \
scene; give --scene" metric --trace "$dir/study/trace_2.csv" --out "$dir/bad"
cp "$dir/trace_1.csv" "$dir/study/trace_3.csv"
one_error 1 "records 2 trials, not trial 3" metric --trace "$dir/study/trace_3.csv" --scene "$demo" --out "$dir/bad"
echo "cmd_metric_trace: ok"
