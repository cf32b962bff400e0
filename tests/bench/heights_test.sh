#!/bin/sh
# tests/bench/heights_test.sh BENCH: `ladarvr bench heights` on a small real survey prints
# its three loops, each with a median and its spread, and the baseline's ratio 1.00x (no
# timing asserted); a bad --repeats is one line naming the option.
set -eu
bench=$1
data=$(cd "$(dirname "$0")/../data/real" && pwd)
out=$("$bench" heights --in "$data/mvk-thin.las" --repeats 3 --warmup 0 2>/dev/null)
echo "$out"
[ "$(echo "$out" | grep -c '^| .* | [0-9.]* \[[0-9.]*\.\.[0-9.]*\] | ')" = 3 ] || { echo "FAIL: not three rows" >&2; exit 1; }
echo "$out" | grep -q '^| running maximum only (baseline) | .* | 1.00x |' || { echo "FAIL: no baseline row" >&2; exit 1; }
if err=$("$bench" heights --repeats 0 2>&1); then echo "FAIL: --repeats 0 accepted" >&2; exit 1; fi
echo "$err" | grep -q 'bench heights: --repeats 0; allowed \[1, 1000\]' || { echo "FAIL: $err" >&2; exit 1; }
echo "heights_test: ok"
