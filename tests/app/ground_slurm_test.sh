#!/bin/sh
# tests/app/ground_slurm_test.sh: `ladarvr ground` on a real Slurm. Starts munged, slurmctld
# and slurmd (Debian's munge and slurm-wlm) on localhost with a one-node configuration in a
# temporary folder (free ports, proctrack/linuxproc, task/none, no cgroup plugin, root as
# SlurmUser), submits scripts/slurm/ground.sbatch as a 2-task array over two ISPRS samples
# (one task per input, --only-tile), waits (bounded), and checks the outputs are the bytes
# of one `ground --out-dir` run. Every daemon it started is stopped on exit.
# Usage: ground_slurm_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR SBATCH_SCRIPT
# Exit 77 (skipped) only when the Slurm or munge programs are not installed (the cluster
# is tests/slurm_cluster.sh's).
set -eu
bin=$1
dir=$2
data=$3
sbatch_script=$4
rm -rf "$dir"
mkdir -p "$dir"
. "$(dirname "$0")/../slurm_cluster.sh"

cp "$data/samp54.laz" "$dir/a.laz"
cp "$data/samp24.laz" "$dir/b.laz"
job=$(sbatch --parsable --array=0-1 --chdir="$dir" --output="$dir/task-%a.out" \
    --export=ALL,LADARVR="$bin" "$sbatch_script" "$dir/out" "$dir/a.laz" "$dir/b.laz") ||
    fail "sbatch refused the array"
job=${job%%;*}
slurm_wait "$job" 90
"$bin" ground "$dir/a.laz" "$dir/b.laz" --out-dir "$dir/single" >"$dir/single.log" 2>&1 ||
    fail "single run: $(cat "$dir/single.log")"
for name in a.laz b.laz; do
    [ -f "$dir/out/$name" ] || fail "no $name: $(cat "$dir"/task-*.out 2>/dev/null)"
    cmp -s "$dir/out/$name" "$dir/single/$name" || fail "$name: the array task wrote other bytes than one run"
done
echo "ground slurm: a 2-task array writes the bytes of one --out-dir run"
