#!/bin/sh
# tests/app/cmd_ground_test.sh: `ladarvr ground` as a user runs it, on two real ISPRS
# reference samples (tests/data/isprs, bare earth labelled as LAS class 2).
# Usage: cmd_ground_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR
#  - the default (SMRF, the ISPRS-tuned set) and --method csf agree with the labels within
#    a total error bound (misclassified / all points), read from --json;
#  - the file written holds every point, its ground count as --json says (`info --json`);
#  - bad options give one line naming the option and what is allowed, exit 2 or 1, and
#    no output; the input is never overwritten;
#  - a tall roof that runs out of a small real tile is not ground;
#  - a survey in feet gets its options converted from metres (stderr says so); one in
#    degrees (a geographic CRS) is refused;
#  - --out-dir over surveys of other CRSs and units classifies each as a run over it
#    alone does, none the buffer of another, and refuses two surveys' outputs of one name;
#  - a survey far sparser than SMRF's cells gets one line saying so and what helps, and the
#    same bytes on one thread, three and the default;
#  - --noise gives the low outliers of another producer's LAS class 7 and moves no other;
#  - in a discrete-return survey a return with a later one behind it is not ground by
#    default (--returns auto), is with --returns all; a survey of single returns keeps
#    every return whatever --returns says.
set -eu
bin=$1
dir=$2
data=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

# field NAME FILE: the number after "NAME": in a --json object.
field() { sed -n "s/^ *\"$1\": \([0-9.]*\),*$/\1/p" "$2" | head -1; }

# check SAMPLE METHOD BOUND_PERCENT [OPTIONS...]: ground the sample, check the error bound.
check() {
    sample=$1 method=$2 bound=$3
    shift 3
    "$bin" ground "$data/$sample.las" --out "$dir/$sample-$method.laz" --method "$method" --json "$@" \
        >"$dir/json" 2>"$dir/err" || fail "ground $sample --method $method: $(cat "$dir/err")"
    [ -s "$dir/err" ] && fail "ground printed on stderr: $(cat "$dir/err")"
    points=$(field points "$dir/json")
    found=$(field ground_points "$dir/json")
    labelled=$(field input_ground_points "$dir/json")
    kept=$(field input_ground_points_kept "$dir/json")
    [ -n "$points" ] && [ -n "$found" ] && [ -n "$labelled" ] && [ -n "$kept" ] ||
        fail "--json lacks a count: $(cat "$dir/json")"
    # Misclassified: labelled ground called object, plus object called ground.
    error=$(awk -v n="$points" -v f="$found" -v l="$labelled" -v k="$kept" \
        'BEGIN { printf "%.3f", 100 * ((l - k) + (f - k)) / n }')
    awk -v e="$error" -v b="$bound" 'BEGIN { exit !(e <= b) }' ||
        fail "$sample --method $method: total error $error % above $bound %"
    "$bin" info --json "$dir/$sample-$method.laz" >"$dir/info" 2>"$dir/err" || fail "info: $(cat "$dir/err")"
    flat=$(tr -d ' \n' <"$dir/info")
    echo "$flat" | grep -q "\"points\":$points," || fail "$sample: the file does not hold $points points"
    echo "$flat" | grep -q "{\"class\":2,\"name\":\"ground\",\"points\":$found}" ||
        fail "$sample: the file's class 2 count is not $found: $flat"
    echo "$sample $method: total error $error % (bound $bound %)"
}

check samp24 smrf 4.3
check samp54 smrf 4.0
check samp24 csf 12.0
check samp54 csf 8.2

# Text output: one line naming the file and the counts.
"$bin" ground "$data/samp54.las" --out "$dir/text.las" >"$dir/out" 2>"$dir/err" || fail "ground text: $(cat "$dir/err")"
grep -q "^ground: wrote $dir/text.las: 8608 points, [0-9]* ground" "$dir/out" || fail "text line: $(cat "$dir/out")"

# A survey in US survey feet (tests/data/real/4_6_crop.las, its GeoTIFF keys say so): the
# options, in metres, are converted to feet, and stderr says so; the raster's 1 m cells
# are 3.28 ft wide (62 x 62 over its 200 ft x 200 ft). The same options divided by
# 3.2808 give what a run that took feet for metres gave: 1 ft cells (about 200 x 200) and
# another ground.
real=$data/../real
"$bin" ground "$real/4_6_crop.las" --out "$dir/feet.las" --json >"$dir/json" 2>"$dir/err" ||
    fail "ground feet: $(cat "$dir/err")"
