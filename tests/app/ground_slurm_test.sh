#!/bin/sh
# tests/app/ground_slurm_test.sh: `ladarvr ground` on a real Slurm. Starts munged, slurmctld
# and slurmd (Debian's munge and slurm-wlm) on localhost with a one-node configuration in a
# temporary folder (free ports, proctrack/linuxproc, task/none, no cgroup plugin, root as
# SlurmUser), submits scripts/slurm/ground.sbatch as a 2-task array over two ISPRS samples
# (one task per input, --only-tile), waits (bounded), and checks the outputs are the bytes
# of one `ground --out-dir` run. Every daemon it started is stopped on exit.
# Usage: ground_slurm_test.sh LADARVR_BINARY SCRATCH_DIR DATA_DIR SBATCH_SCRIPT
# Exit 77 (skipped) only when the Slurm or munge programs are not installed.
set -eu
bin=$1
dir=$2
data=$3
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

cp "$data/samp54.laz" "$dir/a.laz"
cp "$data/samp24.laz" "$dir/b.laz"
job=$(sbatch --parsable --array=0-1 --chdir="$dir" --output="$dir/task-%a.out" \
    --export=ALL,LADARVR="$bin" "$sbatch_script" "$dir/out" "$dir/a.laz" "$dir/b.laz") ||
    fail "sbatch refused the array"
job=${job%%;*}
n=0
while [ -n "$(squeue -h -j "$job" -o %i 2>/dev/null)" ]; do
    n=$((n + 1))
    [ "$n" -lt 450 ] || fail "the array job $job did not finish in 90 s: $(squeue -j "$job")"
    sleep 0.2
done
"$bin" ground "$dir/a.laz" "$dir/b.laz" --out-dir "$dir/single" >"$dir/single.log" 2>&1 ||
    fail "single run: $(cat "$dir/single.log")"
for name in a.laz b.laz; do
    [ -f "$dir/out/$name" ] || fail "no $name: $(cat "$dir"/task-*.out 2>/dev/null)"
    cmp -s "$dir/out/$name" "$dir/single/$name" || fail "$name: the array task wrote other bytes than one run"
done
echo "ground slurm: a 2-task array writes the bytes of one --out-dir run"
