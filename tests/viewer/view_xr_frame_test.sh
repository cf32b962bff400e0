#!/usr/bin/env bash
# tests/viewer/view_xr_frame_test.sh LADARVR: what the viewer hands the OpenXR compositor
# each frame, on Monado's simulated HMD (null compositor) under Xvfb:
#   - depth: Monado offers XR_KHR_composition_layer_depth and GL_DEPTH_COMPONENT32F, so the
#     run log says depth is submitted, every submitted frame chains its eyes' depth
#     (window depth 0..1 for the projection's near and far: the event names them), and the
#     runtime, which validates each XrCompositionLayerDepthInfoKHR, reports no XR error;
#   - timing: every XR frame carries xrWaitFrame's predicted display time (increasing) and
#     period (> 0), and the run log sums the periods up (the frame budget); the controllers
#     are located at the display time of the frame they are drawn in (once FOCUSED).
# The simulated HMD has no controllers, but xrSyncActions and the aim spaces' locates run
# all the same, and the frame records when they ran (input_time_ns).
# The run ends after --frames frames; headless_env.sh starts and kills Xvfb and Monado.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-xrframe.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

status=0
"$here/headless_env.sh" --monado --timeout 150 -- "$bin" view --xres 64 --yres 64 --views 40 --width 640 \
  --height 360 --timeout 120 --frames 30 --orbit-period 100000 --log-json "$work/log.json" \
  2>"$work/stderr" || status=$?
[ "$status" = 0 ] || { cat "$work/stderr" >&2; echo "view_xr_frame_test: view exited $status" >&2; exit 1; }

python3 - "$work" "$here" <<'PY'
import json, sys
work = sys.argv[1]
sys.path.insert(0, sys.argv[2])
from check_view_log import check, failures

err = open(f"{work}/stderr").read()
xr_errors = [l for l in err.splitlines() if l.startswith("ladarvr: xr:")]
check(not xr_errors, f"XR errors: {xr_errors}")
log = json.load(open(f"{work}/log.json"))
check(log.get("xr_active_at_end") is not None and log.get("fallback", "") == "", f"fallback: {log.get('fallback')}")
submitted = log.get("frames_submitted", 0)
check(submitted > 0, f"frames_submitted {submitted}")
depth = log.get("xr_depth", {})
check(depth == {"extension": True, "format": 0x8CAC, "submitted": True}, f"xr_depth {depth}")
check(log.get("xr_depth_frames", 0) >= submitted, f"xr_depth_frames {log.get('xr_depth_frames')} of {submitted}")
check("xr: depth submitted (near 0.1 m, far 20000 m)" in log["events"], f"events: {log['events']}")
xr_frames = [f for f in log["frames"] if f["xr"]]
check(len(xr_frames) == log.get("frames_counted"), f"{len(xr_frames)} XR frames of {log.get('frames_counted')}")
check(all(f.get("depth_submitted") is True for f in xr_frames), "a frame without depth")
check(all(f.get("display_period_ns", 0) > 0 for f in xr_frames), "a frame without a predicted display period")
times = [f["display_time_ns"] for f in xr_frames]
check(all(b > a for a, b in zip(times, times[1:])), f"display times not increasing: {times}")
synced = [f for f in xr_frames if f.get("input_time_ns", 0) != 0]
check(len(synced) > len(xr_frames) // 2, f"controllers read in {len(synced)} of {len(xr_frames)} frames")
check(all(f["input_time_ns"] == f["display_time_ns"] for f in synced),
      "controllers located at another time than the frame's display time: " +
      str([(f["input_time_ns"], f["display_time_ns"]) for f in synced if f["input_time_ns"] != f["display_time_ns"]][:3]))
period = log.get("xr_display_period_ms", {})
check(period.get("frames", 0) >= len(xr_frames), f"xr_display_period_ms {period}")
check(0 < period.get("min", 0) <= period.get("last", 0) <= period.get("max", 0), f"xr_display_period_ms {period}")
periods_ms = [f["display_period_ns"] * 1e-6 for f in xr_frames]
check(xr_frames and period.get("min", 0) <= min(periods_ms) and max(periods_ms) <= period.get("max", 0),
      f"frame periods {periods_ms} outside the summary {period}")
for f in failures:
    print("view_xr_frame_test:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