[ "$(cat "$dir/err")" = "ground: coordinates in US survey feet (0.3048006 m): options converted" ] ||
    fail "ground feet: stderr: $(cat "$dir/err")"
[ "$(field nx "$dir/json") $(field ny "$dir/json") $(field cell_m "$dir/json")" = "62 62 1.0" ] ||
    fail "ground feet: raster: $(cat "$dir/json")"
feet_ground=$(field ground_points "$dir/json")
"$bin" ground "$real/4_6_crop.las" --out "$dir/feet-as-m.las" --json --smrf-cell-m 0.3048006096 \
    --smrf-window-m 5.4864109728 --smrf-threshold-m 0.1524003048 --smrf-scalar 0.381000762 \
    --low-outlier-m 1.8288036576 >"$dir/json" 2>"$dir/err" || fail "ground feet as metres: $(cat "$dir/err")"
[ "$(field nx "$dir/json")" -ge 200 ] && [ "$(field ny "$dir/json")" -ge 200 ] ||
    fail "ground feet as metres: raster: $(cat "$dir/json")"
[ "$(field ground_points "$dir/json")" != "$feet_ground" ] ||
    fail "ground feet: the same ground ($feet_ground points) with options in feet and in metres"

# A folder of unrelated surveys with --out-dir: each set of inputs of one CRS and unit is a
# survey of its own, classified as a run over it alone would (the same bytes), and the
# inputs of one are never the buffer of another's, even where the same numbers stand for
# two places. Here a survey in feet, one in UTM 42N and a copy of that one without its CRS
# and 30 m higher: as the other's buffer, either would change the other's ground.
mkdir -p "$dir/mixed"
cp "$real/4_6_crop.las" "$real/hexbin-crop.las" "$dir/mixed/"
python3 - "$real/hexbin-crop.las" "$dir/mixed/nocrs.las" <<'PY' || fail "writing a copy without a CRS"
import sys
import laspy
f = laspy.read(sys.argv[1])
f.header.vlrs = [v for v in f.header.vlrs if v.user_id != "LASF_Projection"]
f.z = f.z + 30.0
f.write(sys.argv[2])
PY
"$bin" ground "$dir/mixed" --out-dir "$dir/mixed-out" --json >"$dir/json" 2>"$dir/err" ||
    fail "ground --out-dir over mixed surveys: $(cat "$dir/err")"
[ "$(cat "$dir/err")" = "ground: $dir/mixed/4_6_crop.las and the inputs in its CRS: coordinates in US survey feet (0.3048006 m): options converted" ] ||
    fail "mixed surveys: stderr: $(cat "$dir/err")"
[ "$(grep -c '"ground_points"' "$dir/json")" = 3 ] || fail "mixed surveys: --json: $(cat "$dir/json")"
for f in 4_6_crop.las hexbin-crop.las nocrs.las; do
    "$bin" ground "$dir/mixed/$f" --out-dir "$dir/alone" >/dev/null 2>&1 || fail "ground $f alone"
    cmp -s "$dir/alone/$f" "$dir/mixed-out/$f" || fail "mixed surveys: $f differs from a run over it alone"
done
python3 -c '
import json, sys
g = {o["in"].rsplit("/", 1)[-1]: o["ground_points"] for o in json.load(open(sys.argv[1]))}
assert g["nocrs.las"] == g["hexbin-crop.las"] > 30000, g
' "$dir/json" || fail "mixed surveys: the copy 30 m higher lost its ground to the other CRS's points"
# An output among a folder's tiles would be read as a tile by the next run: refused in one
# line, nothing written; in a subfolder it may go.
mkdir -p "$dir/tiles"
cp "$real/hexbin-crop.las" "$dir/tiles/"
if "$bin" ground "$dir/tiles" --out "$dir/tiles/merged.las" >/dev/null 2>"$dir/err"; then
    fail "ground --out among the tiles it reads succeeded"
fi
[ "$(wc -l <"$dir/err")" = 1 ] && grep -q "is 'merged.las' inside the input folder '$dir/tiles' of this run" "$dir/err" ||
    fail "ground --out among the tiles: $(cat "$dir/err")"
[ -e "$dir/tiles/merged.las" ] && fail "ground --out among the tiles left merged.las"
"$bin" ground "$dir/tiles" --out "$dir/tiles/sub/merged.las" >/dev/null 2>"$dir/err" ||
    fail "ground --out in a subfolder of the tiles: $(cat "$dir/err")"
