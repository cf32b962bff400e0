#!/usr/bin/env bash
# tests/safety/corpus_safety_test.sh LADARVR SCRATCH SCENE: `ladarvr corpus` as a careless or
# hostile user drives it (docs/stress.md, "Safety"):
# - --histogram / --plan onto the corpus's own files (manifest, corpus.json, an item's
#   cloud) is refused before any work and the file is unchanged;
# - a planted DIR/items symlink is refused, nothing is made where it points;
# - a FIFO or device node at the lock file, a symlink at the manifest or corpus.json is
#   refused with words naming the file (never "Too many levels of symbolic links");
# - the stale-temporary cleanup removes only what a run makes (regular files; item
#   folders holding only item files), never a FIFO, a link or a foreign folder tree;
# - a SPEC whose vary nests 100,000 arrays is one line, no crash;
# - a SPEC counting 10^8 items reaches its first item without a list of them in memory
#   (held there by the LADARVR_TEST_HOLD_ITEM hook, then killed);
# - a target_files entry that cannot be read names vary.target_files[0], not meshes[0];
# - a mesh's reflectance and class reach the items' scene.json;
# - options of another mode (SPEC --select) are refused, not ignored;
# - --column on a manifest without numeric columns names no empty list.
set -euo pipefail
bin=$1
dir=$2
scene=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }
# Runs the CLI expecting exit 1 and one line on stderr that contains $1.
refused() {
    local expect=$1
    shift
    local status=0
    "$bin" "$@" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq 1 ] || fail "$* exited $status, expected 1: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "$*: not one line: $(cat "$dir/err")"
    grep -q -F -e "$expect" "$dir/err" || fail "$*: error lacks '$expect': $(cat "$dir/err")"
}

cat >"$dir/spec.json" <<END
{"scene": "$scene", "count": 2, "seed": 5,
 "vary": {"target_yaw_deg": {"min": 0, "max": 360}, "resolution": 8, "views": 3}}
END
"$bin" corpus "$dir/spec.json" --out "$dir/c" 2>"$dir/build.log" || fail "build: $(cat "$dir/build.log")"
c=$dir/c

# --- outputs onto the inputs of --stats / --select ----------------------------------
sums() { md5sum "$c/manifest.jsonl" "$c/corpus.json" "$c/items/0000/cloud.pcd"; }
before=$(sums)
refused "inside the input folder" corpus --stats "$c" --histogram "$c/manifest.jsonl"
refused "inside the input folder" corpus --stats "$c" --histogram "$c/items/0000/cloud.pcd"
refused "inside the input folder" corpus --stats "$c" --select "points>0" --count 1 --plan "$c/manifest.jsonl"
refused "inside the input folder" corpus --stats "$c" --select "points>0" --count 1 --plan "$c/corpus.json"
# A hard link to the manifest elsewhere is the same file.
ln "$c/manifest.jsonl" "$dir/manifest-link.jsonl"
refused "is the input file" corpus --stats "$c" --histogram "$dir/manifest-link.jsonl"
[ "$(sums)" = "$before" ] || fail "an output replaced a file of the corpus"
# Beside the manifest, the defaults still go.
"$bin" corpus --stats "$c" >/dev/null 2>"$dir/err" || fail "stats: $(cat "$dir/err")"
[ -f "$c/histogram.png" ] || fail "no DIR/histogram.png"

# --- a planted DIR/items symlink ----------------------------------------------------
mkdir -p "$dir/planted" "$dir/elsewhere"
ln -s "$dir/elsewhere" "$dir/planted/items"
refused "is a symbolic link; allowed: a folder this command made" corpus "$dir/spec.json" --out "$dir/planted"
[ -z "$(ls -A "$dir/elsewhere")" ] || fail "corpus created items where DIR/items points: $(ls -A "$dir/elsewhere")"

# --- lock file, manifest and corpus.json must be regular files we created -----------
mkdir -p "$dir/fifolock"
mkfifo "$dir/fifolock/manifest.jsonl.lock"
refused "manifest.jsonl.lock: is a FIFO (named pipe); allowed: a regular file this command created" \
    corpus "$dir/spec.json" --out "$dir/fifolock"
