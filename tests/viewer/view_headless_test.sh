#!/usr/bin/env bash
# tests/viewer/view_headless_test.sh LADARVR SCENARIO: drives `ladarvr view` headless and
# asserts on its run log and screenshot (tests/viewer/check_view_log.py). Scenarios:
#   xr       Monado's simulated HMD (null compositor) under Xvfb: session reaches FOCUSED,
#            40 frames submitted with both eyes from the runtime's poses, the poses move,
#            scripted space bar automatic -> free -> automatic, target pixels in the mirror.
#   desktop  no OpenXR runtime: one clear line, desktop fallback, same script and checks.
#   escape   desktop, a scripted cut (frame 2) and colour (frame 3) switch the cutting volume
#            on and step the colour mode; a scripted Escape at frame 5 closes the viewer cleanly.
#   lost     the runtime is killed once 2 XR frames are submitted (the scripted toggles'
#            lines): the viewer drops to the desktop mode with the cloud kept and runs
#            on until a scripted Escape 20 frames after the drop (desktop+20).
#   budget   desktop run with --point-budget 40000, uploading 20,000 points a frame (9 frames
#            for the cloud), Escape 5 frames after the whole cloud is on the GPU (loaded+5):
#            those frames all hold the cloud and each draws at most 40,000 of the
#            163,840 points (LOD prefixes), still over 30,000, and the target is still red on screen.
#   stream   a known binary PCD (make_test_pcd.py, origin 10^6 m away) is streamed in: at
#            most --upload-budget points reach the GPU per frame, points are drawn from the
#            first frames, the red target block is on screen.
#   xr_shot  Monado's simulated HMD, a scripted Escape at frame 10 with --screenshot: the
#            session ends after the frame is saved (exit 0, exit reason escape, a PNG of
#            the window's size), not before any frame could be saved.
#   xr_controllers  Monado's simulated HMD alone binds no controller: one warning line,
#            the run log's xr_controllers false and its event; with QWERTY_ENABLE=1 (Monado's
#            qwerty driver: both controllers emulated from keyboard and mouse) they are
#            bound: xr_controllers true and no warning.
#   refused  files the reader refuses (0 points, label 7, truncated): exit 1 with one line
#            naming the file, and no screenshot; one inf point among the stream test's
#            163,840 is dropped with a warning and the other 163,839 are drawn.
# Each run has a timeout; headless_env.sh starts and kills Xvfb and Monado (trap).
set -euo pipefail
bin=$(realpath "$1")
scenario=$2
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-viewtest.XXXXXX)
trap 'rm -rf "$work"' EXIT

# Under the asan preset: ignore leaks inside Mesa's GLX driver (see lsan.supp).
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
printf '# frame key\n10 space\n25 space\n' >"$work/script.txt"
# A small demo cloud (64x64 pixels x 40 views = 163,840 points) keeps llvmpipe frames short.
common=(view --xres 64 --yres 64 --views 40 --width 960 --height 540 --timeout 120
        --screenshot "$work/shot.png" --log-json "$work/log.json")
status=0
case "$scenario" in
  xr)
    "$here/headless_env.sh" --monado --timeout 150 -- "$bin" "${common[@]}" --frames 40 \
      --script "$work/script.txt" --colour label --mirror left --orbit-period 100000 \
      2>"$work/stderr" || status=$?
    ;;
  desktop)
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" --frames 40 \
      --script "$work/script.txt" --orbit-period 20 2>"$work/stderr" || status=$?
    ;;
  escape)
    printf '2 cut\n3 colour\n5 escape\n' >"$work/escape.txt"
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" --no-xr \
      --script "$work/escape.txt" 2>"$work/stderr" || status=$?
    ;;
  lost)
    # Event-driven: the scripted space presses at frames 1 and 2 print "free mode (script)"
    # and "automatic mode (script)", so once the second line is out at least 2 XR frames
    # were submitted and the runtime is killed; Escape comes 20 frames after the drop to
    # the desktop (desktop+20), whenever that happens.
    printf '1 space\n2 space\ndesktop+20 escape\n' >"$work/escape.txt"
    cat >"$work/lost.sh" <<LOST
set -u
"$bin" ${common[*]} --script "$work/escape.txt" --colour label --orbit-period 100000 \
  2>"$work/stderr" &
viewer=\$!
for _ in \$(seq 1200); do
  grep -q "automatic mode (script)" "$work/stderr" && break
  kill -0 \$viewer 2>/dev/null || break
  sleep 0.1
