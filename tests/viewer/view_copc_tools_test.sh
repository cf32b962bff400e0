#!/usr/bin/env bash
# tests/viewer/view_copc_tools_test.sh LADARVR: the operator's tools on a cloud read node by
# node from COPC, headless (Xvfb, desktop mode). make_test_pcd.py's cloud (a white ground
# grid and a red target block at the centre, origin 10^6 m away) is indexed with `ladarvr
# index` and viewed with candidate boxes, the cutting volume on (--cut) and the label
# colours. The script waits for the pointer's first pick index (pickable+N), then:
#   - aims at a far candidate box and rejects it;
#   - aims at the block's top, designates it: the run log's designation is a target point
#     inside the block and names the octree level of the node it was picked from, which
#     is one of the file's levels; the frames' pointer records give the level too;
#   - confirms the block's candidate box;
#   - the cutting volume then hides the points far from the designation: the mirror shows
#     far fewer lit pixels than the same run without --cut, and the red block is on screen;
#   - frames after the designation draw a focus (the run log's stream.focus_points).
# The runs end on a scripted Escape (no sleeps); headless_env.sh starts and kills Xvfb.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-copctools.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

python3 "$here/make_test_pcd.py" "$work/demo.pcd"
# 163,840 points over nodes of at most 100,000: more than one level.
"$bin" index "$work/demo.pcd" --out "$work/demo.copc.laz" --threads 1 --node-points 100000 2>"$work/index.err" ||
  { cat "$work/index.err" >&2; exit 1; }
cat >"$work/candidates.json" <<'JSON'
{"candidates": [{"id": "block", "centre": [1000000, 2000000, 51.5], "size_m": [8, 4, 3], "yaw_deg": 0, "score": 0.9},
                {"id": "far", "centre": [1000040, 2000040, 51], "size_m": [6, 6, 2], "yaw_deg": 0, "score": 0.2}]}
JSON
cat >"$work/script.txt" <<'SCRIPT'
pickable+2 aim 1000040 2000040 51
+2 reject
+2 aim 1000000 2000000 53
+2 designate
+2 confirm
+10 escape
SCRIPT
common=(view "$work/demo.copc.laz" --no-xr --width 1280 --height 720 --timeout 120 --orbit-period 100000
        --orbit-radius 40 --orbit-height 25
        --colour label --candidates "$work/candidates.json" --script "$work/script.txt" --point-size 3)
for run in cut whole; do
  extra=()
  [ "$run" = cut ] && extra=(--cut)
  status=0
  "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" "${extra[@]}" --screenshot "$work/$run.png" \
    --log-json "$work/$run.json" 2>"$work/$run.err" || status=$?
  [ "$status" = 0 ] || { cat "$work/$run.err" >&2; echo "view_copc_tools_test: $run run exited $status" >&2; exit 1; }
done

python3 - "$work" "$here" <<'PY'
import json, struct, sys
work, here = sys.argv[1], sys.argv[2]
sys.path.insert(0, here)
from check_view_log import read_png, check, failures

def pixels(path):
    w, h, px = read_png(path)
    return [(px[i], px[i + 1], px[i + 2]) for i in range(0, len(px), 3)]

# The file's levels, from its hierarchy (io/copc.hpp: 32-byte entries, key level first).
data = open(f"{work}/demo.copc.laz", "rb").read()
root_offset, root_size = struct.unpack_from("<QQ", data, 375 + 54 + 5 * 8)  # after centre, halfsize, spacing
levels = set()
pages = [(root_offset, root_size)]
while pages:
    off, size = pages.pop()
    for k in range(size // 32):
        level, x, y, z, offset, byte_size, count = struct.unpack_from("<iiiiQii", data, off + 32 * k)
        if count == -1:
            pages.append((offset, byte_size))
        elif count > 0:
            levels.add(level)
check(len(levels) > 1, f"the index has one level only: {levels}")

for run in ("cut", "whole"):
    log = json.load(open(f"{work}/{run}.json"))
    check(log.get("source", {}).get("kind") == "copc", f"{run}: not read as COPC: {log.get('source')}")
    check(log["exit"] == "escape", f"{run}: exit {log['exit']}")
    actions = log["actions"]
    names = [a["action"] for a in actions]
    check(names == ["reject", "designate", "confirm"], f"{run}: actions {names}")
    designations = [a for a in actions if a["action"] == "designate"]
    if designations:
        d = designations[0]
        w = d.get("world")
        check(w is not None and abs(w[0] - 1e6) <= 4.1 and abs(w[1] - 2e6) <= 2.1 and 49.9 <= w[2] <= 53.1,
              f"{run}: designated {w}, not on the block")
        check(d.get("label") == "target", f"{run}: designated label {d.get('label')}")
        check(d.get("level") in levels, f"{run}: designation level {d.get('level')} not one of the file's {levels}")
    verdicts = {c["id"]: c["verdict"] for c in log["candidates"]}
    check(verdicts == {"block": "confirmed", "far": "rejected"}, f"{run}: verdicts {verdicts}")
    hits = [f["pointer"] for f in log["frames"] if f["pointer"].get("hit") is not None]
    check(hits and all(h.get("level") in levels for h in hits), f"{run}: pointer records without a level: {hits[:3]}")
    check(all(f["colour"] == "label" for f in log["frames"]), f"{run}: colour modes")
    # The designation (and the pointer's hit) make a focus drawn whatever the budget.
    focus = [f["stream"].get("focus_points", 0) for f in log["frames"]]
    check(max(focus) > 0, f"{run}: no frame drew a focus")
    check(all(f["cut"] == (run == "cut") for f in log["frames"]), f"{run}: cut flags")

lit = {}
red = {}
for run in ("cut", "whole"):
    px = pixels(f"{work}/{run}.png")
    lit[run] = sum(1 for r, g, b in px if r + g + b > 100)  # the background sums to about 56
    red[run] = sum(1 for r, g, b in px if r > 150 and g < 60 and b < 60)
check(red["cut"] >= 20 and red["whole"] >= 20, f"red target pixels: {red}")
check(lit["cut"] * 2 < lit["whole"], f"the cutting volume hides too little: lit pixels {lit}")
for f in failures:
    print("view_copc_tools_test:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
