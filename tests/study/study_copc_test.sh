#!/usr/bin/env bash
# tests/study/study_copc_test.sh LADARVR: a study whose trial clouds are COPC files, and
# what is done with its results afterwards, headless (Xvfb, desktop mode):
#   1. the demo cloud (64x64 x 40 views) written as COPC by `generate` is the cloud of both
#      trials of a plan (read whole, within --memory-mb, by the one cloud reader); the
#      script waits for each ready screen (`next`), designates the tank and confirms: two
#      rows, both confirmed hits, with traces and the tank's candidate confirmed;
#   2. `study --replay` plays trial 1's trace over its COPC cloud to the end;
#   3. `metric --trace` of trial 1's trace over P1, P2 and P3 given as COPC files gives
#      the same per-view target figures as over the same clouds given as PCD files. Every
#      trace row is a view (--trace-step-s 0): the script counts frames, so the trial's
#      length in seconds depends on the machine's frame time and a time step would not.
# The study ends on the script's last confirm (no sleeps); headless_env.sh starts and
# kills Xvfb.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
env_sh="$here/../viewer/headless_env.sh"
work=$(mktemp -d /tmp/ladarvr-studycopc.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/../viewer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fail() { echo "study_copc_test: FAIL: $*" >&2; exit 1; }

small=(--xres 64 --yres 64 --views 40)
"$bin" generate "${small[@]}" --out "$work/demo.copc.laz" 2>"$work/gen.err" || { cat "$work/gen.err"; exit 1; }
"$bin" index --check "$work/demo.copc.laz" >/dev/null || fail "generate wrote no valid COPC file"

cat >"$work/candidates.json" <<'JSON'
{"candidates": [{"id": "tank", "centre": [0, 0, 1.2], "size_m": [7, 3.5, 2.5], "yaw_deg": 20, "score": 0.9}]}
JSON
cat >"$work/plan.json" <<PLAN
{"trials": [{"cloud": "demo.copc.laz", "candidates": "candidates.json", "time_limit_s": 300, "name": "copc A"},
            {"cloud": "demo.copc.laz", "time_limit_s": 300, "name": "copc B"}],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000}}
PLAN
cat >"$work/script.txt" <<'SCRIPT'
1 next
+4 aim 0 0 1.2
+1 designate
+6 confirm
+2 next
+4 aim 0 0 1.2
+1 designate
+6 confirm
SCRIPT
status=0
"$env_sh" --timeout 220 -- "$bin" study "$work/plan.json" --out "$work/out" --width 640 --height 360 --timeout 200 \
  --script "$work/script.txt" --no-xr --no-metric 2>"$work/study.err" || status=$?
[ "$status" = 0 ] || { cat "$work/study.err" >&2; fail "study exited $status"; }

python3 - "$work/out" <<'PY' || fail "the study's files"
import csv, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/trials.csv")))
problems = []
if len(rows) != 2:
    problems.append(f"{len(rows)} rows in trials.csv")
for r in rows:
    if not r["cloud"].endswith("demo.copc.laz"):
        problems.append(f"trial {r['trial']}: cloud {r['cloud']}")
    if r["decision"] != "confirm" or r["hit"] != "1" or not float(r["target_distance_m"]) < 1.0:
        problems.append(f"trial {r['trial']}: not a confirmed hit: {r}")
    trace = list(csv.DictReader(open(f"{out}/trace_{r['trial']}.csv")))
    if len(trace) < 5 or sum(1 for t in trace if t["hit_x"]) < 3:
        problems.append(f"trace_{r['trial']}: {len(trace)} rows")
cands = list(csv.DictReader(open(f"{out}/candidates.csv")))
if [(c["candidate"], c["verdict"]) for c in cands if c["trial"] == "1"] != [("tank", "confirmed")]:
    problems.append(f"candidates: {cands}")
for p in problems:
    print("study_copc_test:", p, file=sys.stderr)
sys.exit(1 if problems else 0)
PY

# 2. The replay of trial 1 over its COPC cloud runs to the trace's end.
status=0
"$env_sh" --timeout 220 -- "$bin" study --replay "$work/out" --trial 1 --width 320 --height 180 \
  --log-json "$work/replay.json" 2>"$work/replay.err" || status=$?
[ "$status" = 0 ] || { cat "$work/replay.err" >&2; fail "replay exited $status"; }
python3 -c "import json,sys; e=json.load(open(sys.argv[1]))['exit']; sys.exit(e != 'replay done')" \
  "$work/replay.json" || fail "replay: $(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['exit'])" "$work/replay.json")"

# 3. metric --trace over COPC clouds, against the same clouds as PCD.
for role in target environment target,environment; do
  name=${role/,/_}
  "$bin" generate "${small[@]}" --roles "$role" --out "$work/$name.pcd" 2>>"$work/gen.err"
  "$bin" index "$work/$name.pcd" --out "$work/$name.copc.laz" --threads 1 2>>"$work/gen.err"
done
for kind in pcd copc.laz; do
  "$bin" metric --trace "$work/out/trace_1.csv" --p1 "$work/target.$kind" --p2 "$work/environment.$kind" \
    --p3 "$work/target_environment.$kind" --no-exact --width 64 --height 64 --trace-step-s 0 \
    --out "$work/metric_${kind%%.*}" >"$work/metric_${kind%%.*}.out" 2>"$work/metric_${kind%%.*}.err" ||
    { cat "$work/metric_${kind%%.*}.err" >&2; fail "metric --trace over $kind clouds"; }
done
python3 - "$work" <<'PY' || fail "metric --trace over COPC differs from PCD"
import csv, sys
work = sys.argv[1]
pcd = list(csv.DictReader(open(f"{work}/metric_pcd/views.csv")))
copc = list(csv.DictReader(open(f"{work}/metric_copc/views.csv")))
problems = []
if len(pcd) != len(copc) or len(pcd) < 2:
    problems.append(f"views: {len(pcd)} over PCD, {len(copc)} over COPC")
in_view = sum(1 for r in pcd if float(r["i1"]) > 0)
if in_view == 0:
    problems.append("the target is in view in no sample")
for a, b in zip(pcd, copc):
    if (float(a["i1"]) > 0) != (float(b["i1"]) > 0):
        problems.append(f"target in view differs: {a} / {b}")
    if abs(float(a["visible"]) - float(b["visible"])) > 0.02:
        problems.append(f"visible differs: {a['visible']} / {b['visible']}")
for p in problems:
    print("study_copc_test:", p, file=sys.stderr)
print(f"metric --trace: {len(pcd)} views, target in view in {in_view}, COPC agrees with PCD")
sys.exit(1 if problems else 0)
PY
echo "study_copc_test: ok"