[ -p "$dir/fifolock/manifest.jsonl.lock" ] || fail "the planted FIFO lock is gone"
if mknod "$dir/devnull" c 1 3 2>/dev/null; then
    mkdir -p "$dir/devlock"
    mv "$dir/devnull" "$dir/devlock/manifest.jsonl.lock"
    refused "is a character device; allowed: a regular file this command created" \
        corpus "$dir/spec.json" --out "$dir/devlock"
fi
cp -a "$c" "$dir/linked"
mv "$dir/linked/manifest.jsonl" "$dir/linked/real-manifest.jsonl"
ln -s real-manifest.jsonl "$dir/linked/manifest.jsonl"
refused "corpus: manifest $dir/linked/manifest.jsonl: is a symbolic link; allowed: a regular file" \
    corpus "$dir/spec.json" --out "$dir/linked"
cp -a "$c" "$dir/linkedrec"
mv "$dir/linkedrec/corpus.json" "$dir/linkedrec/real-corpus.json"
ln -s real-corpus.json "$dir/linkedrec/corpus.json"
refused "corpus: record $dir/linkedrec/corpus.json: is a symbolic link" corpus "$dir/spec.json" --out "$dir/linkedrec"
grep -q manifest "$dir/err" && fail "corpus.json called the manifest: $(cat "$dir/err")"

# --- stale temporaries: only what a run makes goes ----------------------------------
sh -c 'exit 0' &
dead=$!
wait "$dead"
items=$c/items
mkdir -p "$items/.ladarvr-tmp-$dead-abcdef/sub"
echo keep >"$items/.ladarvr-tmp-$dead-abcdef/sub/data"
mkfifo "$items/.ladarvr-tmp-$dead-fifo01"
ln -s /etc/hostname "$items/.ladarvr-tmp-$dead-link01"
mkdir "$items/.ladarvr-tmp-$dead-0009"
echo '{}' >"$items/.ladarvr-tmp-$dead-0009/scene.json"
echo precious >"$items/.ladarvr-tmp-$dead-0009/precious.txt"
mkdir "$items/.ladarvr-tmp-$dead-0008"
echo '{}' >"$items/.ladarvr-tmp-$dead-0008/scene.json"
echo x >"$items/.ladarvr-tmp-$dead-0008/.ladarvr-tmp-$dead-Q1w2E3"
echo x >"$items/.ladarvr-tmp-$dead-Zx9Yw8"
"$bin" corpus "$dir/spec.json" --out "$c" 2>"$dir/err" || fail "rerun: $(cat "$dir/err")"
[ -f "$items/.ladarvr-tmp-$dead-abcdef/sub/data" ] || fail "the cleanup removed a folder tree it did not make"
[ -p "$items/.ladarvr-tmp-$dead-fifo01" ] || fail "the cleanup removed a FIFO"
[ -L "$items/.ladarvr-tmp-$dead-link01" ] || fail "the cleanup removed a symbolic link"
[ -f "$items/.ladarvr-tmp-$dead-0009/precious.txt" ] || fail "the cleanup removed a folder holding a foreign file"
[ ! -e "$items/.ladarvr-tmp-$dead-0008" ] || fail "a dead run's item folder (an item's files only) was left"
[ ! -e "$items/.ladarvr-tmp-$dead-Zx9Yw8" ] || fail "a dead run's temporary file was left"

# --- a SPEC nesting 100,000 arrays --------------------------------------------------
python3 - "$dir/deep.json" "$scene" <<'PY'
import sys
n = 100000
open(sys.argv[1], "w").write('{"scene": "%s", "count": 2, "vary": {"altitude_m": %s%s}}' % (sys.argv[2], "[" * n, "]" * n))
PY
refused "nested deeper than 256 levels; allowed at most 256" corpus "$dir/deep.json" --out "$dir/deep"

