#!/usr/bin/env bash
# tests/study/study_report_test.sh LADARVR: `ladarvr study report` end to end. The first two
# of a 12-participant, 3-condition, 2-block design run their sessions in Monado's simulated
# HMD (tests/viewer/headless_env.sh --monado, Xvfb), driven by scripts that hit the tank, confirm a house
# instead (a false confirmation) or declare no target, with waits that differ per trial;
# each folder gets a questionnaires.csv (SSQ before and after, raw TLX per condition) in
# study/instruments.hpp's layout. Then:
#   - `study report RESULTS --out REPORT` (the folder of sessions) and the same with each
#     session folder named: check_report.py recomputes every figure from the raw CSV files
#     (scipy for the distributions and tests) and compares;
#   - refusals, one line each and no report folder made: sessions of two designs, a
#     participant twice, a malformed row, the report folder inside the results;
#   - headless Chromium renders index.html to a screenshot (bounded in time, its process
#     group killed on exit): a PNG of the window's size showing the tables' text and the
#     plots' bars.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
env_sh="$here/../viewer/headless_env.sh"
assets=$(cd "$here/../../assets" && pwd)
work=$(mktemp -d /tmp/ladarvr-reporttest.XXXXXX)
browser_pgid=""
cleanup() {
  [ -n "$browser_pgid" ] && kill -KILL -- "-$browser_pgid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
export LSAN_OPTIONS="suppressions=$here/../viewer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

"$bin" generate --scene "$assets/demo/scene.json" --out "$work/demo.pcd" --xres 64 --yres 64 --views 40 \
  >/dev/null 2>"$work/generate.err" || { cat "$work/generate.err"; exit 1; }
cat >"$work/candidates.json" <<'CANDIDATES'
{"candidates": [{"id": "tank", "centre": [0, 0, 1.2], "size_m": [7, 3.5, 2.5], "yaw_deg": 20, "score": 0.9}]}
CANDIDATES
cat >"$work/design.json" <<'DESIGN'
{"conditions": [{"name": "heightedl", "colour": "height", "eye_dome": true, "candidates": true},
                {"name": "white", "colour": "white", "eye_dome": false, "candidates": false},
                {"name": "label", "colour": "label", "eye_dome": true, "candidates": false}],
 "practice": [{"cloud": "demo.pcd", "name": "practice"}],
 "blocks": [{"name": "first", "trials": [{"cloud": "demo.pcd", "candidates": "candidates.json", "name": "one"}]},
            {"name": "second", "trials": [{"cloud": "demo.pcd", "candidates": "candidates.json", "name": "two"}]}],
 "order": "latin",
 "participants": ["P01", "P02", "P03", "P04", "P05", "P06", "P07", "P08", "P09", "P10", "P11", "P12"],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000}}
DESIGN

# script KINDS...: one trial per kind, H (designate the tank, confirm), F (designate the
# large house, confirm: a false confirmation) or N (declare no target); the wait before
# the decision grows with the trial so the times differ.
script() {
  local first=1 wait=4
  for kind in "$@"; do
    if [ $first = 1 ]; then echo "1 next"; first=0; else echo "+2 next"; fi
    wait=$((wait + 3))
    case "$kind" in
      H) echo "+$wait aim 0 0 1.2"; echo "+1 designate"; echo "+6 confirm" ;;
      F) echo "+$wait aim -2.6 7.0 2.5"; echo "+1 designate"; echo "+6 confirm" ;;
      N) echo "+$wait no_target" ;;
    esac
  done
}
script H H F H N H H H F >"$work/P01.script"
script H N H F H H F H H >"$work/P02.script"

mkdir -p "$work/results"
for p in P01 P02; do
  "$env_sh" --monado --timeout 220 -- "$bin" study "$work/design.json" --participant "$p" --out "$work/results/$p" \
    --width 320 --height 180 --timeout 200 --script "$work/$p.script" --no-metric --log-json "$work/$p.log.json" \
    2>"$work/$p.err" || { echo "FAIL: $p's session exited $?"; cat "$work/$p.err"; exit 1; }
  # The session ran in the headset: its frames went to OpenXR.
  python3 -c 'import json,sys; n=json.load(open(sys.argv[1])).get("frames_submitted", 0); sys.exit(0 if n > 0 else 1)' \
    "$work/$p.log.json" || { echo "FAIL: $p's session submitted no frame to OpenXR"; cat "$work/$p.err"; exit 1; }
