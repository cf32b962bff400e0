#!/usr/bin/env bash
# tests/viewer/headless_env.sh: runs a command under a private Xvfb (on the display number
# it picks, -displayfd) and, with --monado, a
# private Monado service with its simulated HMD and null compositor (docs/viewer.md,
# "Headless tests"):
#
#   tests/viewer/headless_env.sh [--monado | --monado-stay] [--timeout S] -- COMMAND ARGS...
#
# --monado exits the service when its client disconnects (IPC_EXIT_ON_DISCONNECT=1, what
# the tests want); --monado-stay keeps it for several clients in a row (benchmarks).
# Every process it starts is killed on exit (trap); every wait has a timeout; the exit
# status is the command's (124 if it ran past --timeout). Used by the viewer's ctest
# entries and by `ladarvr bench view` runs on machines without a display or an HMD.
set -euo pipefail

monado=0
exit_on_disconnect=1
timeout_s=120
while [ $# -gt 0 ]; do
  case "$1" in
    --monado) monado=1; shift ;;
    --monado-stay) monado=1; exit_on_disconnect=0; shift ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "headless_env: unknown option '$1'; allowed --monado, --monado-stay, --timeout S, --" >&2; exit 2 ;;
  esac
done
[ $# -gt 0 ] || { echo "headless_env: no command given after --" >&2; exit 2; }

work=$(mktemp -d /tmp/ladarvr-headless.XXXXXX)
pids=()
cleanup() {
  local p
  # Entries are PIDs, or -PGID for a process group; all were started by this script.
  for p in "${pids[@]}"; do kill -- "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 -- "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 -- "$p" 2>/dev/null || true
  done
  rm -rf "$work"
}
trap cleanup EXIT INT TERM

# Xvfb picks a free display number itself and writes it to fd 3 once it accepts
# connections (-displayfd): no guessing from lock files, no race with other servers.
Xvfb -displayfd 3 -screen 0 1600x900x24 -nolisten tcp 3>"$work/display" >"$work/xvfb.log" 2>&1 &
pids+=($!)
display=""
for _ in $(seq 100); do
  # The number is complete once its line ends.
  if [ "$(tail -c 1 "$work/display" 2>/dev/null | od -An -tx1 | tr -d ' ')" = 0a ]; then
    display=$(tr -dc '0-9' <"$work/display")
    [ -n "$display" ] && break
  fi
  kill -0 -- "${pids[0]}" 2>/dev/null || { cat "$work/xvfb.log" >&2; echo "headless_env: Xvfb died" >&2; exit 1; }
  sleep 0.1
done
[ -n "$display" ] || { echo "headless_env: Xvfb did not report a display in 10 s" >&2; exit 1; }
export DISPLAY=":$display"

# The OpenXR runtime talks to its clients through a socket in XDG_RUNTIME_DIR.
export XDG_RUNTIME_DIR="$work/xdg"
mkdir -m 700 "$XDG_RUNTIME_DIR"
if [ "$monado" = 1 ]; then
  command -v monado-service >/dev/null || { echo "headless_env: monado-service is not installed" >&2; exit 1; }
  # monado-service watches stdin; with /dev/null it fails, so give it a pipe that stays open.
  # setsid: the pipe's processes form one process group, killed together (kill -- -PGID).
  XRT_COMPOSITOR_NULL=1 SIMULATED_ENABLE=1 IPC_EXIT_ON_DISCONNECT=$exit_on_disconnect XRT_LOG=warning \
    setsid bash -c 'sleep 600 | exec monado-service' >"$work/monado.log" 2>&1 &
  monado_pgid=$!
  pids+=("-$monado_pgid")
  export LADARVR_MONADO_PGID=$monado_pgid   # lets a test take the runtime away mid-run
  # Wait for the socket itself: the service creates a lock file beside it first, and a
  # client that starts between the two finds no socket and falls back to the desktop.
  socket="$XDG_RUNTIME_DIR/monado_comp_ipc"
  for _ in $(seq 150); do
    [ -S "$socket" ] && break
    sleep 0.1
  done
  [ -S "$socket" ] ||
    { cat "$work/monado.log" >&2; echo "headless_env: monado-service did not open its socket in 15 s" >&2; exit 1; }
else
  # No runtime: point the loader at nothing so an installed runtime is not picked up.
  export XR_RUNTIME_JSON="$work/no-runtime.json"
fi

status=0
timeout --kill-after=5 "$timeout_s" "$@" || status=$?
if [ "$status" != 0 ] && [ "$monado" = 1 ]; then
  echo "headless_env: command failed ($status); monado-service log:" >&2
  tail -n 20 "$work/monado.log" >&2 || true
fi
exit "$status"
