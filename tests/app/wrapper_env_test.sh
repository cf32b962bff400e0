#!/usr/bin/env bash
# tests/app/wrapper_env_test.sh SOURCE_DIR LADARVR_BINARY: the ./ladarvr wrapper passes
# what OpenXR and X11 need, and nothing else, to the commands it runs.
#  1. `./ladarvr shell -c env` sees XDG_RUNTIME_DIR, XR_RUNTIME_JSON, XAUTHORITY, DISPLAY
#     and LADARVR_* from the caller, and not an unrelated variable;
#  2. a private monado-service (its own socket folder, started by headless_env.sh outside
#     the wrapper) is found by `./ladarvr view` through the wrapper: the session reaches
#     FOCUSED and frames are submitted. Without XDG_RUNTIME_DIR passed on, the viewer
#     would not find the socket and would fall back to the desktop;
#  3. a command that dies by a signal gives one line naming the signal and the signal's
#     exit status, not bash's report of the job.
# Inside the Debian 13 root (ctest runs there) the wrapper runs natively: the same
# environment filter, no chroot. Skipped (77) when the binary is not the checkout's
# build/<preset>/app/ladarvr, which is what the wrapper would run.
set -euo pipefail
src=$(realpath "$1")
bin=$(realpath "$2")
preset=$(basename "$(dirname "$(dirname "$bin")")")
[ "$bin" = "$src/build/$preset/app/ladarvr" ] || { echo "skip: $bin is not under $src/build/<preset>"; exit 77; }
work=$(mktemp -d /tmp/ladarvr-wrappertest.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# 1. The filter itself.
env -i PATH="$PATH" HOME="${HOME:-/root}" LADARVR_PRESET="$preset" DISPLAY=:77 XAUTHORITY=/nonexistent/xauth \
  XDG_RUNTIME_DIR="$work" XR_RUNTIME_JSON=/nonexistent/runtime.json LADARVR_SOMETHING=1 \
  UNRELATED_SECRET=leak "$src/ladarvr" shell -c env >"$work/env.txt" 2>"$work/err" ||
  fail "ladarvr shell -c env: $(cat "$work/err")"
for want in DISPLAY=:77 XAUTHORITY=/nonexistent/xauth "XDG_RUNTIME_DIR=$work" \
            XR_RUNTIME_JSON=/nonexistent/runtime.json LADARVR_SOMETHING=1 "LADARVR_PRESET=$preset"; do
  grep -qx -- "$want" "$work/env.txt" || fail "$want not passed: $(cat "$work/env.txt")"
done
! grep -q UNRELATED_SECRET "$work/env.txt" || fail "an unrelated variable was passed"

# 2. Monado outside the wrapper, the viewer through it.
status=0
"$src/tests/viewer/headless_env.sh" --monado --timeout 150 -- \
  env LADARVR_PRESET="$preset" "$src/ladarvr" view --xres 64 --yres 64 --views 40 --width 320 --height 240 \
  --frames 10 --timeout 120 --log-json "$work/log.json" >"$work/out" 2>"$work/err" || status=$?
[ "$status" -eq 0 ] || fail "ladarvr view through the wrapper exited $status: $(tail -n 20 "$work/err")"
python3 - "$work/log.json" <<'PY' || fail "log: $(head -c 2000 "$work/log.json")"
import json, sys
log = json.load(open(sys.argv[1]))
assert "FOCUSED" in log["states"], log["states"]
xr_frames = [f for f in log["frames"] if f["xr"]]
assert len(xr_frames) >= 5, len(xr_frames)
PY
# 3. Death by signal: one line, the status kept.
status=0
env LADARVR_PRESET="$preset" "$src/ladarvr" shell -c 'echo before >&2; kill -TERM $$' >"$work/out" 2>"$work/err" ||
  status=$?
[ "$status" -eq 143 ] || fail "a command killed by SIGTERM: exit $status, expected 143"
[ "$(wc -l <"$work/err")" -eq 2 ] || fail "signal report is not one line: $(cat "$work/err")"
grep -qx 'before' "$work/err" || fail "the command's own stderr was lost: $(cat "$work/err")"
grep -qx 'ladarvr: stopped by signal SIGTERM (exit 143)' "$work/err" || fail "no signal line: $(cat "$work/err")"

echo "wrapper_env: ok"
