#!/usr/bin/env bash
# tests/safety/run_paths_test.sh: a run's paths as a careless or hostile user gives them.
# Usage: run_paths_test.sh LADARVR_BINARY SCRATCH_DIR
# - no output of a run may be one of its inputs (the scene, a mesh, a cloud inside the
#   metric's folder) or another of its outputs: refused before any work, nothing written;
# - every output is checked, and written, before the first one lands (--dtm on a full
#   disk leaves no cloud);
# - paths longer than the system opens: one line, exit 1, the path shortened;
# - output folders: never a symbolic link, the right words for a file or a dangling link;
# - bounded memory: detect --memory-mb refuses a cloud too big from its header alone;
#   metric --trace streams the trace and caps the poses it keeps.
# The disk-full case mounts a tmpfs (root only) and is skipped with a message elsewhere.
set -euo pipefail
bin=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir"
mnt="$dir/tmpfs"
cleanup() { mountpoint -q "$mnt" 2>/dev/null && umount "$mnt" || true; }
trap cleanup EXIT
# KEEP_GOING=1 reports every failing case instead of stopping at the first (to see which
# cases an older build fails).
failures=0
fail() {
    echo "FAIL: $*" >&2
    [ "${KEEP_GOING:-0}" = 1 ] || exit 1
    failures=$((failures + 1))
}
scene_src=$(cd "$(dirname "$0")/../data/scenes/basic" && pwd)
small=(--xres 16 --yres 16 --views 2)

# Runs the CLI expecting exit 1 and one error line containing $1.
refused() {
    local expect=$1
    shift
    local status=0
    "$bin" "$@" >"$dir/out.txt" 2>"$dir/err.txt" || status=$?
    [ "$status" -eq 1 ] || { fail "${*:1:4}... exited $status, expected 1: $(head -c 600 "$dir/err.txt")"; return 0; }
    grep -q -F -e "$expect" "$dir/err.txt" || { fail "${*:1:4}...: error does not say '$expect': $(head -c 600 "$dir/err.txt")"; return 0; }
    [ "$(grep -c -v ': warning: ' "$dir/err.txt")" -eq 1 ] || fail "${*:1:4}...: more than one line: $(head -c 600 "$dir/err.txt")"
}
no_temporaries() {
    local left
    left=$(ls -A "$1" | grep '^\.ladarvr-tmp-' || true)
    [ -z "$left" ] || fail "temporaries left in $1: $left"
}

"$bin" generate "${small[@]}" --out "$dir/cloud.pcd" 2>/dev/null || fail "the small cloud was not generated"

# --- two outputs of one run under one name: refused before any work ---
two="$dir/two"
mkdir -p "$two"
refused "generate: --out '$two/x.asc' and --dtm '$two/x.asc' name the same file" \
    generate "${small[@]}" --format pcd --out "$two/x.asc" --dtm "$two/x.asc"
refused "name the same file" generate "${small[@]}" --format pcd --out "$two/x.asc" --dtm "$two/./sub/../x.asc"
[ -z "$(ls -A "$two")" ] || fail "generate with one name for two outputs wrote: $(ls -A "$two")"
refused "view: --screenshot '$two/f.png' and --log-json '$two/f.png' name the same file" \
    view --no-xr --frames 1 --screenshot "$two/f.png" --log-json "$two/f.png" "$dir/cloud.pcd"
echo '{"trials": [{"cloud": "'"$dir/cloud.pcd"'", "time_limit_s": 10}]}' >"$two/plan.json"
refused "study: --log-json '$two/d/trace_1.csv' lies inside the output folder --out '$two/d', where this run writes 'trace_1.csv'" \
    study "$two/plan.json" --no-xr --out "$two/d" --log-json "$two/d/trace_1.csv"
[ "$(ls -A "$two")" = plan.json ] || fail "study with its log among its traces wrote: $(ls -A "$two")"

# --- metric --out DIR never deletes an input stored in DIR under a metric name ---
mf="$dir/metricfolder"
mkdir -p "$mf/report"
cp "$dir/cloud.pcd" "$mf/report/view_0_i1.png"
refused "metric: --p1 '$mf/report/view_0_i1.png' lies inside the output folder --out '$mf/report', which this run replaces as a whole" \
    metric --p1 "$mf/report/view_0_i1.png" --p2 "$dir/cloud.pcd" --p3 "$dir/cloud.pcd" --views 2 --width 32 --height 32 \
    --out "$mf/report"
cmp -s "$dir/cloud.pcd" "$mf/report/view_0_i1.png" || fail "metric deleted or changed its input cloud"
# The same through a link to the input's folder.
ln -s "$mf/report" "$mf/alias"
refused "lies inside the output folder" metric --p1 "$mf/alias/view_0_i1.png" --p2 "$dir/cloud.pcd" \
    --p3 "$dir/cloud.pcd" --views 2 --width 32 --height 32 --out "$mf/report"
cmp -s "$dir/cloud.pcd" "$mf/report/view_0_i1.png" || fail "metric deleted its input cloud (given through a link)"

