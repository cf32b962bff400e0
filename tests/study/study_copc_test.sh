#!/usr/bin/env bash
# tests/study/study_copc_test.sh LADARVR: a study whose trial clouds are COPC files, and
# what is done with its results afterwards, headless (Xvfb, desktop mode):
#   1. the demo cloud (64x64 x 40 views) written as COPC by `generate` is the cloud of both
#      trials of a plan (read whole, within --memory-mb, by the one cloud reader); the
#      script waits for each ready screen (`next`); in trial 1 it designates the ground
#      20 m from the tank, then points at the tank's candidate box and confirms it: a hit
#      by the box (box_hit 1, designation_hit 0), judged on the cloud's target points; in
#      trial 2 it designates the tank and confirms: a hit by the designation. Both rows
#      are confirmed hits, with traces, the tank's candidate confirmed, and shown_N.json
#      holding the boxes shown and the marks made;
#   2. `study --replay` plays trial 1's trace over its COPC cloud to the end, with the
#      boxes and marks of shown_1.json: the replay's log has the designation where it was
#      made and the tank's box confirmed;
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
+4 aim 20 0 0
+1 designate
+4 aim 0 0 1.2
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
    if r["decision"] != "confirm" or r["hit"] != "1":
        problems.append(f"trial {r['trial']}: not a confirmed hit: {r}")
# Trial 1: the designation stood on the ground away from the tank; the confirmed box
# holds the tank's points (box_hit). Trial 2: the designation hit; no box was confirmed.
if rows and (float(rows[0]["target_distance_m"] or 0) < 5.0 or rows[0]["designation_hit"] != "0"
             or rows[0]["box_hit"] != "1"):
    problems.append(f"trial 1: not a hit by the box alone: {rows[0]}")
if len(rows) > 1 and (not float(rows[1]["target_distance_m"]) < 1.0 or rows[1]["designation_hit"] != "1"
                      or rows[1]["box_hit"] != ""):
    problems.append(f"trial 2: not a hit by the designation alone: {rows[1]}")
    trace = list(csv.DictReader(open(f"{out}/trace_{r['trial']}.csv")))
    if len(trace) < 5 or sum(1 for t in trace if t["hit_x"]) < 3:
        problems.append(f"trace_{r['trial']}: {len(trace)} rows")
cands = list(csv.DictReader(open(f"{out}/candidates.csv")))
if [(c["candidate"], c["verdict"]) for c in cands if c["trial"] == "1"] != [("tank", "confirmed")]:
    problems.append(f"candidates: {cands}")
import json
shown = [json.load(open(f"{out}/shown_{n}.json")) for n in (1, 2)]
if [c["id"] for c in shown[0]["candidates"]] != ["tank"] or shown[1]["candidates"] != []:
    problems.append(f"shown files' candidates: {shown}")
marks = shown[0]["marks"]
if len(marks) != 2 or "designate" not in marks[0] or marks[1].get("verdict") != "confirmed":
    problems.append(f"shown_1.json's marks: {marks}")
elif rows and any(abs(marks[0]["designate"][i] - float(rows[0]["designated_" + "xyz"[i]])) > 1e-3 for i in range(3)):
    problems.append(f"shown_1.json's designation {marks[0]} is not trials.csv's")
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
# The replay showed the trial's box and the operator's marks as recorded.
python3 - "$work" <<'PY' || fail "the replay's boxes and marks"
import json, sys
work = sys.argv[1]
log = json.load(open(f"{work}/replay.json"))
shown = json.load(open(f"{work}/out/shown_1.json"))
problems = []
if log.get("candidates") != [{"id": "tank", "verdict": "confirmed"}]:
    problems.append(f"candidates {log.get('candidates')}")
replayed = [a for a in log["actions"] if a.get("source") == "replay"]
if [a["action"] for a in replayed] != ["designate", "confirm"]:
    problems.append(f"replayed actions {replayed}")
elif any(abs(replayed[0]["world"][i] - shown["marks"][0]["designate"][i]) > 1e-6 for i in range(3)):
    problems.append(f"the designation replayed at {replayed[0]['world']}, recorded at {shown['marks'][0]}")
for p in problems:
    print("study_copc_test:", p, file=sys.stderr)
sys.exit(1 if problems else 0)
PY

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