done
python3 "$here/check_report.py" questionnaires "$work/results"

# The report from the folder of sessions, and from the session folders named one by one.
"$bin" study report "$work/results" --out "$work/report" 2>"$work/report.err" ||
  { echo "FAIL: study report exited $?"; cat "$work/report.err"; exit 1; }
grep -q "study report: 2 participant(s), 3 condition(s)" "$work/report.err" || { echo "FAIL: no summary line"; cat "$work/report.err"; exit 1; }
"$bin" study report "$work/results/P02" "$work/results/P01" --out "$work/report2" 2>"$work/report2.err" ||
  { echo "FAIL: study report of named folders exited $?"; cat "$work/report2.err"; exit 1; }
cmp -s "$work/report/figures.json" "$work/report2/figures.json" || { echo "FAIL: the two forms differ"; exit 1; }
python3 "$here/check_report.py" figures "$work/results" "$work/report"

# Refusals: one line, exit 1, no report folder.
refused() {  # refused WANT ARGS...
  local want=$1 status=0
  shift
  rm -rf "$work/refused"
  "$bin" study report "$@" --out "$work/refused" 2>"$work/refused.err" || status=$?
  echo "refused: exit $status: $(cat "$work/refused.err")"
  [ "$status" = 1 ] && [ "$(wc -l <"$work/refused.err")" = 1 ] && grep -q -- "$want" "$work/refused.err" ||
    { echo "FAIL: not refused with one line saying '$want'"; exit 1; }
  [ ! -e "$work/refused" ] || { echo "FAIL: a refused report made its folder"; exit 1; }
}
mkdir -p "$work/other"
cp -r "$work/results/P02" "$work/other/P02"
python3 - "$work/other/P02/study.json" <<'PY'
import json, sys
p = sys.argv[1]
d = json.load(open(p))
d["design_sha256"] = "0" * 64
json.dump(d, open(p, "w"))
PY
refused "design SHA-256 0000000000000000000000000000000000000000000000000000000000000000 differs from" \
  "$work/results/P01" "$work/other/P02"
cp -r "$work/results/P01" "$work/other/P01again"
refused "participant P01 again" "$work/results" "$work/other/P01again"
mkdir -p "$work/bad"
cp -r "$work/results/P01" "$work/bad/P01"
sed -i '3s/,confirm,/,confirmed,/' "$work/bad/P01/trials.csv"
refused "trials.csv: line 3, column decision: 'confirmed'; allowed confirm, no_target, timeout or quit" "$work/bad/P01"
status=0
"$bin" study report "$work/results" --out "$work/results/report" 2>"$work/inside.err" || status=$?
echo "refused (inside): exit $status: $(cat "$work/inside.err")"
[ "$status" = 1 ] && [ "$(wc -l <"$work/inside.err")" = 1 ] && [ ! -e "$work/results/report" ] ||
  { echo "FAIL: a report folder inside the results was not refused"; exit 1; }

# A real browser renders the page: a screenshot of the window's size with text and plots.
browser=$(command -v chromium-headless-shell || command -v chromium || true)
[ -n "$browser" ] || { echo "FAIL: no chromium-headless-shell (third_party/packages-build.txt)"; exit 1; }
setsid timeout -k 5 90 "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run \
  --user-data-dir="$work/chromium" --window-size=1000,1600 --screenshot="$work/shot.png" \
  "file://$work/report/index.html" >"$work/chromium.log" 2>&1 &
browser_pgid=$!
status=0
wait "$browser_pgid" || status=$?
kill -KILL -- "-$browser_pgid" 2>/dev/null || true
browser_pgid=""
[ "$status" = 0 ] && [ -s "$work/shot.png" ] || { echo "FAIL: chromium exited $status without a screenshot"; tail -20 "$work/chromium.log"; exit 1; }
python3 "$here/check_report.py" screenshot "$work/shot.png" 1000 1600
echo "study report test: ok"
