#!/usr/bin/env bash
# tests/viewer/view_real_test.sh LADARVR SCENARIO: `ladarvr view` on real survey files
# (tests/data/real) headless, asserting on the screenshot and stderr. Scenarios:
#   fit     hexbin-crop.las (293 m x 201 m, 101 m of relief): the orbit fitted to the
#           cloud's extent shows the survey from outside, so the points fill the upper half
#           of the frame (the panel is in the lower left); today's fixed 60 m orbit
#           (--orbit-radius 60) sees it from inside one corner, sparse.
#   above-ground  hexbin-crop.las holds no height above ground but classifies its ground
#           (class 2): --colour above-ground says once on stderr that its colours come from
#           the file's class 2, records the terrain in the run log, and shows the ground
#           white (the run's last frame waits for the terrain); the red is the lowest objects.
#   heights  `ladarvr ground`'s output of CSite3_orig-utm.laz (a town, point format 0: no
#           colours, so every point reads white) carries each point's height above ground:
#           --colour above-ground shows its class 2 white and the roofs and trees in the jet
#           colours, from the LAS file as from its COPC index, not every point white.
#   colourless  CSite3_orig-utm.laz (point format 0) without --colour: a file without colours
#           reads white throughout, so its file colours are the height colours, not a white mass;
#           likewise 4_6_crop.las, whose RGB fields all hold 0 (not a black mass), and its COPC index.
#   class   hexbin-crop.las's classes 1 and 2 in the ASPRS palette: mostly ground brown,
#           some grey; --colour intensity shows many levels of grey.
#   eight-bit  hexbin-crop.las's points written by laspy with 8-bit colours (a yellow,
#           255 200 40) in LAS's 16-bit fields, as many producers do: `--colour file` shows
#           them yellow, not black (the high byte of an 8-bit value is 0).
#   strays  FSite5_orig-utm.laz holds 187 returns 610-899 m up (birds, clouds) over a
#           survey whose trees reach 400 m: --colour height spans the survey's own heights,
#           so its picture has as many blue, cyan and green pixels as that of a copy
#           without those returns (stretched to 899 m, the survey is red to orange, with
#           none), and the orbit centres on the survey, not 250 m above it.
# Each run has a timeout; headless_env.sh starts and kills Xvfb (trap).
set -euo pipefail
bin=$(realpath "$1")
scenario=$2
here=$(cd "$(dirname "$0")" && pwd)
data=$(cd "$here/../data/real" && pwd)
work=$(mktemp -d /tmp/ladarvr-viewreal.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$here/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
common=(view --no-xr --frames 10 --width 640 --height 480 --timeout 120)
# view_whole NAME POINTS CLOUD ARGS...: views CLOUD headless with more frames each time
# until the run log NAME.json shows all POINTS on the GPU (the file streams in), the last
# frame in NAME.png.
view_whole() {
    local name=$1 points=$2 cloud=$3 uploaded=0 frames
    shift 3
    for frames in 10 60 300 1500 6000; do
        "$here/headless_env.sh" --timeout 150 -- "$bin" view --no-xr --frames "$frames" --width 640 --height 480 \
          --timeout 120 "$cloud" --log-json "$work/$name.json" --screenshot "$work/$name.png" "$@" 2>"$work/stderr" ||
          { cat "$work/stderr" >&2; exit 1; }
        uploaded=$(python3 -c "import json, sys; print(json.load(open(sys.argv[1]))['points_uploaded'])" "$work/$name.json")
        [ "$uploaded" = "$points" ] && return 0
    done
    echo "FAIL: $name: $uploaded of $points points on the GPU after $frames frames" >&2
    exit 1
}

# lit SHOT.png ROWS: the fraction of pixels of the frame's upper half (ROWS=upper: the
# settings panel keeps to the lower half) or all of it (ROWS=all) that are not the clear
# colour.
lit() {
  python3 - "$here" "$1" "$2" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
w, h, px = read_png(sys.argv[2])
if sys.argv[3] == "upper":
    px, h = px[:w * (h // 2) * 3], h // 2
bg = (15, 18, 23)  # the clear colour 0.06, 0.07, 0.09
print(count(px, lambda r, g, b: abs(r - bg[0]) + abs(g - bg[1]) + abs(b - bg[2]) > 30) / (w * h))
PY
}

# above LIMIT VALUE WHAT: fails unless VALUE > LIMIT.
above() {
  python3 -c "import sys; sys.exit(0 if float('$2') > float('$1') else 1)" || {
    echo "FAIL: $3: $2, want > $1" >&2
    exit 1
  }
}

case "$scenario" in
  fit)
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" "$data/hexbin-crop.las" --point-size 4 \
      --screenshot "$work/fit.png" 2>"$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" "$data/hexbin-crop.las" --point-size 4 \
      --orbit-radius 60 --screenshot "$work/fixed.png" 2>"$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
    fitted=$(lit "$work/fit.png" upper)
    fixed=$(lit "$work/fixed.png" upper)
    echo "upper half lit: fitted orbit $fitted, fixed 60 m orbit $fixed"
    above 0.5 "$fitted" "the fitted orbit's view of hexbin-crop.las is not filled"
    above "$fixed" "$fitted" "the fitted orbit shows no more of the survey than the fixed one"
    ;;
  above-ground)
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" "$data/hexbin-crop.las" --point-size 4 \
      --colour above-ground --log-json "$work/log.json" --screenshot "$work/ag.png" 2>"$work/stderr" ||
      { cat "$work/stderr" >&2; exit 1; }
    lines=$(grep -c "view: above-ground colours from the file's class 2" "$work/stderr" || true)
    [ "$lines" = 1 ] || { cat "$work/stderr" >&2; echo "FAIL: $lines terrain lines, want 1" >&2; exit 1; }
    if grep -q "showing height" "$work/stderr"; then cat "$work/stderr" >&2; echo "FAIL: a fallback warning" >&2; exit 1; fi
    python3 - "$here" "$work" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
log = json.load(open(f"{sys.argv[2]}/log.json"))
terrain = log.get("terrain")
assert terrain and terrain["source"].startswith("the file's class 2") and terrain["cells"] > 0, f"run log terrain: {terrain}"
assert "colour_fallback" not in log, f"run log colour_fallback: {log.get('colour_fallback')}"
w, h, px = read_png(f"{sys.argv[2]}/ag.png")
px = px[:w * (h // 2) * 3]  # the upper half (the panel keeps to the lower)
red = count(px, lambda r, g, b: r > 60 and g < 30 and b < 30)
white = count(px, lambda r, g, b: min(r, g, b) > 90 and max(r, g, b) - min(r, g, b) < 12)
lit = count(px, lambda r, g, b: r + g + b > 90)
print(f"upper half: {lit} lit, {white} white (shaded), {red} red")
assert lit > w * (h // 2) // 2, f"only {lit} pixels show the survey"
assert white > lit // 2, f"{white} of {lit} pixels white: the ground is not white"
assert red < lit // 10, f"{red} of {lit} pixels red: the ground is not white"
PY
    ;;
  heights)
    "$bin" ground "$data/CSite3_orig-utm.laz" --out "$work/hag.laz" 2>"$work/stderr" ||
      { cat "$work/stderr" >&2; exit 1; }
    "$bin" index "$work/hag.laz" --out "$work/hag.copc.laz" 2>"$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
    for name in hag hag.copc; do
      view_whole "$name" 377028 "$work/$name.laz" --point-size 4 --no-edl --colour above-ground
    done
    python3 - "$here" "$work" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
for name in ("hag", "hag.copc"):
    log = json.load(open(f"{sys.argv[2]}/{name}.json"))
    assert "terrain" not in log, f"{name}: a terrain built for a file with heights: {log['terrain']}"
    w, h, px = read_png(f"{sys.argv[2]}/{name}.png")
    px = px[:w * (h // 2) * 3]  # the upper half (the panel keeps to the lower)
    white = count(px, lambda r, g, b: min(r, g, b) > 200)
    jet = count(px, lambda r, g, b: max(r, g, b) - min(r, g, b) > 80)
    lit = count(px, lambda r, g, b: r + g + b > 90)
    print(f"{name}: upper half {lit} lit, {white} white, {jet} in jet colours")
    assert lit > w * (h // 2) // 2, f"{name}: only {lit} pixels show the survey"
    assert jet > lit // 4, f"{name}: {jet} of {lit} pixels in jet colours: the objects are not coloured"
    assert white > lit // 10, f"{name}: {white} of {lit} pixels white: the ground is not white"
PY
    ;;
  colourless)
    view_whole plain 377028 "$data/CSite3_orig-utm.laz" --point-size 4 --no-edl
    # 4_6_crop.las has RGB fields (point format 3) that all hold 0, streamed and as COPC.
    view_whole zeros 23875 "$data/4_6_crop.las" --point-size 6 --no-edl
    "$bin" index "$data/4_6_crop.las" --out "$work/zeros.copc.laz" >/dev/null 2>"$work/stderr" ||
      { cat "$work/stderr" >&2; exit 1; }
    view_whole zeros_copc 23875 "$work/zeros.copc.laz" --point-size 6 --no-edl
    python3 - "$here" "$work" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
for name, least_lit in (("plain", None), ("zeros", 20000), ("zeros_copc", 20000)):
    w, h, px = read_png(f"{sys.argv[2]}/{name}.png")
    px = px[:w * (h // 2) * 3]
    jet = count(px, lambda r, g, b: max(r, g, b) - min(r, g, b) > 80)
    white = count(px, lambda r, g, b: min(r, g, b) > 200)
    lit = count(px, lambda r, g, b: r + g + b > 90)
    print(f"{name}: upper half: {lit} lit, {jet} in jet colours, {white} white")
    assert lit > (least_lit or w * (h // 2) // 2), f"{name}: only {lit} pixels show the survey"
    assert jet > lit // 2, f"{name}: {jet} of {lit} pixels in jet colours ({white} white): no colours shown as colours"
PY
    ;;
  class)
    for mode in class intensity; do
      "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" "$data/hexbin-crop.las" --point-size 4 \
        --no-edl --colour "$mode" --screenshot "$work/$mode.png" 2>"$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
    done
    python3 - "$here" "$work" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
w, h, px = read_png(f"{sys.argv[2]}/class.png")
px = px[:w * (h // 2) * 3]
brown = count(px, lambda r, g, b: (r, g, b) == (153, 102, 51))
grey = count(px, lambda r, g, b: (r, g, b) == (153, 153, 153))
print(f"class: {brown} ground brown, {grey} unclassified grey")
assert brown > w * (h // 2) // 3, f"only {brown} ground brown pixels"
assert 0 < grey < brown, f"{grey} grey pixels against {brown} brown"
w, h, px = read_png(f"{sys.argv[2]}/intensity.png")
px = px[:w * (h // 2) * 3]
levels = {p for p in zip(px[0::3], px[1::3], px[2::3]) if p[0] == p[1] == p[2]}
print(f"intensity: {len(levels)} levels of grey")
assert len(levels) > 50, f"{len(levels)} levels of grey: no intensity stretch"
PY
    ;;
  eight-bit)
    python3 - "$data/hexbin-crop.las" "$work/eight.las" <<'PY'
import sys
import laspy
import numpy as np
src = laspy.read(sys.argv[1])
header = laspy.LasHeader(point_format=3, version="1.2")
header.scales, header.offsets = src.header.scales, src.header.offsets
out = laspy.LasData(header)
out.X, out.Y, out.Z = src.X, src.Y, src.Z
out.classification = src.classification
n = len(src.points)
out.red, out.green, out.blue = (np.full(n, v, dtype=np.uint16) for v in (255, 200, 40))
out.write(sys.argv[2])
PY
    "$here/headless_env.sh" --timeout 150 -- "$bin" "${common[@]}" "$work/eight.las" --point-size 4 --no-edl \
      --colour file --screenshot "$work/eight.png" 2>"$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
    python3 - "$here" "$work/eight.png" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
w, h, px = read_png(sys.argv[2])
px = px[:w * (h // 2) * 3]  # the upper half (the panel keeps to the lower)
yellow = count(px, lambda r, g, b: r > 200 and g > 150 and b < 90)
print(f"upper half: {yellow} of {w * (h // 2)} pixels the file's yellow")
assert yellow > w * (h // 2) // 2, f"only {yellow} yellow pixels: the 8-bit colours are not shown"
PY
    ;;
  strays)
    python3 - "$data/FSite5_orig-utm.laz" "$work/clean.las" <<'PY'
import sys
import laspy
src = laspy.read(sys.argv[1])
keep = (src.z > 200) & (src.z < 500)
assert (~keep).sum() >= 150, f"{(~keep).sum()} stray returns in FSite5, want the file's 188"
src.points = src.points[keep]
src.write(sys.argv[2])
PY
    # The file loads beside the frames: each view runs more frames than the last until its
    # log shows every point of the file on the GPU.
    for name in strays clean; do
      cloud="$data/FSite5_orig-utm.laz"
      want=628320
      [ "$name" = clean ] && { cloud="$work/clean.las"; want=628132; }
      loaded=no
      for frames in 10 60 300 1500; do
        "$here/headless_env.sh" --timeout 200 -- "$bin" view --no-xr --frames "$frames" --width 640 --height 480 \
          --timeout 180 "$cloud" --no-edl --colour height --log-json "$work/$name.json" \
          --screenshot "$work/$name.png" 2>"$work/stderr" || { cat "$work/stderr" >&2; exit 1; }
        if python3 -c "import json, sys; j = json.load(open(sys.argv[1])); sys.exit(0 if j['points_uploaded'] == $want else 1)" \
          "$work/$name.json"; then loaded=yes; break; fi
      done
      [ "$loaded" = yes ] || { echo "FAIL: $name: not every point on the GPU after 1500 frames" >&2; exit 1; }
    done
    python3 - "$here" "$work" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from check_view_log import read_png, count
cool = {}
for name in ("strays", "clean"):
    w, h, px = read_png(f"{sys.argv[2]}/{name}.png")
    px = px[:w * (h // 2) * 3]  # the upper half (the panel keeps to the lower)
    lit = count(px, lambda r, g, b: r + g + b > 90)
    cool[name] = count(px, lambda r, g, b: r + g + b > 90 and max(g, b) > r + 40)
    print(f"{name}: {lit} lit pixels, {cool[name]} blue, cyan or green")
    assert lit > w * (h // 2) // 3, f"{name}: only {lit} pixels show the survey"
assert cool["clean"] > 0, "the survey without strays shows no blue, cyan or green"
assert cool["strays"] > 0.7 * cool["clean"], f"with its stray returns {cool['strays']} cool pixels, want near {cool['clean']}"
PY
    ;;
  *)
    echo "view_real_test: unknown scenario '$scenario'" >&2
    exit 2
    ;;
esac
echo "view_real_test $scenario: ok"
