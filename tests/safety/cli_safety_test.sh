#!/usr/bin/env bash
# tests/safety/cli_safety_test.sh: `ladarvr` driven as a hostile user would, as root.
# Usage: cli_safety_test.sh LADARVR_BINARY SCRATCH_DIR
# Every case: the exit status, one error line naming the problem, and exactly which files
# exist afterwards. Special files are made inside SCRATCH_DIR (mknod only as root), never
# in /dev. The disk-full case mounts a 2 MiB tmpfs and is skipped (with a message) when
# that is not allowed.
set -euo pipefail
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
mnt="$dir/tmpfs"
cleanup() { mountpoint -q "$mnt" 2>/dev/null && umount "$mnt" || true; }
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
scene_src=$(cd "$(dirname "$0")/../data/scenes/basic" && pwd)
small=(--xres 16 --yres 16 --views 2)

# Runs the CLI expecting exit 1 and one error line containing $1.
refused() {
    local expect=$1
    shift
    local status=0
    "$bin" "$@" >"$dir/out.txt" 2>"$dir/err.txt" || status=$?
    [ "$status" -eq 1 ] || fail "$* exited $status, expected 1: $(cat "$dir/err.txt")"
    grep -q -F -e "$expect" "$dir/err.txt" || fail "$*: error does not say '$expect': $(cat "$dir/err.txt")"
    # One line (warnings about the scene itself aside).
    [ "$(grep -c -v ': warning: ' "$dir/err.txt")" -eq 1 ] || fail "$*: more than one line: $(cat "$dir/err.txt")"
}
# No temporary of ours is left in folder $1.
no_temporaries() {
    local left
    left=$(ls -A "$1" | grep '^\.ladarvr-tmp-' || true)
    [ -z "$left" ] || fail "temporaries left in $1: $left"
}

# --- 1. special files and links as destinations are refused and left as they are ---
sp="$dir/special"
mkdir -p "$sp"
mkfifo "$sp/fifo.pcd"
refused "is a FIFO (named pipe); refusing to replace it" generate "${small[@]}" --out "$sp/fifo.pcd"
[ -p "$sp/fifo.pcd" ] || fail "the FIFO was replaced"
echo "victim" >"$sp/victim"
ln -s "$sp/victim" "$sp/link.pcd"
refused "is a symbolic link; refusing to replace it" generate "${small[@]}" --out "$sp/link.pcd"
[ -L "$sp/link.pcd" ] && [ "$(cat "$sp/victim")" = victim ] || fail "the link or its target changed"
if mknod -m 666 "$sp/null" c 1 3 2>/dev/null; then
    refused "is a character device; refusing to replace it" generate "${small[@]}" --out "$sp/null"
    [ -c "$sp/null" ] || fail "the device node was replaced"
    # view --log-json and --screenshot: refused before any window opens.
    "$bin" generate "${small[@]}" --out "$sp/cloud.pcd" 2>/dev/null
    refused "is a character device" view --no-xr --log-json "$sp/null" "$sp/cloud.pcd"
    [ -c "$sp/null" ] || fail "view replaced the device node"
else
    echo "safety.cli: mknod needs root: the device-node cases are skipped"
fi
no_temporaries "$sp"

# --- 2. symlinks planted at the old predictable temporary names are not followed ---
pl="$dir/planted"
mkdir -p "$pl"
echo "unrelated" >"$pl/victim"
next=$(sh -c 'echo $$')
for p in $(seq "$next" $((next + 400))); do
    ln -s "$pl/victim" "$pl/out.pcd.tmp-$p"
    ln -s "$pl/victim" "$pl/out.pcd.spool-$p"
done
# A small budget makes these runs stream: binary PCD into the output itself, ASCII PCD
# through the spool file.
for format in pcd pcd-ascii; do
    "$bin" generate --xres 128 --yres 128 --views 8 --white --memory-mb 12 --format "$format" --out "$pl/out.pcd" \
        >/dev/null 2>"$dir/err.txt" || fail "generate ($format) with planted links failed: $(cat "$dir/err.txt")"
done
[ "$(cat "$pl/victim")" = unrelated ] || fail "a planted link was followed: the victim changed"
[ -f "$pl/out.pcd" ] && [ ! -L "$pl/out.pcd" ] || fail "no output written"
no_temporaries "$pl"

# --- 3. --out naming an input (the scene, a mesh, through links) is refused ---
in="$dir/inputs"
cp -r "$scene_src" "$in"
before=$(cat "$in/scene.json" "$in/box.obj" | sha256sum)
refused "name the same file" generate "${small[@]}" --scene "$in/scene.json" --format pcd --out "$in/scene.json"
ln "$in/box.obj" "$in/hard.pcd"
refused "is the input file" generate "${small[@]}" --scene "$in/scene.json" --out "$in/hard.pcd"
ln -s "$in" "$dir/inputs_link"
refused "is the input file" generate "${small[@]}" --scene "$in/scene.json" --format pcd --out "$dir/inputs_link/box.obj"
[ "$(cat "$in/scene.json" "$in/box.obj" | sha256sum)" = "$before" ] || fail "an input was changed"
no_temporaries "$in"