done
kill -- -"\$LADARVR_MONADO_PGID"   # take the runtime away (the test's own Monado)
wait \$viewer
LOST
    "$here/headless_env.sh" --monado --timeout 150 -- bash "$work/lost.sh" || status=$?
    ;;
  stream)
    python3 "$here/make_test_pcd.py" "$work/demo.pcd"
    "$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/demo.pcd" --no-xr --upload-budget 20000 \
      --frames 15 --width 960 --height 540 --screenshot "$work/shot.png" --log-json "$work/log.json" \
      2>"$work/stderr" || status=$?
    ;;
  budget)
    # Event-driven: Escape 5 frames after the whole cloud is on the GPU (loaded+5), so
    # the frames checked draw the full cloud however fast the generator runs.
    printf 'loaded+5 escape\n' >"$work/loaded.txt"
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" --no-xr --script "$work/loaded.txt" \
      --colour label --orbit-period 100000 --point-budget 40000 --upload-budget 20000 2>"$work/stderr" || status=$?
    ;;
  refused)
    python3 "$here/make_test_pcd.py" "$work/demo.pcd"
    python3 - "$work" <<'PY'
import struct, sys
work = sys.argv[1]
data = open(f"{work}/demo.pcd", "rb").read()
body = data.index(b"DATA binary\n") + 12
head = data[:body]
open(f"{work}/empty.pcd", "wb").write(head.replace(b"WIDTH 163840", b"WIDTH 0").replace(b"POINTS 163840", b"POINTS 0"))
open(f"{work}/cut.pcd", "wb").write(data[:-1000])
label7 = bytearray(data)
label7[body + 16] = 7          # point 0's label byte (records x y z rgb label: 17 bytes)
open(f"{work}/label7.pcd", "wb").write(label7)
inf = bytearray(data)
inf[body:body + 4] = struct.pack("<f", float("inf"))   # point 0's x
open(f"{work}/inf.pcd", "wb").write(inf)
PY
    fail=0
    for name in empty cut label7; do
      rc=0
      "$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/$name.pcd" --no-xr --frames 5 \
        --width 320 --height 180 --screenshot "$work/$name.png" 2>"$work/$name.err" || rc=$?
      line=$(grep "^ladarvr: error: view: pcd: $work/$name.pcd: " "$work/$name.err" || true)
      echo "$name: exit $rc: $line"
      [ "$rc" = 1 ] || { echo "FAIL: $name: exit $rc, expected 1"; fail=1; }
      [ "$(printf '%s\n' "$line" | grep -c .)" = 1 ] || { echo "FAIL: $name: no single error line"; fail=1; }
      # Besides the start-up lines saying how the file is read (not COPC: streamed) and which
      # mode the window opened in (and the first frame, when one was drawn before the
      # error): nothing (no summary).
      [ "$(grep -v -c -F -e 'is not COPC: streamed' -e 'desktop mode' -e 'first frame drawn' "$work/$name.err")" = 1 ] ||
        { echo "FAIL: $name: more than the error line: $(cat "$work/$name.err")"; fail=1; }
      [ ! -e "$work/$name.png" ] || { echo "FAIL: $name: a screenshot was written"; fail=1; }
    done
    grep -q "holds no points to show" "$work/empty.err" || { echo "FAIL: empty: wrong message"; fail=1; }
    grep -q "truncated" "$work/cut.err" || { echo "FAIL: cut: wrong message"; fail=1; }
    grep -q "label 7 is not" "$work/label7.err" || { echo "FAIL: label7: wrong message"; fail=1; }
    rc=0
    "$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/inf.pcd" --no-xr --frames 5 \
      --width 320 --height 180 --screenshot "$work/inf.png" --log-json "$work/inf.json" 2>"$work/inf.err" || rc=$?
    grep "warning" "$work/inf.err" || true
    [ "$rc" = 0 ] || { echo "FAIL: inf: exit $rc"; fail=1; }
    grep -q "^ladarvr: warning: pcd: $work/inf.pcd: dropped 1 of 163840 points with a non-finite" "$work/inf.err" ||
      { echo "FAIL: inf: no warning line"; fail=1; }
    python3 -c 'import json,sys; n=json.load(open(sys.argv[1]))["points_arrived"]; print("inf: points arrived", n); sys.exit(n != 163839)' \
      "$work/inf.json" || { echo "FAIL: inf: not 163,839 points"; fail=1; }
    [ -s "$work/inf.png" ] || { echo "FAIL: inf: no screenshot"; fail=1; }
    [ "$fail" = 0 ] && echo PASS
    exit "$fail"
    ;;
  las)
    # A LAZ from elsewhere (laspy, world coordinates, ASPRS classes, no ladarvr fields)
    # streams in like a binary PCD: every point arrives, the target class reads as target.
    python3 "$here/make_test_pcd.py" "$work/demo.pcd"
    python3 - "$work" <<'PY'
