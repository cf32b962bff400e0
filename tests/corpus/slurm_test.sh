#!/bin/sh
# tests/corpus/slurm_test.sh: the corpus on a real Slurm. Starts munged, slurmctld and
# slurmd (Debian's munge and slurm-wlm) on localhost with a one-node configuration in a
# temporary folder (free ports, proctrack/linuxproc, task/none, no cgroup plugin, root as
# SlurmUser), submits scripts/slurm/corpus.sbatch as a 4-task array over a small SPEC,
# waits (bounded), merges, and checks the merged manifest has the ids and cloud SHA-256s
# of a single-process run. Every daemon it started is stopped on exit.
# Usage: slurm_test.sh LADARVR_BINARY SCRATCH_DIR SCENE SBATCH_SCRIPT
# Exit 77 (skipped) only when the Slurm or munge programs are not installed (the cluster
# is tests/slurm_cluster.sh's).
set -eu
bin=$1
dir=$2
scene=$3
sbatch_script=$4
rm -rf "$dir"
mkdir -p "$dir"
. "$(dirname "$0")/../slurm_cluster.sh"

cat >"$dir/spec.json" <<END
{
  "scene": "$scene",
  "count": 10,
  "seed": 5,
  "vary": {
    "target_yaw_deg": {"min": 0, "max": 360},
    "target_offset_m": {"min": 0, "max": 15},
    "altitude_m": {"min": 200, "max": 400},
    "resolution": [8, 12],
    "views": 3,
    "centre_offset_m": {"min": 0, "max": 10}
  }
}
END
job=$(sbatch --parsable --array=0-3 --chdir="$dir" --output="$dir/task-%a.out" \
    --export=ALL,LADARVR="$bin" "$sbatch_script" "$dir/spec.json" "$dir/out") || fail "sbatch refused the array"
job=${job%%;*}
slurm_wait "$job" 90
for i in 0 1 2 3; do
    [ -f "$dir/out/manifest.$i.jsonl" ] || fail "task $i wrote no manifest.$i.jsonl: $(cat "$dir/task-$i.out" 2>/dev/null)"
    grep -q "built" "$dir/task-$i.out" || fail "task $i: $(cat "$dir/task-$i.out")"
done
"$bin" corpus --merge "$dir/out" 2>"$dir/merge.log" || fail "merge: $(cat "$dir/merge.log")"
"$bin" corpus "$dir/spec.json" --out "$dir/single" 2>"$dir/single.log" || fail "single run: $(cat "$dir/single.log")"
python3 - "$dir" <<'PY' || fail "the array's manifest differs from the single run's"
import json, sys
d = sys.argv[1]
def clouds(path):
    return [(r["id"], r["files"]["cloud.pcd"]["sha256"]) for r in map(json.loads, open(path))]
merged, single = clouds(d + "/out/manifest.jsonl"), clouds(d + "/single/manifest.jsonl")
assert [i for i, _ in merged] == ["%04d" % k for k in range(10)], merged
assert merged == single, (merged, single)
for i in range(4):
    rows = [json.loads(l) for l in open("%s/out/manifest.%d.jsonl" % (d, i))]
    assert sorted(r["index"] for r in rows) == list(range(i, 10, 4)), (i, rows)
PY
echo "slurm: a 4-task array over 10 items matches the single-process run"