# --- 4. signals mid-write: SIGTERM 143, SIGINT 130, nothing of ours left; SIGKILL: only
#        a hidden temporary, removed by the next run ---
# Event-driven: LADARVR_TEST_HOLD_COMMIT holds the run with its output written to the
# temporary, not yet renamed into place, and says "held <temporary>" on a FIFO; the
# signal goes then. A watcher wakes the reader should the run end without holding.
sg="$dir/signals"
mkdir -p "$sg"
set -m  # background jobs keep SIGINT (a non-interactive shell would ignore it for them)
# Starts a generate into $sg/big.pcd and waits until it holds with its temporary written.
start_big() {
    rm -f "$dir/hold" && mkfifo "$dir/hold"
    LADARVR_TEST_HOLD_COMMIT="$dir/hold" "$bin" generate "${small[@]}" --out "$sg/big.pcd" >/dev/null \
        2>"$sg/err.txt" &
    big=$!
    # O_RDWR: an open that never waits; what it writes is lost once no one reads.
    (tail --pid="$big" -f /dev/null && echo "exited" 1<>"$dir/hold") &
    watcher=$!
    held=
    read -r held <"$dir/hold" || true
    case "$held" in
        "held .ladarvr-tmp-$big-"*) ;;
        *) fail "the run did not hold in its commit: '$held' $(cat "$sg/err.txt")" ;;
    esac
    [ -s "$sg/${held#held }" ] || fail "the held temporary '${held#held }' is not there, or empty: $(ls -A "$sg")"
}
for pair in TERM:143 INT:130; do
    sig=${pair%%:*}
    start_big
    kill -s "$sig" "$big"
    status=0
    wait "$big" || status=$?
    wait "$watcher" || true
    [ "$status" -eq "${pair##*:}" ] || fail "SIG$sig: exit $status, expected ${pair##*:}"
    [ "$(ls -A "$sg")" = err.txt ] || fail "SIG$sig left files: $(ls -A "$sg")"
done
start_big
kill -s KILL "$big"
wait "$big" || true
wait "$watcher" || true
[ ! -e "$sg/big.pcd" ] || fail "SIGKILL left a file under the output's name"
left=$(ls -A "$sg" | grep -v '^err.txt$')
echo "$left" | grep -q -E "^\.ladarvr-tmp-$big-[A-Za-z0-9]{6}$" || fail "SIGKILL left '$left'"
"$bin" generate "${small[@]}" --out "$sg/small.pcd" >/dev/null 2>&1 || fail "the run after SIGKILL failed"
[ "$(ls -A "$sg" | sort | tr '\n' ' ')" = "err.txt small.pcd " ] ||
    fail "the next run did not remove the dead run's temporary: $(ls -A "$sg")"
set +m

