#!/bin/sh
# tests/corpus/slurm_test.sh: the corpus on a real Slurm. Starts munged, slurmctld and
# slurmd (Debian's munge and slurm-wlm) on localhost with a one-node configuration in a
# temporary folder (free ports, proctrack/linuxproc, task/none, no cgroup plugin, root as
# SlurmUser), submits scripts/slurm/corpus.sbatch as a 4-task array over a small SPEC,
# waits (bounded), merges, and checks the merged manifest has the ids and cloud SHA-256s
# of a single-process run. Every daemon it started is stopped on exit.
# Usage: slurm_test.sh LADARVR_BINARY SCRATCH_DIR SCENE SBATCH_SCRIPT
# Exit 77 (skipped) only when the Slurm or munge programs are not installed.
set -eu
bin=$1
dir=$2
scene=$3
sbatch_script=$4
fail() {
    echo "FAIL: $*" >&2
    for f in "$run"/slurmctld.log "$run"/slurmd.log "$run"/munged.log; do
        [ -f "$f" ] && { echo "--- $f" >&2; tail -n 15 "$f" >&2; }
    done
    exit 1
}
for program in munged mungekey slurmctld slurmd sbatch squeue scontrol; do
    command -v "$program" >/dev/null 2>&1 || { echo "SKIP: $program is not installed"; exit 77; }
done
rm -rf "$dir"
mkdir -p "$dir"
# munged wants every folder above its socket searchable by all; a short /tmp path also
# keeps the socket's name under the 108 bytes of sun_path.
run=$(mktemp -d /tmp/ladarvr-slurm.XXXXXX)
chmod 755 "$run"
pids=""
stop() {
    [ -n "${SLURM_CONF:-}" ] && scancel --quiet --user="$(id -un)" 2>/dev/null || true
    for pid in $pids; do kill "$pid" 2>/dev/null || true; done
    for pid in $pids; do
        n=0
        while kill -0 "$pid" 2>/dev/null && [ "$n" -lt 50 ]; do sleep 0.1; n=$((n + 1)); done
        kill -9 "$pid" 2>/dev/null || true
    done
    rm -rf "$run"
}
trap stop EXIT
trap 'exit 1' INT TERM

mungekey --create --keyfile="$run/munge.key" >/dev/null 2>&1 || fail "mungekey could not make a key"
chmod 600 "$run/munge.key"
munged --foreground --key-file="$run/munge.key" --socket="$run/munge.sock" --pid-file="$run/munged.pid" \
    --log-file="$run/munged.log" --seed-file="$run/munged.seed" 2>"$run/munged.log" &
pids="$pids $!"
n=0
while [ ! -S "$run/munge.sock" ]; do
    n=$((n + 1))
    [ "$n" -lt 100 ] || fail "munged did not create its socket in 10 s"
    sleep 0.1
done

set -- $(python3 -c 'import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(" ".join(str(x.getsockname()[1]) for x in s))')
host=$(hostname)
cpus=$(nproc)
mkdir -p "$run/state" "$run/spool"
cat >"$run/slurm.conf" <<END
ClusterName=ladarvrtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$1
SlurmdPort=$2
SlurmUser=$(id -un)
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$run/munge.sock
StateSaveLocation=$run/state
SlurmdSpoolDir=$run/spool
SlurmctldPidFile=$run/slurmctld.pid
SlurmdPidFile=$run/slurmd.pid
SlurmctldLogFile=$run/slurmctld.log
SlurmdLogFile=$run/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
ReturnToService=2
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
END
echo "CgroupPlugin=disabled" >"$run/cgroup.conf"
export SLURM_CONF="$run/slurm.conf"
slurmctld -D -i >"$run/slurmctld.out" 2>&1 &
pids="$pids $!"
slurmd -D -N "$host" >"$run/slurmd.out" 2>&1 &
pids="$pids $!"
n=0
until sinfo -h -o %t 2>/dev/null | grep -q -e idle -e mix; do
    n=$((n + 1))
    [ "$n" -lt 150 ] || fail "the node did not come up in 30 s"
    sleep 0.2
done

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
n=0
while [ -n "$(squeue -h -j "$job" -o %i 2>/dev/null)" ]; do
    n=$((n + 1))
    [ "$n" -lt 450 ] || fail "the array job $job did not finish in 90 s: $(squeue -j "$job")"
    sleep 0.2
done
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
