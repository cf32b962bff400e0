#!/usr/bin/env bash
# tests/viewer/view_real_test.sh LADARVR SCENARIO: `ladarvr view` on real survey files
# (tests/data/real) headless, asserting on the screenshot and stderr. Scenarios:
#   fit     hexbin-crop.las (293 m x 201 m, 101 m of relief): the orbit fitted to the
#           cloud's extent shows the survey from outside, so the points fill the upper half
#           of the frame (the panel is in the lower left); today's fixed 60 m orbit
#           (--orbit-radius 60) sees it from inside one corner, sparse.
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
  *)
    echo "view_real_test: unknown scenario '$scenario'" >&2
    exit 2
    ;;
esac
echo "view_real_test $scenario: ok"
