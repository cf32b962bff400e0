#!/usr/bin/env bash
# tests/study/study_headless_test.sh LADARVR SCENARIO: `ladarvr study` driven headless by a
# script (tests/viewer/headless_env.sh starts Xvfb and, for xr, Monado's simulated HMD),
# checked by check_study.py. The plan: two trials of the bundled demo scene (a small
# cloud: 64 x 64 pixels x 40 views); trial 1 rejects a candidate box on a house and
# confirms the tank's, trial 2 aims at a house.
#   xr        on Monado: trial 1 a hit (< 1 m), trial 2 a miss; candidates.csv: house
#             rejected, tank confirmed, the third unreviewed; traces one row per
#             submitted frame, times increasing; the panel drawn in the headset; exit 0.
#   desktop   the same without an OpenXR runtime; then `study --replay` of trial 1 follows
#             the trace's head poses in the mirror.
#   kill      SIGKILL once trial 1 has ended (its line on stderr): trials.csv is whole
#             with one row.
#   sigterm   SIGTERM once trial 2 has started: the frame finishes, trial 2 is logged as
#             quit, the run log is written, exit 143.
#   sigint    `ladarvr view --log-json` stopped by SIGINT (timeout -s INT's signal) still
#             writes its log, with exit "SIGINT", and exits 130.
# Event-driven: the script's `next` waits for the trial's cloud, +N counts frames from the
# previous action, and the signals wait for the viewer's own lines.
set -euo pipefail
bin=$(realpath "$1")
scenario=$2
here=$(cd "$(dirname "$0")" && pwd)
env_sh="$here/../viewer/headless_env.sh"
assets=$(cd "$here/../../assets" && pwd)
work=$(mktemp -d /tmp/ladarvr-studytest.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/../viewer/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

# Trial 1 has candidate boxes: the tank's, a house's (rejected) and one nobody reviews.
cat >"$work/candidates.json" <<'CANDIDATES'
{"candidates": [{"id": "tank", "centre": [0, 0, 1.2], "size_m": [7, 3.5, 2.5], "yaw_deg": 20, "score": 0.9},
                {"id": "house", "centre": [-30, 22, 3], "size_m": [12, 8, 6], "yaw_deg": 75, "score": 0.4},
                {"id": "far", "centre": [80, -80, 2], "size_m": [7, 3.5, 2.5], "yaw_deg": 0, "score": 0.1}]}
CANDIDATES
cat >"$work/plan.json" <<PLAN
{"trials": [{"scene": "$assets/demo/scene.json", "candidates": "candidates.json", "time_limit_s": 300,
             "name": "demo A"},
            {"scene": "$assets/demo/scene.json", "time_limit_s": 300, "name": "demo B"}],
 "orbit": {"radius_m": 60, "height_m": 40, "period_s": 100000},
 "generate": {"xres": 64, "yres": 64, "views": 40}}
PLAN
# The tank stands at the origin (2.5 m high); a large house at (-30, 22). Trial 1 rejects
# the house's box, then designates the tank and confirms its box (which ends the trial).
cat >"$work/script.txt" <<'SCRIPT'
1 next
+4 aim -30 22 3
+1 reject
+3 aim 0 0 1.2
+1 designate
+6 confirm
+2 next
+8 aim -30 22 3
+1 designate
+6 confirm
SCRIPT
common=(study "$work/plan.json" --out "$work/out" --width 640 --height 360 --timeout 200
        --script "$work/script.txt" --log-json "$work/log.json" --no-metric)
status=0
case "$scenario" in
  xr)
    "$env_sh" --monado --timeout 220 -- "$bin" "${common[@]}" 2>"$work/stderr" || status=$?
    ;;
  desktop)
    "$env_sh" --timeout 220 -- "$bin" "${common[@]}" --no-xr 2>"$work/stderr" || status=$?
    # Then trial 1's trace replayed in the mirror.
    [ "$status" = 0 ] && { "$env_sh" --timeout 220 -- "$bin" study --replay "$work/out" --trial 1 --width 320 \
      --height 180 --log-json "$work/replay.json" 2>"$work/replay.err" || status=$?; }
    ;;
  kill|sigterm)
    if [ "$scenario" = kill ]; then wait_for="study: trial 1 ended"; sig=KILL; want=137
    else wait_for="study: trial 2 started"; sig=TERM; want=143; fi
    # The study stops after trial 1's `next` for trial 2 so the kill finds it mid-run.
    [ "$scenario" = kill ] && sed -i '7,$d' "$work/script.txt"
    [ "$scenario" = sigterm ] && sed -i '8,$d' "$work/script.txt"
    cat >"$work/run.sh" <<RUN
set -u
"$bin" ${common[*]} --no-xr 2>"$work/stderr" &
viewer=\$!
for _ in \$(seq 1800); do
  grep -q "$wait_for" "$work/stderr" && break
  kill -0 \$viewer 2>/dev/null || break
  sleep 0.1
done
kill -$sig \$viewer
rc=0
wait \$viewer || rc=\$?
echo "exit \$rc" >"$work/rc"
RUN
    "$env_sh" --timeout 220 -- bash "$work/run.sh" || status=$?
    rc=$(cut -d' ' -f2 "$work/rc")
    echo "study exit status after SIG$sig: $rc (want $want)"
    [ "$rc" = "$want" ] || { echo "FAIL: exit $rc, expected $want"; grep -v '^\s\|^LOG\|^$' "$work/stderr" || true; exit 1; }
    ;;
  sigint)
    # set -m: a background job of a script otherwise starts with SIGINT ignored.
    cat >"$work/run.sh" <<RUN
set -um
"$bin" view --xres 64 --yres 64 --views 40 --no-xr --width 320 --height 180 --log-json "$work/log.json" \
  2>"$work/stderr" &
viewer=\$!
for _ in \$(seq 1800); do
  grep -q "first frame drawn" "$work/stderr" 2>/dev/null && break   # after the handlers and one counted frame
  kill -0 \$viewer 2>/dev/null || break
  sleep 0.1
done
kill -INT \$viewer
rc=0
wait \$viewer || rc=\$?
echo "exit \$rc" >"$work/rc"
RUN
    "$env_sh" --timeout 220 -- bash "$work/run.sh" || status=$?
    rc=$(cut -d' ' -f2 "$work/rc")
    echo "view exit status after SIGINT: $rc"
    [ "$rc" = 130 ] || { echo "FAIL: exit $rc, expected 130"; cat "$work/stderr"; exit 1; }
    ;;
  *) echo "study_headless_test: unknown scenario '$scenario'" >&2; exit 2 ;;
esac
echo "--- stderr (exit $status) ---"
grep -v '^\s\|^LOG\|^$' "$work/stderr" || true
[ "$status" = 0 ] || { echo "FAIL: the run exited with status $status"; exit 1; }
python3 "$here/check_study.py" "$scenario" "$work"