# --- count 10^8: the first item starts without a list of 10^8 items -----------------
sed 's/"count": 2/"count": 100000000/' "$dir/spec.json" >"$dir/huge.json"
mkfifo "$dir/hold"
LADARVR_TEST_HOLD_ITEM="0:$dir/hold" "$bin" corpus "$dir/huge.json" --out "$dir/huge" --threads 1 2>"$dir/huge.log" &
pid=$!
read -r held <"$dir/hold" || true
[ "$held" = "held 00000000" ] || { kill -9 "$pid"; fail "the run did not reach item 0: '$held' $(cat "$dir/huge.log")"; }
peak_kb=$(awk '/^VmHWM:/ {print $2}' "/proc/$pid/status")
kill -9 "$pid"
wait "$pid" 2>/dev/null || true
[ "$peak_kb" -lt 262144 ] || fail "a SPEC of 10^8 items held $peak_kb kB before its first item"

# --- target_files that cannot be read name their key --------------------------------
cat >"$dir/badtarget.json" <<END
{"scene": "$scene", "count": 2, "vary": {"target_files": ["/proc/self/mem"]}}
END
refused "vary.target_files[0]" corpus "$dir/badtarget.json" --out "$dir/badtarget"
grep -q "meshes\[0\]" "$dir/err" && fail "a target_files entry blamed meshes[0]: $(cat "$dir/err")"

# --- a mesh's reflectance and class reach the items ----------------------------------
python3 - "$scene" "$dir/refl_scene.json" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
base = os.path.dirname(os.path.abspath(sys.argv[1]))
for m in s["meshes"]:
    m["file"] = os.path.normpath(os.path.join(base, m["file"]))
s["meshes"][2]["reflectance"] = 0.125
s["meshes"][2]["class"] = 6
json.dump(s, open(sys.argv[2], "w"))
PY
sed "s|\"scene\": \"$scene\"|\"scene\": \"$dir/refl_scene.json\"|" "$dir/spec.json" >"$dir/refl.json"
"$bin" corpus "$dir/refl.json" --out "$dir/refl" 2>"$dir/err" || fail "reflectance corpus: $(cat "$dir/err")"
python3 - "$dir/refl/items/0000/scene.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))["meshes"][2]
assert m.get("reflectance") == 0.125 and m.get("class") == 6, m
PY

# --- options of another mode are refused ---------------------------------------------
status=0
"$bin" corpus "$dir/spec.json" --out "$dir/mode" --select "points>0" 2>"$dir/err" || status=$?
[ "$status" -eq 2 ] && grep -q -e "--select does not go with SPEC" "$dir/err" ||
    fail "SPEC --select: $status $(cat "$dir/err")"
[ ! -e "$dir/mode" ] || fail "SPEC --select built a corpus"
status=0
"$bin" corpus --stats "$c" --jobs 2 2>"$dir/err" || status=$?
[ "$status" -eq 2 ] && grep -q -e "--jobs does not go with --stats" "$dir/err" || fail "--stats --jobs: $status $(cat "$dir/err")"

# --- --column on a manifest without numeric columns ---------------------------------
mkdir -p "$dir/bare"
printf '{"index": 0, "id": "0000"}\n' >"$dir/bare/manifest.jsonl"
refused "allowed none (the manifest's lines hold no numeric column)" corpus --stats "$dir/bare" --column metric

# --- numbers in --select are decimal, as every number option -------------------------
refused "does not end in a finite decimal number" corpus --stats "$c" --select "points>0x10" --count 1
refused "does not end in a finite decimal number" corpus --stats "$c" --select "points>nan" --count 1

# --- an output path longer than the system can open ----------------------------------
long=$dir/$(printf 'a%.0s' $(seq 1 200))
for _ in $(seq 1 21); do long=$long/$(printf 'b%.0s' $(seq 1 200)); done
refused "bytes long; allowed at most 4095 bytes" corpus --stats "$c" --histogram "$long/h.png"
grep -q -F "$(printf 'b%.0s' $(seq 1 200))/$(printf 'b%.0s' $(seq 1 200))" "$dir/err" &&
    fail "the long path is not shortened in the message: $(wc -c <"$dir/err") bytes"

echo "corpus safety: all checks passed"