"$bin" ground "$dir/mixed" --out-dir "$dir/mixed-only" --only-tile 2 >/dev/null 2>"$dir/err" ||
    fail "mixed surveys --only-tile 2: $(cat "$dir/err")"
[ "$(ls "$dir/mixed-only")" = "nocrs.las" ] || fail "--only-tile 2 wrote: $(ls "$dir/mixed-only")"
cmp -s "$dir/mixed-only/nocrs.las" "$dir/mixed-out/nocrs.las" || fail "--only-tile 2 wrote other bytes"
# Two surveys whose inputs share a stem (hexbin-crop.las, and nocrs.las renamed
# hexbin-crop.laz) would write one grid under --dtm-dir: refused in one line, nothing written.
mkdir -p "$dir/stems"
cp "$dir/mixed/hexbin-crop.las" "$dir/stems/"
"$bin" ground "$dir/mixed/nocrs.las" --out "$dir/stems/hexbin-crop.laz" >/dev/null 2>&1 || fail "writing hexbin-crop.laz"
if "$bin" ground "$dir/stems" --out-dir "$dir/stems-out" --dtm-dir "$dir/stems-dtm" >"$dir/out" 2>"$dir/err"; then
    fail "two surveys writing one grid were not refused"
fi
grep -q "^ladarvr: error: ground: .*stems-dtm/hexbin-crop.asc" "$dir/err" && [ "$(wc -l <"$dir/err")" = 1 ] ||
    fail "two surveys writing one grid: $(cat "$dir/err")"
[ ! -e "$dir/stems-out" ] && [ ! -e "$dir/stems-dtm" ] || fail "two surveys writing one grid: something was written"

# A building 26 m tall whose flat roof covers most of a small tile and runs out of it
# (tests/data/real/sample_c.las; its producer classified the roof as building, class 6,
# and the ground beside it, class 2): no point lies between roof and ground over the
# building's 15 m shadow, and the tile's edge cuts the roof. The roof is not ground; the
# producer's ground is. Misclassified against the producer's classes, from --json.
"$bin" ground "$real/sample_c.las" --out "$dir/roof.las" --json >"$dir/json" 2>"$dir/err" ||
    fail "ground sample_c: $(cat "$dir/err")"
points=$(field points "$dir/json") found=$(field ground_points "$dir/json")
labelled=$(field input_ground_points "$dir/json") kept=$(field input_ground_points_kept "$dir/json")
[ "$points $labelled $kept" = "14408 1368 1368" ] || fail "ground sample_c: counts: $(cat "$dir/json")"
[ "$found" -le 1600 ] || fail "ground sample_c: $found points called ground (the producer's ground: 1368)"

# A survey far sparser than its cells (tests/data/real/mvk-thin.las: 6,280 points over
# 5 km, in feet; 2 m cells, 762 x 763): the run says so in one line after the units', with
# the option that helps; the raster's size is the one --json reports.
"$bin" ground "$real/mvk-thin.las" --out "$dir/sparse.laz" --json --smrf-cell-m 2 >"$dir/json" 2>"$dir/err" ||
    fail "ground sparse: $(cat "$dir/err")"
[ "$(field nx "$dir/json") $(field ny "$dir/json")" = "762 763" ] || fail "ground sparse: raster: $(cat "$dir/json")"
[ "$(sed -n 2p "$dir/err")" = 'ground: 6280 points over 581406 cells of 2 m, one point per 93 cells: most of the run fills empty cells; a coarser --smrf-cell-m is faster on so sparse a survey (docs/ground.md, "Sparse surveys")' ] &&
    [ "$(wc -l <"$dir/err")" -eq 2 ] || fail "ground sparse: stderr: $(cat "$dir/err")"
# The same bytes on one thread and on three (the hole filling's sweeps shared among them,
# which is most of this run) as with the default, the cores divided by --jobs.
for threads in 1 3; do
    "$bin" ground "$real/mvk-thin.las" --out "$dir/sparse-t$threads.laz" --smrf-cell-m 2 --threads "$threads" \
        >/dev/null 2>"$dir/err" || fail "ground sparse --threads $threads: $(cat "$dir/err")"
    cmp -s "$dir/sparse.laz" "$dir/sparse-t$threads.laz" || fail "ground sparse: --threads $threads wrote other bytes"
done

# Returns (tests/data/real/mvk-thin.las: a discrete-return survey, some pulses with one
# return and some with several): by default only a pulse's last return may be ground, and
# --json counts the earlier returns the filter found on the terrain; with --returns all
# those are ground too, every other point as before. The file written holds no class 2
# point that is not its pulse's last. A survey of single returns (hexbin-crop.las) keeps
# every return whatever --returns says, as auto decides.
"$bin" ground "$real/mvk-thin.las" --out "$dir/last.las" --json >"$dir/json" 2>"$dir/err" ||
    fail "ground returns: $(cat "$dir/err")"
