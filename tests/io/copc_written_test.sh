#!/bin/sh
# copc_written_test.sh LADARVR COPC_TOOL NPM_DIR SCRATCH: the COPC files our writer makes
# (generate --out X.copc.laz in memory and past its memory bound, index from memory, index
# past its memory bound) pass `index --check` (the COPC rules, io::checkCopc) and are read
# by copc.js, a real client,
# exactly as io::CopcReader reads them (copcjs_test.sh). A copy with one chunk's bytes
# broken fails the check with a finding line on stdout and exit 1.
set -eu
bin="$1"
tool="$2"
npm="$3"
dir="$4"
here="$(cd "$(dirname "$0")" && pwd)"
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# A cloud of a few hundred thousand points in nodes of at most 100,000: several octree levels.
"$bin" generate --xres 128 --yres 128 --views 24 --node-points 100000 --out "$dir/gen.copc.laz" 2>"$dir/gen.log" ||
    fail "generate to COPC: $(cat "$dir/gen.log")"
"$bin" generate --xres 128 --yres 128 --views 100 --out "$dir/plain.pcd" 2>"$dir/plain.log" ||
    fail "generate to PCD: $(cat "$dir/plain.log")"
"$bin" index "$dir/plain.pcd" --out "$dir/mem.copc.laz" --node-points 100000 2>"$dir/mem.log" || fail "index: $(cat "$dir/mem.log")"
# Past the bound the points spill: at 120 MiB the spilled points all stay in memory, at
# 80 MiB some go on to a scratch file; both write the in-memory file.
for mb in 120 80; do
    "$bin" index "$dir/plain.pcd" --out "$dir/spill.copc.laz" --node-points 100000 --memory-mb $mb --threads 1 \
        2>"$dir/spill.log" || fail "index past its bound of $mb MiB: $(cat "$dir/spill.log")"
    cmp -s "$dir/mem.copc.laz" "$dir/spill.copc.laz" || fail "index past its bound of $mb MiB wrote another file"
done
# generate to COPC past its memory bound spills too (the octree's upper levels streamed
# from a scratch file) and writes the file it writes in memory.
"$bin" generate --xres 128 --yres 128 --views 100 --threads 1 --node-points 100000 --out "$dir/genmem.copc.laz" 2>"$dir/genmem.log" ||
    fail "generate to COPC in memory: $(cat "$dir/genmem.log")"
"$bin" generate --xres 128 --yres 128 --views 100 --threads 1 --node-points 100000 --memory-mb 160 \
    --out "$dir/genspill.copc.laz" \
    2>"$dir/genspill.log" || fail "generate to COPC past its bound: $(cat "$dir/genspill.log")"
cmp -s "$dir/genmem.copc.laz" "$dir/genspill.copc.laz" || fail "generate past its memory bound wrote another file"
# At 115 MiB the fusion fits in memory, but the fused cloud held there (62 MiB) would leave
# the writer less than the least it needs (56 MiB with nodes of 100,000 points on one
# thread): the run goes through the spool instead of refusing, and writes the same file.
# Past its bound there, the writer is given the points from the spool first, and sorts
# them into its octree's parts as they come instead of spilling them.
"$bin" generate --xres 128 --yres 128 --views 100 --threads 1 --node-points 100000 --memory-mb 115 \
    --out "$dir/genspool.copc.laz" \
    2>"$dir/genspool.log" || fail "generate to COPC through the spool: $(cat "$dir/genspool.log")"
cmp -s "$dir/genmem.copc.laz" "$dir/genspool.copc.laz" || fail "generate through the spool wrote another file"

for f in gen mem; do
    status=0
    "$bin" index --check "$dir/$f.copc.laz" >"$dir/$f.check" 2>"$dir/$f.err" || status=$?
    [ "$status" -eq 0 ] || fail "$f.copc.laz: index --check exit $status: $(cat "$dir/$f.check" "$dir/$f.err")"
    grep -q "valid COPC ([0-9]* nodes\{0,1\} with points" "$dir/$f.check" || fail "$f: $(cat "$dir/$f.check")"
    nodes=$(sed 's/.*valid COPC (\([0-9]*\) nodes.*/\1/' "$dir/$f.check")
    [ "$nodes" -gt 2 ] || fail "$f.copc.laz has $nodes nodes; the test wants an octree of several levels"
    sh "$here/copcjs_test.sh" "$tool" "$npm" "$dir/copcjs_$f" "$dir/$f.copc.laz" >"$dir/$f.copcjs" 2>&1 ||
        fail "copc.js on $f.copc.laz: $(cat "$dir/$f.copcjs")"
done

# The info VLR's centre moved 10 km (its data starts at 375 + 54): the cube no longer holds
# the header's bounds nor any node its points; the check says so, point by point.
python3 - "$dir/mem.copc.laz" "$dir/broken.copc.laz" <<'PY'
import struct, sys
data = bytearray(open(sys.argv[1], "rb").read())
assert data[375 + 2:375 + 6] == b"copc", "the info VLR is not first"
x, = struct.unpack_from("<d", data, 375 + 54)
struct.pack_into("<d", data, 375 + 54, x + 10000.0)
open(sys.argv[2], "wb").write(data)
PY
status=0
"$bin" index --check "$dir/broken.copc.laz" >"$dir/broken.check" 2>"$dir/broken.err" || status=$?
[ "$status" -eq 1 ] || fail "a moved cube: exit $status: $(cat "$dir/broken.check" "$dir/broken.err")"
grep -q "^index --check: .*broken.copc.laz: bounds-within-cube: " "$dir/broken.check" ||
    fail "a moved cube: no bounds-within-cube finding: $(cat "$dir/broken.check")"
grep -q "^index --check: .*broken.copc.laz: xyz: " "$dir/broken.check" ||
    fail "a moved cube: no xyz finding: $(cat "$dir/broken.check")"
[ "$(wc -l <"$dir/broken.err")" -eq 1 ] || fail "a moved cube: stderr is not one line: $(cat "$dir/broken.err")"
# The error line counts the distinct rules broken, and the lines they take on stdout.
rules=$(sed 's/^index --check: .*broken.copc.laz: \([a-z-]*\): .*/\1/' "$dir/broken.check" | sort -u | wc -l)
lines=$(wc -l <"$dir/broken.check")
grep -q "not a valid COPC file ($rules rules broken in $lines lines, listed on stdout)" "$dir/broken.err" ||
    fail "a moved cube: the error does not count $rules rules in $lines lines: $(cat "$dir/broken.err")"

# Not COPC at all: a plain LAZ is refused by the info-VLR rule.
"$bin" generate --xres 32 --yres 32 --views 4 --out "$dir/plain.laz" 2>/dev/null || fail "generate LAZ"
status=0
"$bin" index --check "$dir/plain.laz" >"$dir/plain.check" 2>/dev/null || status=$?
[ "$status" -eq 1 ] && grep -q ": copc-info: " "$dir/plain.check" || fail "a plain LAZ: $(cat "$dir/plain.check")"
echo "COPC written by ladarvr: valid, read by copc.js"
