#!/usr/bin/env bash
# tests/viewer/view_copc_converge_test.sh LADARVR: a still view of a COPC cloud at full
# budget converges to the picture of the same points held in core.
#
# The demo scene (163,840 points) is generated to LAS and indexed to COPC in nodes of at
# most 100,000 points, so that more than one node loads (the same points:
# both files quantise to the same 1 mm grid, which the equal bounds below confirm). Both files are viewed headless
# in desktop mode from the same pose (the automatic orbit at its start angle: a period of
# 10^12 s moves it by under 10^-9 rad in a run), the COPC one with a cache and a point
# budget that hold everything; each run takes its screenshot 3 frames after the "loaded"
# mark (a script's loaded+3 escape; no sleeps). The screenshots are compared pixel by pixel
# outside the ImGui panel (its text differs: frame times, the source line), with eye-dome
# lighting off and on:
#   - off: at most 0.02 % of the compared pixels differ. What may differ is which point wins
#     a pixel where two points lie at (nearly) the same depth: the file has duplicate
#     positions (a target point on a ground point), drawn in whole-cloud cell order in core
#     and in node order from COPC, and each point's float position is relative to its cell's
#     centre, which differs between the whole cloud's cells and the nodes' cells (rounding
#     in the last bit of the depth).
#   - on: eye-dome lighting shades each pixel from its neighbours' depths, so that same last-
#     bit rounding moves many pixels by a few levels: at most 0.2 % of the compared pixels
#     may differ by more than 3 levels in a channel.
# The run logs must show every node resident and every point on the GPU for the COPC run,
# and the same orbit centre in both (the same bounds).
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d /tmp/ladarvr-copcconv.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

"$bin" generate --xres 64 --yres 64 --views 40 --out "$work/demo.las" >"$work/generate.out" 2>&1 ||
  { cat "$work/generate.out" >&2; echo "view_copc_converge_test: generate failed" >&2; exit 1; }
"$bin" index "$work/demo.las" --out "$work/demo.copc.laz" --node-points 100000 >"$work/index.out" 2>&1 ||
  { cat "$work/index.out" >&2; echo "view_copc_converge_test: index failed" >&2; exit 1; }
printf 'loaded+3 escape\n' >"$work/script.txt"

view() {  # NAME FILE ARGS...
  local name=$1 file=$2 status=0
  shift 2
  "$here/headless_env.sh" --timeout 150 -- "$bin" view "$file" --no-xr --width 800 --height 720 --timeout 120 \
    --orbit-period 1e12 --script "$work/script.txt" --screenshot "$work/$name.png" --log-json "$work/$name.json" \
    "$@" 2>"$work/$name.err" || status=$?
  [ "$status" = 0 ] ||
    { cat "$work/$name.err" >&2; echo "view_copc_converge_test: view $name exited $status" >&2; exit 1; }
}
full=(--cache-mb 1024 --point-budget 0)
view core-edl "$work/demo.las"
view copc-edl "$work/demo.copc.laz" "${full[@]}"
view core-flat "$work/demo.las" --no-edl
view copc-flat "$work/demo.copc.laz" "${full[@]}" --no-edl

python3 - "$work" "$here" <<'PY'
import json, sys
work, here = sys.argv[1], sys.argv[2]
sys.path.insert(0, here)
from check_view_log import read_png, check, failures

TITLE = (41, 74, 122)    # ImGui's active title bar (the panel at the bottom left)

def panel_box(name, w, h, px):
    """The panel's top row and right edge from its title bar, which is in the lower half."""
    at = lambda x, y: tuple(px[3 * (y * w + x):3 * (y * w + x) + 3])
    rows = [y for y in range(h // 2, h) if at(15, y) == TITLE]
    check(rows, f"{name}: no ImGui panel title bar found at the bottom left")
    if not rows:
        return h, w
    title = [x for x in range(w) if at(x, rows[0]) == TITLE]
    return rows[0] - 2, max(title) + 2

def compare(core, copc):
    w, h, a = read_png(f"{work}/{core}.png")
    w2, h2, b = read_png(f"{work}/{copc}.png")
    check((w, h) == (w2, h2), f"{core} {w}x{h} against {copc} {w2}x{h2}")
    (top_a, right_a), (top_b, right_b) = panel_box(core, w, h, a), panel_box(copc, w, h, b)
    top, right = min(top_a, top_b), max(right_a, right_b)
    compared = differ = over3 = lit = 0
    for y in range(h):
        for x in range(right if y >= top else 0, w):
            i = 3 * (y * w + x)
            compared += 1
            d = max(abs(a[i + k] - b[i + k]) for k in range(3))
            differ += d > 0
            over3 += d > 3
            lit += a[i] + a[i + 1] + a[i + 2] > 120
    return compared, differ, over3, lit

for kind in ("edl", "flat"):
    core, copc = json.load(open(f"{work}/core-{kind}.json")), json.load(open(f"{work}/copc-{kind}.json"))
    src = copc.get("source", {})
    check(src.get("kind") == "copc", f"copc-{kind}: source {src}")
    check(src.get("nodes_loaded", 0) > 1 and src.get("nodes_resident") == src.get("nodes_loaded"),
          f"copc-{kind}: nodes loaded {src.get('nodes_loaded')}, resident {src.get('nodes_resident')}")
    check(src.get("nodes_failed") == 0 and src.get("nodes_evicted") == 0, f"copc-{kind}: source {src}")
    check(copc.get("points_uploaded") == core.get("points_uploaded") == 163840,
          f"{kind}: points on the GPU: core {core.get('points_uploaded')}, copc {copc.get('points_uploaded')}")
    check(copc.get("orbit_centre_local") == core.get("orbit_centre_local"),
          f"{kind}: orbit centres {core.get('orbit_centre_local')} and {copc.get('orbit_centre_local')}")
    for name, log in (("core", core), ("copc", copc)):
        check("screenshot" in log, f"{name}-{kind}: no screenshot in the run log")
    compared, differ, over3, lit = compare(f"core-{kind}", f"copc-{kind}")
    print(f"view_copc_converge_test: {kind}: {differ} of {compared} pixels differ, {over3} by more than 3 levels; "
          f"{lit} lit", file=sys.stderr)
    check(lit > compared // 4, f"{kind}: only {lit} of {compared} pixels show points")
    if kind == "flat":
        check(differ * 10000 <= 2 * compared, f"flat: {differ} of {compared} pixels differ (at most 0.02 %)")
    else:
        check(over3 * 1000 <= 2 * compared, f"edl: {over3} of {compared} pixels differ by over 3 levels (at most 0.2 %)")
for f in failures:
    print("view_copc_converge_test:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
