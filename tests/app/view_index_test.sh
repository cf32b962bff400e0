#!/usr/bin/env bash
# tests/app/view_index_test.sh LADARVR: the path a cloud file that is not COPC takes in
# `ladarvr view` (app/src/view_index.cpp), headless (Xvfb, desktop mode), with
# XDG_CACHE_HOME pointed at a scratch folder:
#   1. a PCD over --index-above-mb is indexed (progress lines, "indexed now") into
#      $XDG_CACHE_HOME/ladarvr (made 0700) and viewed node by node;
#   2. the same file again: "cached index ... is reused", no indexing line, no new file;
#      the cached index damaged on disk: one warning, indexed again, viewed;
#   3. the file's modification time changes: indexed again under another name; two views
#      of a new file at once both run and leave one whole index and no temporary;
#   4. another file with a cache bound of 2.5 indexes: the least recently used index goes
#      (one line), the others and files not named as ours stay;
#   5. --in-core and a file under the threshold: streamed whole, nothing indexed;
#   6. --index-to FILE.copc.laz: indexed there, not into the cache;
#   7. a cache folder that is a symbolic link: refused with one line, exit 1, nothing
#      written through it;
#   8. options that do not go together (--index-to with a COPC file or with --in-core,
#      a name that is not .copc.laz, the cloud itself): one line each, exit 1.
# Every run ends after --frames frames (no sleeps); headless_env.sh starts and kills Xvfb.
set -euo pipefail
bin=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
viewer_tests="$here/../viewer"
work=$(mktemp -d /tmp/ladarvr-viewindex.XXXXXX)
trap 'rm -rf "$work"' EXIT
export LSAN_OPTIONS="suppressions=$viewer_tests/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
fail() { echo "view_index_test: FAIL: $*" >&2; exit 1; }

python3 "$viewer_tests/make_test_pcd.py" "$work/a.pcd"   # 163,840 points: 13.1 MiB in core
cp "$work/a.pcd" "$work/b.pcd"
export XDG_CACHE_HOME="$work/cache"
cache="$work/cache/ladarvr"

view() {  # view NAME CLOUD ARGS...: a short headless run, stderr in $work/NAME.err
    local name=$1 cloud=$2
    shift 2
    local status=0
    "$viewer_tests/headless_env.sh" --timeout 150 -- "$bin" view "$cloud" --no-xr --frames 3 --width 320 \
      --height 180 --timeout 120 "$@" 2>"$work/$name.err" || status=$?
    [ "$status" = 0 ] || { cat "$work/$name.err" >&2; fail "view $name exited $status"; }
}
indexes() { find "$cache" -maxdepth 1 -name 'index-*.copc.laz' -printf '%f\n' | sort; }

# 1. Indexed now.
view first "$work/a.pcd" --index-above-mb 1
grep -q "^ladarvr: view: indexing $work/a.pcd (163840 points) into $cache/index-" "$work/first.err" ||
  fail "no indexing line: $(cat "$work/first.err")"
grep -q "^ladarvr: view: indexing $work/a.pcd: 163840 points read, writing the octree" "$work/first.err" ||
  fail "no progress line: $(cat "$work/first.err")"
grep -q "^ladarvr: view: $work/a.pcd is not COPC: indexed now into $cache/index-[0-9a-f]\{32\}\.copc\.laz$" \
  "$work/first.err" || fail "no 'indexed now' line: $(cat "$work/first.err")"
grep -q "^ladarvr: view: $cache/index-[0-9a-f]*\.copc\.laz is COPC: .* 163840 points, read node by node" \
  "$work/first.err" || fail "the index is not opened as COPC: $(cat "$work/first.err")"
[ "$(stat -c %a "$cache")" = 700 ] || fail "cache folder mode $(stat -c %a "$cache"), expected 700"
first=$(indexes)
[ "$(printf '%s\n' "$first" | grep -c .)" = 1 ] || fail "indexes after the first run: $first"
"$bin" index --check "$cache/$first" >/dev/null || fail "the cached index is no valid COPC file"
size=$(stat -c %s "$cache/$first")