grep -q '"ground_returns": "last",' "$dir/json" || fail "ground returns: not last: $(cat "$dir/json")"
last_ground=$(field ground_points "$dir/json") not_last=$(field not_last_points "$dir/json")
[ "$not_last" -gt 0 ] || fail "ground returns: no earlier return on the terrain: $(cat "$dir/json")"
"$bin" ground "$real/mvk-thin.las" --out "$dir/all.las" --json --returns all >"$dir/json" 2>"$dir/err" ||
    fail "ground returns all: $(cat "$dir/err")"
grep -q '"ground_returns": "all",' "$dir/json" && [ "$(field not_last_points "$dir/json")" = 0 ] &&
    [ "$(field ground_points "$dir/json")" = $((last_ground + not_last)) ] ||
    fail "ground --returns all: not $last_ground + $not_last ground: $(cat "$dir/json")"
python3 - "$dir/last.las" "$dir/all.las" <<'PY' || fail "ground returns: the classes written"
import sys
import laspy, numpy as np
last, every = laspy.read(sys.argv[1]), laspy.read(sys.argv[2])
rn, nr = np.asarray(last.return_number), np.asarray(last.number_of_returns)
earlier = (rn >= 1) & (rn < nr)
c0, c1 = np.asarray(last.classification), np.asarray(every.classification)
assert not ((c0 == 2) & earlier).any(), "an earlier return written as class 2"
assert ((c1 == 2) & earlier).any(), "--returns all: no earlier return is ground"
moved = c0 != c1
assert earlier[moved].all() and (c1[moved] == 2).all(), "--returns moved other points"
PY
"$bin" ground "$real/hexbin-crop.las" --out "$dir/single.las" --json >"$dir/json" 2>"$dir/err" ||
    fail "ground single returns: $(cat "$dir/err")"
grep -q '"ground_returns": "all",' "$dir/json" || fail "ground single returns: not all: $(cat "$dir/json")"
single_ground=$(field ground_points "$dir/json")
"$bin" ground "$real/hexbin-crop.las" --out "$dir/single-last.las" --json --returns last >"$dir/json" 2>"$dir/err" ||
    fail "ground single returns, last: $(cat "$dir/err")"
[ "$(field ground_points "$dir/json")" = "$single_ground" ] ||
    fail "ground single returns: --returns last changed the ground: $(cat "$dir/json")"

# Its memory follows the cells that hold a point, not the 64 x 64 tiles they touch: at
# 1 m cells (1523 x 1524) the run peaks at most 80 bytes a cell above a small sample's run
# (the lowest heights of every cell of each touched tile would be 100 bytes a cell).
peak_mib() {
    python3 -c 'import resource, subprocess, sys
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
if r.returncode != 0: sys.exit("exit %d" % r.returncode)
print(int(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024))' "$@"
}
small_mib=$(peak_mib "$bin" ground "$data/samp24.las" --out "$dir/small.laz") || fail "ground samp24 failed"
sparse_mib=$(peak_mib "$bin" ground "$real/mvk-thin.las" --out "$dir/sparse.laz") || fail "ground mvk-thin failed"
[ "$sparse_mib" -le $((small_mib + 1523 * 1524 * 80 / 1048576)) ] ||
    fail "ground sparse: peak $sparse_mib MiB, $small_mib MiB on samp24: more than 80 bytes a cell"

# Bad options: one line, no output.
bad() {
    want=$1
    shift
    rm -f "$dir/bad.las"
    if "$bin" ground "$@" >"$dir/out" 2>"$dir/err"; then fail "ground $* succeeded"; fi
    [ "$(wc -l <"$dir/err")" = 1 ] || fail "ground $*: not one line: $(cat "$dir/err")"
    grep -qF -e "$want" "$dir/err" || fail "ground $*: no '$want' in: $(cat "$dir/err")"
    [ -e "$dir/bad.las" ] && fail "ground $* left $dir/bad.las"
    return 0
}
bad "--method 'pmf': allowed ransac, smrf, csf" "$data/samp24.las" --out "$dir/bad.las" --method pmf
bad "--threads 1025: allowed [0, 1024], 0 = the cores divided by --jobs" "$data/samp24.las" --out "$dir/bad.las" --threads 1025
bad "RANSAC works per view" "$data/samp24.las" --out "$dir/bad.las" --method ransac
bad "--smrf-cell-m" "$data/samp24.las" --out "$dir/bad.las" --smrf-cell-m 0
bad "--low-outlier-m" "$data/samp24.las" --out "$dir/bad.las" --low-outlier-m -1
bad "--csf-rigidness" "$data/samp24.las" --out "$dir/bad.las" --method csf --csf-rigidness 7
bad "--returns first: allowed auto, last, all" "$data/samp24.las" --out "$dir/bad.las" --returns first
bad "--memory-mb" "$data/samp24.las" --out "$dir/bad.las" --memory-mb 2
bad "--out" "$data/samp24.las" --out "$dir/bad.txt"
bad "--out $dir/bad: no extension; allowed a name ending in .las, .laz, .copc.laz, .pcd or .ply" "$data/samp24.las" \
    --out "$dir/bad"
