#!/usr/bin/env bash
# tests/viewer/view_measure_budget_test.sh LADARVR: the default point budget and rasterizer
# measured from the first frames and remembered per GPU, headless (Xvfb, desktop mode, on
# whatever GL the machine has: llvmpipe here). make_test_pcd.py's cloud is viewed three
# times with --measure-budget on and a private cache folder (XDG_CACHE_HOME):
#   1. the first run measures: its run log's event says "budget measured", both choices
#      say "measured", and the cache folder holds one budget file naming this GPU;
#   2. the second run reuses it: the event says "budget remembered", the choices say
#      "remembered" with the first run's budget and rasterizer, and no measure is logged;
#   3. the budget file damaged, the third run gives one warning line naming it and
#      measures again, and the file is whole again.
# The runs end after a fixed number of frames (events, no sleeps).
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-measure.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export XDG_CACHE_HOME="$work/cache"

python3 "$here/make_test_pcd.py" "$work/demo.pcd"
view() {
  local name=$1 status=0
  "$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/demo.pcd" --no-xr --width 320 --height 240 \
    --frames 80 --timeout 120 --measure-budget on --log-json "$work/$name.json" 2>"$work/$name.err" || status=$?
  [ "$status" = 0 ] || { cat "$work/$name.err" >&2; echo "view_measure_budget_test: $name run exited $status" >&2; exit 1; }
}
view first
view second
file=$(ls "$work/cache/ladarvr"/budget-*.json)
printf '{"format": "ladarvr view budget", "version": 1, "point_bud' >"$file"
view third

python3 - "$work" <<'PY'
import glob, json, sys
work = sys.argv[1]
failures = []
def check(ok, what):
    if not ok: failures.append(what)
logs = {n: json.load(open(f"{work}/{n}.json")) for n in ("first", "second", "third")}
def events(log):
    return [e.get("event", e) if isinstance(e, dict) else e for e in log.get("events", [])]
def has(log, words):
    return [e for e in events(log) if isinstance(e, str) and words in e]
files = glob.glob(f"{work}/cache/ladarvr/budget-*.json")
check(len(files) == 1, f"budget files {files}")
first, second, third = logs["first"], logs["second"], logs["third"]
check(len(has(first, "budget measured")) == 1, f"first: events {events(first)}")
for key in ("point_budget_choice", "rasterizer_choice"):
    check(first.get(key, {}).get("from") == "measured", f"first: {key} {first.get(key)}")
    check(second.get(key, {}).get("from") == "remembered", f"second: {key} {second.get(key)}")
check(second["point_budget_choice"].get("point_budget") == first["point_budget_choice"].get("point_budget"),
      "second: not the first run's budget")
check(second["rasterizer_choice"].get("rasterizer") == first["rasterizer_choice"].get("rasterizer"),
      "second: not the first run's rasterizer")
check(len(has(second, "budget remembered")) == 1 and not has(second, "budget measured"), f"second: events {events(second)}")
err = open(f"{work}/third.err").read().splitlines()
warnings = [l for l in err if "warning" in l]
check(len(warnings) == 1 and "budget cache" in warnings[0] and "measured again" in warnings[0],
      f"third: warnings {warnings}")
check(len(has(third, "budget measured")) == 1, f"third: events {events(third)}")
if files:
    doc = json.load(open(files[0]))
    check(doc.get("format") == "ladarvr view budget" and doc.get("point_budget", 0) >= 100000, f"file {doc}")
for f in failures:
    print("view_measure_budget_test:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
