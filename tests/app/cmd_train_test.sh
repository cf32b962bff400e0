#!/bin/sh
# tests/app/cmd_train_test.sh: `ladarvr train` on a tiny corpus and `ladarvr detect --model`
# with its model and the shipped one, as a user runs them.
# Usage: cmd_train_test.sh LADARVR_BINARY ASSETS_DIR SCRATCH_DIR
#  - train writes a model that detect --model reads; candidates keep the file format, best
#    first, scores are probabilities;
#  - the shipped model ranks the demo's tank (centre at the world origin) first;
#  - a damaged model, a text file as model and a size class other than the model's are
#    refused in one line naming the file, exit 1, no candidates file.
set -eu
bin=$1
assets=$2
dir=$3
rm -rf "$dir"
mkdir -p "$dir"
fail() { echo "FAIL: $*" >&2; exit 1; }

cat >"$dir/spec.json" <<EOF2
{"scene": "$assets/demo/scene.json", "count": 3, "seed": 5,
 "vary": {"target_yaw_deg": {"min": 0, "max": 360}, "target_offset_m": {"min": 0, "max": 30},
          "views": 12, "resolution": 128}}
EOF2
"$bin" corpus "$dir/spec.json" --out "$dir/corpus" >/dev/null 2>&1 || fail "corpus failed"
"$bin" train "$dir/corpus" --out "$dir/m.ldm" --rounds 20 >"$dir/out" 2>"$dir/err" || fail "train: $(cat "$dir/err")"
grep -q "wrote $dir/m.ldm" "$dir/out" || fail "no summary line: $(cat "$dir/out")"
[ -s "$dir/m.ldm" ] || fail "no model file"

"$bin" generate --out "$dir/demo.pcd" --xres 128 --yres 128 --views 40 >/dev/null 2>&1 || fail "generate failed"
for model in "$dir/m.ldm" "$assets/detect/model.ldm"; do
    rm -f "$dir/c.json"
    "$bin" detect "$dir/demo.pcd" --model "$model" --out "$dir/c.json" >"$dir/out" 2>"$dir/err" ||
        fail "detect --model $model: $(cat "$dir/err")"
    python3 - "$dir/c.json" "$model" "$assets/detect/model.ldm" <<'PY' || fail "candidates of --model $model"
import json, math, sys
cands = json.load(open(sys.argv[1]))["candidates"]
assert cands, "no candidate"
assert [c["id"] for c in cands] == ["c%d" % (k + 1) for k in range(len(cands))], "ids"
assert all(a["score"] >= b["score"] for a, b in zip(cands, cands[1:])), "not best first"
assert all(0.01 <= c["score"] <= 1 for c in cands), "score outside [--min-score, 1]"
if sys.argv[2] == sys.argv[3]:
    first = cands[0]
    assert math.hypot(first["centre"][0], first["centre"][1]) < 2.5, "the shipped model's first is not the tank: %s" % cands[:3]
    assert first["score"] > 0.5, first
PY
done

one_error() {
    pattern=$1
    shift
    rm -f "$dir/bad.json"
    status=0
    "$bin" "$@" >"$dir/out" 2>"$dir/err" || status=$?
    [ "$status" -eq 1 ] || fail "ladarvr $* exited $status, expected 1: $(cat "$dir/err")"
    [ "$(wc -l <"$dir/err")" -eq 1 ] || fail "not one line: $(cat "$dir/err")"
    grep -q -e "^ladarvr: error: .*$pattern" "$dir/err" || fail "'$pattern' not in: $(cat "$dir/err")"
    [ ! -e "$dir/bad.json" ] || fail "ladarvr $* left $dir/bad.json"
}
head -c 300 "$dir/m.ldm" >"$dir/cut.ldm"
one_error "--model $dir/cut.ldm: .*cut short or damaged" detect "$dir/demo.pcd" --model "$dir/cut.ldm" --out "$dir/bad.json"
one_error "--model $dir/spec.json: not a ladarvr detector model" detect "$dir/demo.pcd" --model "$dir/spec.json" --out "$dir/bad.json"
one_error "trained for 7.0* 3.50* 2.50*; allowed that size or none" detect "$dir/demo.pcd" --model "$dir/m.ldm" --out "$dir/bad.json" --target-size-m 8 2.5 3
one_error "train: .*manifest.jsonl" train "$dir/corpus/items" --out "$dir/bad.json"

# Links planted inside a corpus are not followed: an item's cloud linked to another file,
# the items folder linked to another corpus.
cp -r "$dir/corpus" "$dir/planted"
first=$(ls "$dir/planted/items" | head -n1)
cloud=$(ls "$dir/planted/items/$first" | grep '^cloud\.' | head -n1)
rm "$dir/planted/items/$first/$cloud"
ln -s /proc/self/environ "$dir/planted/items/$first/$cloud"
one_error "train: item $first '.*': 'items/$first/$cloud' in it is a symbolic link; allowed" \
    train "$dir/planted" --out "$dir/bad.json"
rm -rf "$dir/planted/items"
ln -s "$dir/corpus/items" "$dir/planted/items"
one_error "'items' in it is a symbolic link; allowed" train "$dir/planted" --out "$dir/bad.json"

# The manifest and its listing count against --memory-mb, read or not.
mkdir -p "$dir/big"
python3 -c "
import sys
with open(sys.argv[1], 'w') as f:
    for k in range(int(sys.argv[2])):
        f.write('{\"id\": \"%08d\", \"files\": {\"cloud.pcd\": {}}}\n' % k)
" "$dir/big/manifest.jsonl" 15000
one_error "manifest.jsonl: its 15001 lines and their listing pass --memory-mb 1 MiB; raise --memory-mb" \
    train "$dir/big" --out "$dir/bad.json" --memory-mb 1
python3 -c "
import sys
with open(sys.argv[1], 'a') as f:
    f.write('x' * 1200000 + '\n')
" "$dir/big/manifest.jsonl"
one_error "manifest.jsonl: [0-9]* bytes, more than --memory-mb 1 MiB" train "$dir/big" --out "$dir/bad.json" --memory-mb 1
echo ok