bad "no-such.las" "$data/no-such.las" --out "$dir/bad.las"
# A geographic CRS (x and y in degrees): hexbin-crop.las with its WKT record's UTM 42N
# overwritten by WGS 84 (padded with NULs, the record's length kept).
python3 - "$real/hexbin-crop.las" "$dir/degrees.las" <<'PY'
import sys
data = bytearray(open(sys.argv[1], "rb").read())
at = data.find(b'PROJCS["WGS 84 / UTM zone 42N"')
end = data.find(b"\0", at)
wkt = (b'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],'
       b'UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],AUTHORITY["EPSG","4326"]]')
assert at > 0 and end - at > len(wkt)
data[at:end] = wkt + bytes(end - at - len(wkt))
open(sys.argv[2], "wb").write(data)
PY
bad "its CRS 'WGS 84' (EPSG:4326) is geographic (x and y in degrees), and distances in degrees cannot take options in metres; allowed a projected CRS in metres or feet" \
    "$dir/degrees.las" --out "$dir/bad.las"
cp "$data/samp24.las" "$dir/in.las"
before=$(cksum <"$dir/in.las")
if "$bin" ground "$dir/in.las" --out "$dir/in.las" >"$dir/out" 2>"$dir/err"; then fail "ground overwrote its input"; fi
[ "$(cksum <"$dir/in.las")" = "$before" ] || fail "the input changed"
# --noise: sample 41's low returns (its reference calls them objects), written by laspy as
# another producer's LAS, become class 7 when more than --low-outlier-m below the terrain;
# every other point's class is the run's without --noise.
python3 - "$data/samp41.laz" "$dir/low.las" <<'PY'
import sys
import laspy, numpy as np
src = laspy.read(sys.argv[1])
out = laspy.LasData(laspy.LasHeader(point_format=1, version="1.2"))
out.header.scales = [0.01, 0.01, 0.01]
out.header.offsets = [float(np.floor(src.x.min())), float(np.floor(src.y.min())), 0.0]
out.x, out.y, out.z = src.x, src.y, src.z
out.classification = np.asarray(src.classification)
out.write(sys.argv[2])
PY
"$bin" ground "$dir/low.las" --out "$dir/low-plain.las" >"$dir/out" 2>"$dir/err" || fail "ground low.las: $(cat "$dir/err")"
"$bin" ground "$dir/low.las" --out "$dir/low-noise.las" --noise --json >"$dir/json" 2>"$dir/err" ||
    fail "ground low.las --noise: $(cat "$dir/err")"
python3 - "$dir/low.las" "$dir/low-plain.las" "$dir/low-noise.las" "$(field noise_points "$dir/json")" <<'PY' ||
import sys
import laspy, numpy as np
ref, plain, noise = (laspy.read(p) for p in sys.argv[1:4])
c0, c1 = np.asarray(plain.classification), np.asarray(noise.classification)
h = np.asarray(noise.HeightAboveGround)
seven = c1 == 7
assert seven.sum() >= 20 and seven.sum() == int(sys.argv[4]), (seven.sum(), sys.argv[4])
assert (h[seven] < -6).all() and not ((h < -6) & ~seven & (c1 != 2)).any(), "class 7 is not the returns 6 m below"
assert not (c0 == 7).any(), "class 7 without --noise"
assert (c0[~seven] == c1[~seven]).all(), "--noise moved other classes"
assert (np.asarray(ref.classification)[seven] != 2).all(), "bare earth of the reference marked noise"
print("--noise: %d low returns of sample 41 marked class 7" % seven.sum())
PY
    fail "ground --noise: class 7 is not the low outliers"
echo "cmd_ground: ok"
