#!/usr/bin/env bash
# tests/study/study_terrain_test.sh LADARVR: a design whose above-ground condition shows
# real LAS/LAZ files without heights above ground, run headless (--no-xr, Xvfb from
# tests/viewer/headless_env.sh). Each of its cloud trials gets the ground under its file as
# `view` gets it (app/src/view_terrain.hpp), not the height-colour fallback:
#   hexbin-crop.las (class 2)   "the file's class 2 (35,318 points)"
#   FSite8_orig-utm.laz (no class 2)   "a terrain fitted by SMRF on 345,966 of its points"
# Checked: the viewer's stderr line per trial, the run log's events and no colour
# fallback (neither its warning nor the log's colour_fallback), shown_<N>.json's terrain
# for the above-ground trials and none for the height ones, and `study --replay` of the
# SMRF trial binding the same terrain in the same colours before it plays.
# Event-driven: a trial's `next` waits for its cloud and, in above-ground colours, for its
# terrain; the replay plays once its terrain is bound.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
env_sh="$here/../viewer/headless_env.sh"
data=$(cd "$here/../data/real" && pwd)
work=$(mktemp -d /tmp/ladarvr-studyterrain.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/../viewer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fail() { echo "FAIL: $*"; exit 1; }

# One participant, so the conditions run in the Latin square's first row: ag, then ht.
cat >"$work/design.json" <<DESIGN
{"conditions": [{"name": "ag", "colour": "above-ground"}, {"name": "ht", "colour": "height"}],
 "blocks": [{"name": "real", "trials": [{"cloud": "$data/hexbin-crop.las", "name": "hexbin"},
                                        {"cloud": "$data/FSite8_orig-utm.laz", "name": "fsite"}]}],
 "participants": ["P01"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000}}
DESIGN
{
  echo "1 next"; echo "+5 no_target"
  for _ in 2 3 4; do echo "+2 next"; echo "+5 no_target"; done
} >"$work/script.txt"

status=0
"$env_sh" --timeout 280 -- "$bin" study "$work/design.json" --participant P01 --out "$work/out" --no-xr \
  --width 320 --height 180 --timeout 260 --script "$work/script.txt" --log-json "$work/log.json" \
  2>"$work/stderr" || status=$?
echo "--- stderr (exit $status) ---"
grep -v '^\s\|^LOG\|^$' "$work/stderr" || true
[ "$status" = 0 ] || fail "the study exited with status $status"

class2="the file's class 2 (35,318 points)"
smrf="a terrain fitted by SMRF on 345,966 of its points"
for source in "$class2" "$smrf"; do
  [ "$(grep -cxF "ladarvr: view: above-ground colours from $source" "$work/stderr")" = 1 ] ||
    fail "not one terrain line '$source' on stderr"
done
! grep -q "colour above-ground: the cloud holds no height\|no terrain for above-ground" "$work/stderr" ||
  fail "the height-colour fallback was said"

python3 - "$work" "$class2" "$smrf" <<'PY'
import csv, json, sys
work, class2, smrf = sys.argv[1:]
def check(ok, what):
    if not ok:
        sys.exit("FAIL: " + what)
rows = list(csv.DictReader(open(f"{work}/out/trials.csv")))
check([(r["condition"], r["name"]) for r in rows] ==
      [("ag", "hexbin"), ("ag", "fsite"), ("ht", "hexbin"), ("ht", "fsite")], f"trials.csv rows {rows}")
want = {1: class2, 2: smrf, 3: None, 4: None}
for n, source in want.items():
    shown = json.load(open(f"{work}/out/shown_{n}.json"))
    got = shown.get("terrain")
    check(got == ({"source": source} if source else None), f"shown_{n}.json terrain {got}, want {source}")
log = json.load(open(f"{work}/log.json"))
check("colour_fallback" not in log, f"run log colour_fallback {log.get('colour_fallback')}")
for trial, source in ((0, class2), (1, smrf)):
    event = f"trial {trial}: above-ground colours from {source}"
    check(log["events"].count(event) == 1, f"run log events lack '{event}': {log['events']}")
check(not any("terrain" in e or "above-ground colours" in e for e in log["events"]
              if e.startswith(("trial 2:", "trial 3:"))), f"a terrain for a height trial: {log['events']}")
# Each trial is drawn in its condition's colours from its start.
for trial, colour in ((0, "above-ground"), (1, "above-ground"), (2, "height"), (3, "height")):
    colours = {f["colour"] for f in log["frames"] if f.get("trial") == trial}
    check(colours == {colour}, f"trial {trial} drawn in {colours}")
PY

# The replay of the SMRF trial: the same terrain, bound before the trace plays.
"$env_sh" --timeout 200 -- "$bin" study --replay "$work/out" --trial 2 --width 320 --height 180 \
  --log-json "$work/replay.json" 2>"$work/replay.err" || { cat "$work/replay.err"; fail "replay exited non-zero"; }
grep -qxF "ladarvr: view: above-ground colours from $smrf" "$work/replay.err" ||
  fail "no terrain line in the replay: $(cat "$work/replay.err")"
python3 - "$work/replay.json" "$smrf" <<'PY'
import json, sys
log = json.load(open(sys.argv[1]))
def check(ok, what):
    if not ok:
        sys.exit("FAIL: " + what)
check(log.get("terrain", {}).get("source") == sys.argv[2], f"replay terrain {log.get('terrain')}")
check("colour_fallback" not in log, "replay colour_fallback")
check({f["colour"] for f in log["frames"]} == {"above-ground"}, "replay not in above-ground colours")
PY
echo "PASS"