# --- 13. the metric folder after a failed run holds the previous run's whole set ---
mt="$dir/metric"
mkdir -p "$mt"
metric=(metric --views 2 --height 64 --no-exact --out "$mt/report")
"$bin" "${metric[@]}" --width 64 >/dev/null 2>"$dir/err.txt" || fail "metric failed: $(cat "$dir/err.txt")"
first=$(cd "$mt/report" && ls && cat ./* | sha256sum)
# The second run dies on the file size limit (SIGXFSZ) while writing bigger pictures.
status=0
(ulimit -c 0; ulimit -f 2; exec "$bin" metric --views 2 --width 512 --height 512 --no-exact \
    --out "$mt/report") >/dev/null 2>&1 || status=$?
[ "$status" -ne 0 ] || fail "the metric run under a 1 KiB file limit succeeded"
[ "$(cd "$mt/report" && ls && cat ./* | sha256sum)" = "$first" ] || fail "the report folder changed after a failed run"
"$bin" "${metric[@]}" --width 96 >/dev/null 2>&1 || fail "metric after a failed run failed"
grep -q '"width": 96' "$mt/report/summary.json" || fail "the new report was not swapped in"
no_temporaries "$mt"
mkdir -p "$mt/mine" && echo "keep" >"$mt/mine/notes.txt"
refused "holds 'notes.txt', which this command does not write" metric --views 2 --out "$mt/mine"
[ "$(cat "$mt/mine/notes.txt")" = keep ] || fail "a foreign folder was touched"

# --- 6. unbounded or odd script inputs are refused at once ---
"$bin" generate "${small[@]}" --out "$dir/view.pcd" 2>/dev/null
refused "is a character device" view --no-xr --script /dev/zero "$dir/view.pcd"
refused "is a directory" view --no-xr --script "$dir" "$dir/view.pcd"
mkfifo "$dir/cloud_fifo.pcd"
refused "view: cloud '$dir/cloud_fifo.pcd' is a FIFO (named pipe)" view --no-xr "$dir/cloud_fifo.pcd"
refused "is a directory; allowed: a regular file" view --no-xr "$dir"

# --- 7. crafted LAS/LAZ: one line and exit 1 from every reader of clouds, never a crash ---
# Each file is one of ours with the bytes LASzip trusts changed (tests/safety/craft_las.py).
lz="$dir/crafted"
mkdir -p "$lz"
"$bin" generate "${small[@]}" --out "$lz/ok.laz" 2>/dev/null
"$bin" generate "${small[@]}" --out "$lz/ok.las" 2>/dev/null
craft() { python3 "$(dirname "$0")/craft_las.py" "$1" "$lz/ok.$2" "$lz/$1.$2"; }
for c in compressor1:"the LASzip VLR is not one this reader knows (compressor 1" \
         compressor2:"the LASzip VLR is not one this reader knows (compressor 2" \
         cut6:"is outside the file" cut7:"is outside the file" count_high:"the chunk table lists" \
         layers_wrap:"chunk 0's layers declare" fewer_points:"chunk 0 holds"; do
    name=${c%%:*}
    craft "$name" laz
    refused "${c#*:}" detect --out "$lz/c.json" "$lz/$name.laz"
    refused "${c#*:}" metric --views 2 --p1 "$lz/$name.laz" --p2 "$lz/$name.laz" --p3 "$lz/$name.laz" --out "$lz/m"
done
craft two_extra las
refused "is a second extra bytes VLR; allowed: one per file" detect --out "$lz/c.json" "$lz/two_extra.las"
craft fewer_points las
refused "bytes follow the header's" detect --out "$lz/c.json" "$lz/fewer_points.las"
: >"$lz/empty.las"
refused "las: $lz/empty.las: truncated: a LAS header needs 227 bytes, the file has 0" detect --out "$lz/c.json" "$lz/empty.las"
[ ! -e "$lz/c.json" ] && [ ! -e "$lz/m" ] || fail "a refused cloud left an output"
# The LAS header: ladarvr and its version, the creation date of SOURCE_DATE_EPOCH
# (2024-03-01 is day 61 of 2024), and a SOURCE_DATE_EPOCH that is no number refused.
SOURCE_DATE_EPOCH=1709251200 "$bin" generate "${small[@]}" --out "$lz/dated.las" 2>/dev/null
[ "$(head -c 90 "$lz/dated.las" | tail -c 32 | tr -d '\0' | cut -c1-8)" = "ladarvr " ] || fail "generating software"
[ "$(od -An -tu2 -j90 -N4 "$lz/dated.las" | tr -s ' ')" = " 61 2024" ] || fail "creation day/year: $(od -An -tu2 -j90 -N4 "$lz/dated.las")"
SOURCE_DATE_EPOCH=yesterday refused "SOURCE_DATE_EPOCH='yesterday': allowed a whole number of seconds" \
    generate "${small[@]}" --out "$lz/undated.laz"
[ ! -e "$lz/undated.laz" ] || fail "a refused SOURCE_DATE_EPOCH left the cloud"

# --- 5/4. a full disk: one line, nothing left on the small file system ---
mkdir -p "$mnt"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=2m tmpfs "$mnt" 2>/dev/null; then
    refused "No space left on device" generate --xres 128 --yres 128 --views 32 --out "$mnt/full.pcd"
    [ -z "$(ls -A "$mnt")" ] || fail "a full disk left files: $(ls -A "$mnt")"
    # LAS through LASzip's stream and LAZ through our chunk writer: the same words.
    refused "write failed: No space left on device" generate --xres 128 --yres 128 --views 32 --out "$mnt/full.las"
    [ -z "$(ls -A "$mnt")" ] || fail "a full disk left LAS files: $(ls -A "$mnt")"
    # The metric's PNGs are compressed: a much smaller disk fills on them.
    umount "$mnt" && mount -t tmpfs -o size=8k tmpfs "$mnt"
    refused "No space left on device" metric --json --views 2 --width 1024 --height 1024 --no-exact --out "$mnt/report"
    [ -z "$(ls -A "$mnt")" ] || fail "a full disk left metric files: $(ls -A "$mnt")"
    refused "No space left on device" generate --xres 64 --yres 64 --views 8 --out "$mnt/full.laz"
    [ -z "$(ls -A "$mnt")" ] || fail "a full disk left LAZ files: $(ls -A "$mnt")"
    umount "$mnt"
else
    echo "safety.cli: mounting a tmpfs needs root: the disk-full case is skipped"
fi
echo "safety.cli: all cases passed"
