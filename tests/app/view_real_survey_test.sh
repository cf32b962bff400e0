#!/usr/bin/env bash
# tests/app/view_real_survey_test.sh LADARVR DATA: `ladarvr view` on real surveys
# (tests/data/real), headless (Xvfb, desktop mode), with XDG_CACHE_HOME in a scratch folder:
#   1. --colour above-ground on a file with class 2 (hexbin-crop.las): the terrain comes
#      from its class 2, said on stderr and in the run log;
#   2. on a file without class 2 (FSite8_orig-utm.laz, all class 0): fitted by SMRF;
#   3. a file whose points carry their height above ground (`ladarvr ground`'s output):
#      no terrain is built;
#   4. a folder of two tiles (hexbin-crop.las cut in two by laspy) viewed as one survey:
#      one index, the points of both, the survey's class 2; the same tiles named on the
#      command line reuse that index (the survey lies 3,100 m up, far from the frame's
#      origin: the orbit must find it from the index's bounds before any node is read);
#   5. refusals in one line, exit 1: tiles of different CRS, a folder without LAS/LAZ
#      files, a folder beside other clouds, --in-core with several files, an output
#      inside the tiles' folder named like a tile.
# The terrain arrives while the view runs. A --frames run with above-ground colours ends
# only once it is bound or has failed (the viewer's wait); a view still runs a few frames,
# then more, until its log shows the terrain and the first points, or a frame limit, so the
# survey's points have all arrived too; no sleeps.
set -euo pipefail
bin=$(realpath "$1")
data=$(realpath "$2")
here=$(cd "$(dirname "$0")" && pwd)
viewer_tests="$here/../viewer"
work=$(mktemp -d /tmp/ladarvr-viewsurvey.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$viewer_tests/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export XDG_CACHE_HOME="$work/cache"
fail() { echo "view_real_survey_test: FAIL: $*" >&2; exit 1; }

# view NAME FRAMES CLOUD... -- ARGS...: a headless run, stderr in NAME.err (and added to
# NAME.all), log NAME.json
view() {
    local name=$1 frames=$2
    shift 2
    local clouds=()
    while [ "$1" != "--" ]; do clouds+=("$1"); shift; done
    shift
    local status=0
    rm -f "$work/$name.json"
    "$viewer_tests/headless_env.sh" --timeout 200 -- "$bin" view "${clouds[@]}" --no-xr --frames "$frames" \
      --width 320 --height 180 --timeout 180 --log-json "$work/$name.json" "$@" 2>"$work/$name.err" || status=$?
    [ "$status" = 0 ] || { cat "$work/$name.err" >&2; fail "view $name exited $status"; }
    cat "$work/$name.err" >>"$work/$name.all"  # every run's lines
}
# log NAME EXPR: prints the Python expression EXPR of the run log j (e.g. j.get('terrain')).
log() { python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($2)" "$work/$1.json"; }
# until_terrain NAME CLOUD... -- ARGS...: views with more frames each time until the log
# shows the terrain (or its failure) and every point arrived.
until_terrain() {
    local name=$1
    shift
    for frames in 10 60 300 1500 6000; do
        view "$name" "$frames" "$@"
        [ "$(log "$name" "'terrain' in j and j['first_points_frame'] >= 0")" = True ] && return 0
    done
    fail "$name: no terrain in the log after 6000 frames: $(cat "$work/$name.err")"
}

# 1. The file's class 2: hexbin-crop.las holds 35,318 class 2 points of 38,367.
until_terrain class2 "$data/hexbin-crop.las" -- --colour above-ground
[ "$(log class2 "j['terrain'].get('source')")" = "the file's class 2 (35,318 points)" ] ||
  fail "class 2 terrain: $(log class2 "j['terrain']")"
[ "$(log class2 "j['terrain']['cells'] > 0")" = True ] || fail "class 2 terrain without cells"
grep -q "^ladarvr: view: above-ground colours from the file's class 2 (35,318 points)$" "$work/class2.err" ||
  fail "no terrain line: $(cat "$work/class2.err")"

# 2. No class 2: the terrain is fitted by SMRF on the file's 345,966 points.
until_terrain smrf "$data/FSite8_orig-utm.laz" -- --colour above-ground
[ "$(log smrf "j['terrain'].get('source')")" = "a terrain fitted by SMRF on 345,966 of its points" ] ||
  fail "fitted terrain: $(log smrf "j['terrain']")"
grep -q "^ladarvr: view: above-ground colours from a terrain fitted by SMRF on 345,966 of its points$" "$work/smrf.err" ||
  fail "no terrain line: $(cat "$work/smrf.err")"

# 3. Heights above ground in the file: no terrain is built, and in another colour mode
# none either.
"$bin" ground "$data/hexbin-crop.las" --out "$work/hag.las" 2>"$work/ground.err" || fail "ground: $(cat "$work/ground.err")"
view hag 10 "$work/hag.las" -- --colour above-ground
[ "$(log hag "'terrain' in j")" = False ] || fail "a terrain for a file with heights: $(log hag "j['terrain']")"
view filemode 10 "$data/hexbin-crop.las" -- --colour file
[ "$(log filemode "'terrain' in j")" = False ] || fail "a terrain in file colours: $(log filemode "j['terrain']")"

# 4. Two tiles of one survey (hexbin-crop.las cut at its middle x), viewed as one.
mkdir "$work/tiles"
python3 - "$data/hexbin-crop.las" "$work/tiles" <<'PY'
import sys
import laspy
import numpy as np
src = laspy.read(sys.argv[1])
mid = np.median(src.x)
for name, keep in (("west.las", src.x < mid), ("east.las", src.x >= mid)):
    tile = laspy.LasData(src.header)
    tile.points = src.points[keep]
    tile.write(sys.argv[2] + "/" + name)
PY
echo "not a cloud" >"$work/tiles/README.txt"
until_terrain survey "$work/tiles" -- --colour above-ground
grep -q "^ladarvr: view: indexing the survey of 2 files (38367 points) into $work/cache/ladarvr/index-" \
  "$work/survey.all" || fail "no survey indexing line: $(cat "$work/survey.all")"
grep -q "is COPC: .* 38367 points, read node by node .*(the survey of 2 files)$" "$work/survey.err" ||
  fail "the survey's index is not opened: $(cat "$work/survey.err")"
[ "$(log survey "j['points_arrived']")" = 38367 ] || fail "points in the survey's log: $(log survey "j['points_arrived']")"
log survey "j['terrain'].get('source', '')" | grep -q "^the survey's class 2 ([0-9,]* points)$" ||
  fail "survey terrain: $(log survey "j['terrain']")"
# The files in name order are the folder's: the same survey, its index reused.
view sorted 10 "$work/tiles/east.las" "$work/tiles/west.las" --
grep -q "^ladarvr: view: the survey of 2 files is not COPC: its cached index .* is reused$" "$work/sorted.err" ||
  fail "the survey's index is not reused: $(cat "$work/sorted.err")"
[ "$(find "$work/cache/ladarvr" -name 'index-*.copc.laz' | wc -l)" = 1 ] ||
  fail "indexes: $(ls "$work/cache/ladarvr")"

# 5. Refusals: one line each, exit 1, no index written.
refused() {  # refused PATTERN ARGS...
    local pattern=$1
    shift
    local status=0
    "$bin" view "$@" --no-xr --frames 1 >"$work/refused.out" 2>"$work/refused.err" || status=$?
    [ "$status" = 1 ] && [ "$(wc -l <"$work/refused.err")" = 1 ] && grep -q -e "$pattern" "$work/refused.err" ||
      fail "view $*: exit $status: $(cat "$work/refused.err")"
}
before=$(ls "$work/cache/ladarvr")
refused "view: $data/4_6_crop.las: its CRS (.*) differs from $data/hexbin-crop.las's (.*); files viewed as one survey must share their CRS and units" \
  "$data/hexbin-crop.las" "$data/4_6_crop.las"
mkdir "$work/empty"
refused "view: cloud '$work/empty': is a directory; allowed: a regular file, or a folder of .las/.laz tiles" "$work/empty"
refused "view: '$work/tiles' is a folder; allowed: one folder of tiles alone" "$work/tiles" "$data/hexbin-crop.las"
refused "view: --in-core applies to one cloud file" "$work/tiles" --in-core
refused "view: .*--screenshot.*tiles/north.las" "$work/tiles" --screenshot "$work/tiles/north.las"
[ "$(ls "$work/cache/ladarvr")" = "$before" ] || fail "a refused run changed the cache: $(ls "$work/cache/ladarvr")"
echo "view_real_survey_test: ok"