# 2. Reused: no indexing line, the same single file.
view second "$work/a.pcd" --index-above-mb 1
grep -q "indexing" "$work/second.err" && fail "the second run indexed again: $(cat "$work/second.err")"
grep -q "^ladarvr: view: $work/a.pcd is not COPC: its cached index $cache/$first is reused$" "$work/second.err" ||
  fail "no 'reused' line: $(cat "$work/second.err")"
[ "$(indexes)" = "$first" ] || fail "indexes after the reuse: $(indexes)"

# 2b. A cached index damaged on disk: the view says so, indexes again once and runs.
cp "$cache/$first" "$work/first.copc.laz"
head -c 400 "$work/first.copc.laz" >"$cache/$first"
view damaged "$work/a.pcd" --index-above-mb 1
grep -q "^ladarvr: warning: view: the cached index does not open (.*); indexing again$" "$work/damaged.err" ||
  fail "no 'indexing again' line: $(cat "$work/damaged.err")"
grep -q "is COPC: .* 163840 points, read node by node" "$work/damaged.err" ||
  fail "the index written again is not opened: $(cat "$work/damaged.err")"
"$bin" index --check "$cache/$first" >/dev/null || fail "the index written again is no valid COPC file"

# 3. A changed file (its modification time) is indexed again under another name.
touch -d '2001-02-03 04:05:06' "$work/a.pcd"
view changed "$work/a.pcd" --index-above-mb 1
grep -q "is not COPC: indexed now into" "$work/changed.err" || fail "not indexed again: $(cat "$work/changed.err")"
changed=$(indexes | grep -v -x "$first")
[ "$(printf '%s\n' "$changed" | grep -c .)" = 1 ] || fail "indexes after the change: $(indexes)"

# 3b. Two views of a new file at once: both index it into their own temporaries and
# rename them into place; both run, one whole index is left, and no temporary.
cp "$work/a.pcd" "$work/c.pcd"
cat >"$work/both.sh" <<BOTH
"$bin" view "$work/c.pcd" --no-xr --frames 3 --width 320 --height 180 --timeout 120 --index-above-mb 1 \
  2>"$work/both1.err" & one=\$!
"$bin" view "$work/c.pcd" --no-xr --frames 3 --width 320 --height 180 --timeout 120 --index-above-mb 1 \
  2>"$work/both2.err" & two=\$!
rc=0
wait \$one || rc=1
wait \$two || rc=1
exit \$rc
BOTH
"$viewer_tests/headless_env.sh" --timeout 150 -- bash "$work/both.sh" ||
  fail "two views at once: $(cat "$work/both1.err" "$work/both2.err")"
both=$(indexes | grep -v -x -e "$first" -e "$changed")
[ "$(printf '%s\n' "$both" | grep -c .)" = 1 ] || fail "indexes after two views at once: $(indexes)"
"$bin" index --check "$cache/$both" >/dev/null || fail "two views at once left no valid index"
[ -z "$(find "$cache" -name '.ladarvr-tmp-*')" ] || fail "temporaries left: $(ls -A "$cache")"
rm "$cache/$both"

# 4. The bound: three indexes of the same size over a bound of 2.5 of them; the least
# recently used (the first, reused in run 2 before the change's was written) goes. Files
# that are not named as ours are neither counted nor removed.
echo keep >"$cache/notes.txt"
echo keep >"$cache/index-not-hex.copc.laz"
bound=$(python3 -c "print($size * 2.5 / 1048576)")
view bound "$work/b.pcd" --index-above-mb 1 --index-cache-mb "$bound"
[ "$(grep -c "index cache: removed" "$work/bound.err")" = 1 ] || fail "removal lines: $(cat "$work/bound.err")"
grep -q "^ladarvr: view: index cache: removed $cache/$first (least recently used" "$work/bound.err" ||
  fail "the oldest was not the one removed: $(cat "$work/bound.err")"