import sys
import laspy
import numpy as np
work = sys.argv[1]
data = open(f"{work}/demo.pcd", "rb").read()
body = data.index(b"DATA binary\n") + 12
origin = np.array([float(v) for v in data.split(b"# ladarvr origin ")[1].split(b"\n")[0].split()])
rec = np.frombuffer(data[body:], dtype=np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4"), ("label", "u1")]))
header = laspy.LasHeader(point_format=7, version="1.4")
header.scales = np.array([0.001, 0.001, 0.001])
header.offsets = origin
las = laspy.LasData(header)
las.x = rec["x"] + origin[0]
las.y = rec["y"] + origin[1]
las.z = rec["z"] + origin[2]
las.red = ((rec["rgb"] >> 16) & 255).astype(np.uint16) * 257
las.green = ((rec["rgb"] >> 8) & 255).astype(np.uint16) * 257
las.blue = (rec["rgb"] & 255).astype(np.uint16) * 257
las.classification = np.array([2, 1, 64], dtype=np.uint8)[rec["label"]]
las.write(f"{work}/demo.laz", laz_backend=laspy.LazBackend.Laszip)
PY
    rc=0
    "$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/demo.laz" --no-xr --frames 8 --colour label \
      --width 320 --height 180 --screenshot "$work/las.png" --log-json "$work/las.json" 2>"$work/las.err" || rc=$?
    fail=0
    [ "$rc" = 0 ] || { echo "FAIL: las: exit $rc: $(grep error "$work/las.err")"; fail=1; }
    python3 -c 'import json,sys; n=json.load(open(sys.argv[1]))["points_arrived"]; print("las: points arrived", n); sys.exit(n != 163840)' \
      "$work/las.json" || { echo "FAIL: las: not 163,840 points"; fail=1; }
    [ -s "$work/las.png" ] || { echo "FAIL: las: no screenshot"; fail=1; }
    [ "$fail" = 0 ] && echo PASS
    exit "$fail"
    ;;
  xr_shot)
    printf '10 escape\n' >"$work/shot_escape.txt"
    rc=0
    "$here/headless_env.sh" --monado --timeout 150 -- "$bin" "${common[@]}" --script "$work/shot_escape.txt" \
      2>"$work/stderr" || rc=$?
    fail=0
    [ "$rc" = 0 ] || { echo "FAIL: xr_shot: exit $rc"; cat "$work/stderr"; fail=1; }
    grep -q "no frame was rendered" "$work/stderr" && { echo "FAIL: xr_shot: no frame saved"; fail=1; }
    python3 - "$work/log.json" "$work/shot.png" <<'PY' || fail=1
import json, struct, sys
log = json.load(open(sys.argv[1]))
problems = []
if log["exit"] != "escape" or log["frames_counted"] not in (10, 11) or log["frames_submitted"] < 1:
    problems.append(f"exit {log['exit']} after {log['frames_counted']} frames ({log['frames_submitted']} submitted)")
shot = log.get("screenshot")
if not shot or shot["frame"] not in (10, 11):
    problems.append(f"screenshot record {shot}")
png = open(sys.argv[2], "rb").read()
if png[:8] != b"\x89PNG\r\n\x1a\n" or struct.unpack(">II", png[16:24]) != (960, 540):
    problems.append("the screenshot is not a 960x540 PNG")
for p in problems:
    print("FAIL: xr_shot:", p)
sys.exit(1 if problems else 0)
PY
    [ "$fail" = 0 ] && echo PASS
    exit "$fail"
    ;;
  xr_controllers)
    fail=0
    for qwerty in 0 1; do
      rc=0
      env $([ "$qwerty" = 1 ] && echo QWERTY_ENABLE=1) "$here/headless_env.sh" --monado --timeout 150 -- \
        "$bin" view --xres 64 --yres 64 --views 40 --width 320 --height 180 --frames 30 \
        --log-json "$work/c$qwerty.json" 2>"$work/c$qwerty.err" || rc=$?
      [ "$rc" = 0 ] || { echo "FAIL: xr_controllers (qwerty $qwerty): exit $rc"; cat "$work/c$qwerty.err"; fail=1; }
      python3 - "$qwerty" "$work/c$qwerty.json" "$work/c$qwerty.err" <<'PY' || fail=1
import json, sys
qwerty, log, err = sys.argv[1] == "1", json.load(open(sys.argv[2])), open(sys.argv[3]).read()
warnings = [l for l in err.splitlines() if "reports no controllers" in l]
problems = []
if log["frames_submitted"] < 20:
    problems.append(f"{log['frames_submitted']} frames submitted")
if log.get("xr_controllers") is not qwerty:
    problems.append(f"xr_controllers {log.get('xr_controllers')}")
if len(warnings) != (0 if qwerty else 1) or any(not w.startswith("ladarvr: warning: view: ") for w in warnings):
    problems.append(f"warning lines {warnings}")
if ("xr: the runtime reports no controllers" in log["events"]) == qwerty:
    problems.append(f"events {log['events']}")
for p in problems:
    print(f"FAIL: xr_controllers (qwerty {int(qwerty)}):", p)
sys.exit(1 if problems else 0)
PY
    done
    [ "$fail" = 0 ] && echo PASS
    exit "$fail"
    ;;
  *) echo "view_headless_test: unknown scenario '$scenario'" >&2; exit 2 ;;
esac
echo "--- viewer stderr (exit $status) ---"
grep -v '^\s\|^LOG\|^$' "$work/stderr" || true
[ "$status" = 0 ] || { echo "FAIL: the viewer exited with status $status"; exit 1; }
python3 "$here/check_view_log.py" "$scenario" "$work/log.json" "$work/shot.png" "$work/stderr"
