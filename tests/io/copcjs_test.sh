#!/bin/sh
# copcjs_test.sh COPC_TOOL NODE_MODULES SCRATCH [FILE]: copc.js, a real COPC client, reads
# FILE (default: the hand-made valid COPC file that `copc_tool make` writes into SCRATCH;
# `many`: its variant of 73 nodes, `copc_tool many`; `nodes`: the file io::CopcNodeWriter
# writes in `copc_tool nodes`; any other path: that COPC file) and
# must report the same info, nodes, point counts, bounds, coordinate sums and roles as
# io::CopcReader (`copc_tool dump`). node runs under a time limit (COPCJS_TIMEOUT_S,
# default 120 s) and never outlives the test.
set -eu
tool="$1"
modules="$2/node_modules"
scratch="$3"
here="$(cd "$(dirname "$0")" && pwd)"
mkdir -p "$scratch"
rm -f "$scratch/ours.json" "$scratch/copcjs.json"
case "${4:-}" in
  "") file="$scratch/handmade.copc.laz"; "$tool" make "$file" ;;
  many) file="$scratch/many.copc.laz"; "$tool" many "$file" ;;
  nodes) file="$scratch/nodes.copc.laz"; "$tool" nodes "$file" ;;
  *) file="$4" ;;
esac
"$tool" dump "$file" >"$scratch/ours.json"
timeout -k 5 "${COPCJS_TIMEOUT_S:-120}" node "$here/copcjs_read.mjs" "$modules" "$file" >"$scratch/copcjs.json"
python3 - "$scratch/ours.json" "$scratch/copcjs.json" <<'PY'
import json, math, sys
ours, theirs = (json.load(open(p)) for p in sys.argv[1:3])
def same(a, b, path):
    if isinstance(a, dict):
        assert isinstance(b, dict) and sorted(a) == sorted(b), f"{path}: keys {sorted(a)} vs {sorted(b)}"
        for k in a: same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), f"{path}: {a} vs {b}"
        for i, (x, y) in enumerate(zip(a, b)): same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        # the info's centre and halfsize come back from copc.js through its cube
        assert math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-9), f"{path}: {a} vs {b}"
    else:
        assert a == b, f"{path}: ours {a}, copc.js {b}"
try:
    same(ours, theirs, "")
except AssertionError as e:
    sys.exit(f"copcjs_test: io::CopcReader and copc.js differ at {e}")
assert ours["points"] > 0 and ours["node_count"] > 0
print(f"copcjs_test: copc.js and io::CopcReader agree: {ours['node_count']} nodes, {ours['points']} points")
PY
