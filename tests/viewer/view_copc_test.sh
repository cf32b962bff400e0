#!/usr/bin/env bash
# tests/viewer/view_copc_test.sh LADARVR COPC_TOOL: `ladarvr view` of COPC files, headless
# (Xvfb, desktop mode), asserting on the start-up line, the run log and the screenshot:
#   1. `copc_tool many` (73 nodes) viewed with a cache far smaller than the file: the
#      start-up line says COPC, nodes are decoded and drawn, the resident bytes never
#      exceed the cache, not every node fits, the pick index over the resident nodes is
#      built, and the mirror shows points.
#   2. `copc_tool bad` (node 1-1-1-1's chunk garbled): one warning line names that node
#      (it is not decoded again), the run log counts one failed node, and other nodes are
#      still loaded and drawn.
# The runs end after --frames frames (no sleeps); headless_env.sh starts and kills Xvfb.
set -euo pipefail
bin=$(realpath "$1")
tool=$(realpath "$2")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-copctest.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

"$tool" many "$work/many.copc.laz"
"$tool" bad "$work/bad.copc.laz"
common=(--no-xr --frames 30 --width 640 --height 360 --timeout 120 --orbit-period 3
        --orbit-radius 150 --orbit-height 80 --point-size 4)
status=0
"$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/many.copc.laz" "${common[@]}" --cache-mb 0.02 \
  --screenshot "$work/many.png" --log-json "$work/many.json" 2>"$work/many.err" || status=$?
[ "$status" = 0 ] || { cat "$work/many.err" >&2; echo "view_copc_test: view of many.copc.laz exited $status" >&2; exit 1; }
status=0
"$here/headless_env.sh" --timeout 150 -- "$bin" view "$work/bad.copc.laz" "${common[@]}" \
  --screenshot "$work/bad.png" --log-json "$work/bad.json" 2>"$work/bad.err" || status=$?
[ "$status" = 0 ] || { cat "$work/bad.err" >&2; echo "view_copc_test: view of bad.copc.laz exited $status" >&2; exit 1; }

python3 - "$work" "$here" <<'PY'
import json, sys
work, here = sys.argv[1], sys.argv[2]
sys.path.insert(0, here)
from check_view_log import read_png, check, failures

def lit_pixels(path):
    w, h, px = read_png(path)
    # The background is (0.06, 0.07, 0.09): anything clearly brighter is a point.
    return sum(1 for i in range(0, len(px), 3) if px[i] + px[i + 1] + px[i + 2] > 120)

many_err = open(f"{work}/many.err").read()
check("many.copc.laz is COPC: 73 nodes" in many_err and "within a 0.02 MB cache" in many_err,
      f"no COPC start-up line in: {many_err!r}")
log = json.load(open(f"{work}/many.json"))
src = log.get("source", {})
check(src.get("kind") == "copc", f"run log source: {src}")
check(src.get("nodes") == 73, f"nodes {src.get('nodes')}")
check(src.get("cache_bytes") == int(0.02 * 1048576), f"cache_bytes {src.get('cache_bytes')}")
check(0 < src.get("nodes_loaded", 0) < 73, f"nodes_loaded {src.get('nodes_loaded')} (the cache holds fewer than 73)")
check(0 < src.get("resident_bytes_peak", 0) <= src.get("cache_bytes", 0),
      f"resident_bytes_peak {src.get('resident_bytes_peak')} over cache_bytes {src.get('cache_bytes')}")
check("first node resident" in log["events"], f"events: {log['events']}")
check(any(e.startswith("picking ready: ") for e in log["events"]), f"no pick index: {log['events']}")
drawn = [f["points_drawn"] for f in log["frames"]]
check(max(drawn) > 0, f"no points drawn: {drawn}")
check(lit_pixels(f"{work}/many.png") > 50, "the mirror shows no points")

bad_err = open(f"{work}/bad.err").read()
warnings = [l for l in bad_err.splitlines() if "warning" in l]
check(len(warnings) == 1 and "node 1-1-1-1" in warnings[0], f"warning lines: {warnings}")
bad = json.load(open(f"{work}/bad.json"))
bsrc = bad.get("source", {})
check(bsrc.get("nodes_failed") == 1, f"nodes_failed {bsrc.get('nodes_failed')}")
check(bsrc.get("nodes_loaded", 0) > 1, f"nodes_loaded {bsrc.get('nodes_loaded')}")
check(max(f["points_drawn"] for f in bad["frames"]) > 0, "no points drawn with one bad node")
check(lit_pixels(f"{work}/bad.png") > 50, "the mirror shows no points with one bad node")
for f in failures:
    print("view_copc_test:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