[ ! -e "$cache/$first" ] || fail "the oldest index is still there"
[ -e "$cache/$changed" ] || fail "a newer index was removed"
[ "$(indexes | grep -c '^index-[0-9a-f]\{32\}')" = 2 ] || fail "indexes after the bound: $(indexes)"
[ -e "$cache/notes.txt" ] && [ -e "$cache/index-not-hex.copc.laz" ] || fail "a file not named as ours was removed"

# 5. --in-core, and a file under the threshold (the default 256 MiB): streamed whole.
before=$(indexes)
view incore "$work/b.pcd" --index-above-mb 1 --in-core
grep -q "^ladarvr: view: $work/b.pcd is not COPC: streamed and held whole$" "$work/incore.err" ||
  fail "--in-core: $(cat "$work/incore.err")"
view small "$work/b.pcd"
grep -q "^ladarvr: view: $work/b.pcd is not COPC: streamed and held whole$" "$work/small.err" ||
  fail "under the threshold: $(cat "$work/small.err")"
grep -q "indexing" "$work/incore.err" "$work/small.err" && fail "indexed in core"
[ "$(indexes)" = "$before" ] || fail "the cache changed in core: $(indexes)"

# 6. --index-to: the index where asked, whatever the size, and the cache untouched.
view indexto "$work/b.pcd" --index-to "$work/out/b.copc.laz"
grep -q "is not COPC: indexed now into $work/out/b.copc.laz (--index-to)$" "$work/indexto.err" ||
  fail "--index-to: $(cat "$work/indexto.err")"
"$bin" index --check "$work/out/b.copc.laz" >/dev/null || fail "--index-to wrote no valid COPC file"
[ "$(indexes)" = "$before" ] || fail "--index-to changed the cache: $(indexes)"

# 7. A symbolic link as the cache folder: one line, exit 1, nothing written through it.
mkdir -p "$work/linked" "$work/target"
ln -s "$work/target" "$work/linked/ladarvr"
status=0
XDG_CACHE_HOME="$work/linked" "$bin" view "$work/a.pcd" --no-xr --frames 3 --index-above-mb 1 \
  >"$work/link.out" 2>"$work/link.err" || status=$?
[ "$status" = 1 ] || fail "a linked cache folder: exit $status: $(cat "$work/link.err")"
[ "$(wc -l <"$work/link.err")" = 1 ] || fail "a linked cache folder: not one line: $(cat "$work/link.err")"
grep -q "^ladarvr: error: view: index cache $work/linked/ladarvr: is a symbolic link; allowed: a folder of this user$" \
  "$work/link.err" || fail "a linked cache folder: $(cat "$work/link.err")"
[ -z "$(ls -A "$work/target")" ] || fail "something was written through the link: $(ls -A "$work/target")"
# 8. Options that do not go together: one line each, exit 1, nothing written.
refused() {  # refused PATTERN ARGS...
    local pattern=$1
    shift
    local status=0
    "$bin" view "$@" --no-xr --frames 1 >"$work/refused.out" 2>"$work/refused.err" || status=$?
    [ "$status" = 1 ] && [ "$(wc -l <"$work/refused.err")" = 1 ] && grep -q -e "$pattern" "$work/refused.err" ||
      fail "view $*: exit $status: $(cat "$work/refused.err")"
}
refused "view: --index-to applies to a cloud file that is not COPC" "$work/out/b.copc.laz" --index-to "$work/x.copc.laz"
refused "view: --in-core and --index-to exclude each other" "$work/a.pcd" --in-core --index-to "$work/x.copc.laz"
refused "view: --index-to .*: allowed a name ending in .copc.laz" "$work/a.pcd" --index-to "$work/x.laz"
refused "view: --index-cache-mb -1: allowed \[0, 1073741824\] MiB" "$work/a.pcd" --index-cache-mb -1
refused "view: cloud .* and --index-to .* name the same file" "$work/a.pcd" --index-to "$work/a.pcd"
[ ! -e "$work/x.copc.laz" ] && [ ! -e "$work/x.laz" ] || fail "a refused run wrote an index"
echo "view_index_test: ok"
