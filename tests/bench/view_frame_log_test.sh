#!/bin/sh
# tests/bench/view_frame_log_test.sh: `ladarvr bench view --paths ooc --frame-log DIR` writes
# each run's second-lap frames as CSV (one row a frame, the GPU and pass times and the
# points drawn), on a small synthetic survey; a folder that does not exist is refused in
# one line. No figure is asserted.
# Usage: view_frame_log_test.sh LADARVR_BENCH_BINARY SCRATCH_DIR
set -eu
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir/log" "$dir/copc"
fail() { echo "FAIL: $*" >&2; exit 1; }

status=0
"$bin" view --paths ooc --frame-log "$dir/missing" >"$dir/out" 2>"$dir/err" || status=$?
[ "$status" -eq 2 ] || fail "a missing --frame-log folder exited $status, expected 2"
[ "$(wc -l <"$dir/err")" -eq 1 ] || fail "a missing --frame-log folder: not one line: $(cat "$dir/err")"
grep -q -e "--frame-log" "$dir/err" || fail "the error does not name --frame-log: $(cat "$dir/err")"

"$bin" view --paths ooc --ooc-synthetic --ooc-points 200000 --head-paths turn --in-core-max 0 --eye 160x160 \
    --no-md --ooc-dir "$dir/copc" --frame-log "$dir/log" >"$dir/out" 2>"$dir/err" ||
    fail "bench view with --frame-log failed: $(tail -3 "$dir/err")"
csv="$dir/log/synthetic_200000_turn_ooc.csv"
[ -f "$csv" ] || fail "no frame log: $(ls "$dir/log")"
[ "$(head -1 "$csv")" = "frame,gpu_eye_ms,frame_ms,drawn_eye,raster_eye_ms,colour_eye_ms,resolve_eye_ms" ] ||
    fail "frame log header: $(head -1 "$csv")"
rows=$(($(wc -l <"$csv") - 1))
[ "$rows" -gt 10 ] || fail "frame log has $rows frames"
# Every row: its index in order, then six numbers; some points drawn in every frame.
awk -F, 'NR > 1 { if ($1 != NR - 2 || NF != 7 || $2 + 0 <= 0 || $4 + 0 <= 0) { print "bad row " NR ": " $0; exit 1 } }' "$csv" ||
    fail "frame log rows malformed"
ls "$dir/log" | grep -qv '\.csv$' && fail "a temporary left in the log folder: $(ls -a "$dir/log")"
echo "bench view --frame-log: $rows frames logged"