# --- metric --out: a link to a folder is not followed; a file and a dangling link named as such ---
mkdir -p "$mf/mine"
"$bin" metric --views 2 --width 32 --height 32 --no-exact --out "$mf/mine/report" >/dev/null 2>"$dir/err.txt" ||
    fail "metric failed: $(cat "$dir/err.txt")"
before=$(cd "$mf/mine/report" && ls && cat ./* | sha256sum)
ln -s "$mf/mine/report" "$mf/link"
refused "output: $mf/link: is a symbolic link; refusing to follow it" \
    metric --views 2 --width 48 --height 48 --no-exact --out "$mf/link"
[ "$(cd "$mf/mine/report" && ls && cat ./* | sha256sum)" = "$before" ] || fail "metric replaced a folder through a link"
[ -L "$mf/link" ] || fail "the link was replaced"
echo text >"$mf/file.txt"
refused "output: $mf/file.txt: is a regular file, not a folder" metric --views 2 --no-exact --out "$mf/file.txt"
[ "$(cat "$mf/file.txt")" = text ] || fail "metric replaced a file"
ln -s "$mf/gone" "$mf/dangling"
refused "study: --out '$mf/dangling/trials.csv': '$mf/dangling' is a dangling symbolic link" \
    study "$two/plan.json" --no-xr --out "$mf/dangling"
[ ! -e "$mf/gone" ] || fail "study created the folder a dangling link points to"

# --- --dtm: an input of the run is refused before the cloud is written ---
in="$dir/inputs"
cp -r "$scene_src" "$in"
cp "$in/scene.json" "$in/scene.asc"
before=$(cat "$in/scene.asc" "$in/box.obj" | sha256sum)
refused "generate: --scene '$in/scene.asc' and --dtm '$in/scene.asc' name the same file" \
    generate "${small[@]}" --scene "$in/scene.asc" --out "$in/cloud.pcd" --dtm "$in/scene.asc"
[ ! -e "$in/cloud.pcd" ] || fail "the cloud was written although --dtm names the scene"
# A mesh of the scene (a hard link to it): known as an input only once the scene is read,
# still before a ray is cast.
ln "$in/box.obj" "$in/box.asc"
refused "is the input file" generate "${small[@]}" --scene "$in/scene.json" --out "$in/cloud.pcd" --dtm "$in/box.asc"
[ ! -e "$in/cloud.pcd" ] || fail "the cloud was written although --dtm names a mesh"
[ "$(cat "$in/scene.asc" "$in/box.obj" | sha256sum)" = "$before" ] || fail "an input was changed"
no_temporaries "$in"
refused "generate: --dtm $dir/terrain.txt: allowed a name ending in .asc" \
    generate "${small[@]}" --out "$dir/c2.pcd" --dtm "$dir/terrain.txt"
[ ! -e "$dir/c2.pcd" ] && [ ! -e "$dir/terrain.txt" ] || fail "generate wrote with a --dtm of the wrong kind"

# --- paths longer than the system opens: one short line, exit 1 ---
long="$dir/$(printf 'a%.0s' $(seq 1 4300))"
longname="$dir/$(printf 'b%.0s' $(seq 1 300)).pcd"
check_long() {
    refused "$1" "${@:2}"
    [ "$(wc -c <"$dir/err.txt")" -lt 400 ] || fail "${*:2:2}: the message is $(wc -c <"$dir/err.txt") bytes long"
}
check_long "generate: --out: $dir/aaa" generate "${small[@]}" --out "$long.pcd"
grep -q -F "bytes long; allowed at most 4095 bytes" "$dir/err.txt" || fail "no length in: $(cat "$dir/err.txt")"
check_long "allowed at most 255 bytes per name" generate "${small[@]}" --out "$longname"
check_long "generate: --dtm: $dir/aaa" generate "${small[@]}" --out "$dir/c3.pcd" --dtm "$long.asc"
check_long "detect: --out: $dir/aaa" detect "$dir/cloud.pcd" --out "$long.json"
check_long "metric: --out: $dir/aaa" metric --views 2 --no-exact --out "$long"
check_long "view: --log-json: $dir/aaa" view --no-xr --frames 1 --log-json "$long.json" "$dir/cloud.pcd"
[ ! -e "$dir/c3.pcd" ] || fail "generate wrote a cloud with an over-long --dtm"

# --- detect --memory-mb: a cloud declaring more points than fit is refused from its header ---
big="$dir/big.pcd"
printf '# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2000000\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2000000\nDATA binary\n' >"$big"
truncate -s $(( $(stat -c %s "$big") + 2000000 * 12 )) "$big"  # sparse: no disk used
refused "detect: --memory-mb 100 is too small: this run needs at least" detect "$big" --out "$dir/c.json" --memory-mb 100
grep -q -F "a cloud of 2000000 points" "$dir/err.txt" || fail "detect does not say why: $(cat "$dir/err.txt")"
[ ! -e "$dir/c.json" ] || fail "detect wrote candidates although it refused"
refused "detect: --memory-mb = 0: allowed [1, 1048576]" detect "$dir/cloud.pcd" --out "$dir/c.json" --memory-mb 0
"$bin" detect --help | grep -q -F -e "--memory-mb" || fail "detect --help does not list --memory-mb"
"$bin" detect --help | grep -- "--memory-mb" | grep -q "512" || fail "detect --help does not give --memory-mb's default"
"$bin" detect "$dir/cloud.pcd" --out "$dir/c.json" >/dev/null 2>"$dir/err.txt" || fail "detect failed: $(cat "$dir/err.txt")"
# metric --p1/--p2/--p3 and view's cloud file: the same rule, from the headers.
refused "metric: --memory-mb 100 is too small: this run needs at least" metric --p1 "$big" --p2 "$dir/cloud.pcd" \
    --p3 "$dir/cloud.pcd" --out "$dir/m_big" --memory-mb 100
grep -q -F "points, --p1, --p2 and --p3 read whole" "$dir/err.txt" || fail "metric does not say why: $(cat "$dir/err.txt")"
[ ! -e "$dir/m_big" ] || fail "metric made its folder although it refused"
refused "view: --memory-mb 100 is too small: this run needs at least" view "$big" --no-xr --frames 1 --memory-mb 100
refused "view: --memory-mb = 0: allowed [1, 1048576]" view "$dir/cloud.pcd" --no-xr --frames 1 --memory-mb 0
"$bin" metric --help | grep -- "--memory-mb" | grep -q "512" || fail "metric --help does not give --memory-mb's default"
printf '{"trials": [{"cloud": "%s"}]}\n' "$big" >"$dir/bigplan.json"
refused "study: --memory-mb 100 is too small: this run needs at least" study "$dir/bigplan.json" --no-xr \
    --out "$dir/s_big" --memory-mb 100
grep -q -F "trial 1's cloud held whole" "$dir/err.txt" || fail "study does not say why: $(cat "$dir/err.txt")"
[ ! -e "$dir/s_big" ] || fail "study made its folder although it refused"

# --- metric --trace: streamed, and the poses it keeps are capped ---
# Peak resident memory of a command (python's getrusage of its child), in MiB.
peak_mib() {
    python3 -c 'import resource, subprocess, sys
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
if r.returncode != 0: sys.exit("exit %d" % r.returncode)
print(int(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024))' "$@"
}
tr="$dir/trace.csv"
demo=$(cd "$(dirname "$0")/../../assets/demo" && pwd)/scene.json  # a trace outside a study names no scene
awk 'BEGIN { print "t_s,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz";
             for (i = 0; i < 3000000; i++) printf "%.3f,0,-60,40,1,0,0,0\n", i / 1000 }' >"$tr"
head -n 4 "$tr" >"$dir/short.csv"
refused "metric: --trace $tr: more than 1000000 samples are at least 0 s apart; allowed at most 1000000 views (raise --trace-step-s)" \
    metric --trace "$tr" --scene "$demo" --trace-step-s 0 --no-exact --width 16 --height 16 --out "$dir/tm"
# Every 1000 s: 3 views (0, 1000, 2000 s) of a 77 MB trace, read without holding it: the
# run's peak memory is that of a 3-row trace's run, give or take the allocator.
trace_run=(metric --scene "$demo" --trace-step-s 1000 --no-exact --width 16 --height 16 --out "$dir/tm")
"$bin" "${trace_run[@]}" --trace "$tr" >"$dir/out.txt" 2>"$dir/err.txt" || fail "metric --trace failed: $(cat "$dir/err.txt")"
grep -q -F "3 of 3000000 samples used" "$dir/out.txt" || fail "metric --trace kept the wrong samples: $(cat "$dir/out.txt")"
base_mib=$(peak_mib "$bin" "${trace_run[@]}" --trace "$dir/short.csv") || fail "metric on a short trace failed"
long_mib=$(peak_mib "$bin" "${trace_run[@]}" --trace "$tr") || fail "metric on a long trace failed"
[ "$long_mib" -le $((base_mib + 48)) ] ||
    fail "metric --trace holds the trace: peak $long_mib MiB on 3 M rows, $base_mib MiB on 3 rows"

# --- a full disk under --dtm: refused before the cloud lands, nothing left anywhere ---
mkdir -p "$mnt"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=16k tmpfs "$mnt" 2>/dev/null; then
    refused "No space left on device" generate --xres 64 --yres 64 --views 4 --out "$dir/full.pcd" --dtm "$mnt/dtm.asc"
    [ ! -e "$dir/full.pcd" ] || fail "the cloud was written although --dtm could not be"
    [ -z "$(ls -A "$mnt")" ] || fail "a full disk left files: $(ls -A "$mnt")"
    no_temporaries "$dir"
    umount "$mnt"
else
    echo "safety.run_paths: mounting a tmpfs needs root: the disk-full case is skipped"
fi
[ "$failures" -eq 0 ] || { echo "safety.run_paths: $failures failures"; exit 1; }
echo "safety.run_paths: all cases passed"
