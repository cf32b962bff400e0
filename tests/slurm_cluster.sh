# tests/slurm_cluster.sh: a real one-node Slurm on localhost for the tests that run a
# Slurm array (sourced by tests/corpus/slurm_test.sh and tests/app/ground_slurm_test.sh,
# under `set -eu`). Starts munged, slurmctld and slurmd (Debian's munge and slurm-wlm) with
# a configuration in a temporary folder (free ports, proctrack/linuxproc, task/none, no
# cgroup plugin, root as SlurmUser), exports SLURM_CONF, and stops every daemon it started
# on exit. Defines fail MESSAGE (prints the daemons' log tails, exit 1) and slurm_wait JOB
# SECONDS (until the job left the queue, bounded). Exits 77 (skipped) only when the Slurm
# or munge programs are not installed.
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

ports=$(python3 -c 'import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(" ".join(str(x.getsockname()[1]) for x in s))')
ctld_port=${ports% *}
slurmd_port=${ports#* }
host=$(hostname)
cpus=$(nproc)
mkdir -p "$run/state" "$run/spool"
cat >"$run/slurm.conf" <<END
ClusterName=ladarvrtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
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

slurm_wait() {
    n=0
    while [ -n "$(squeue -h -j "$1" -o %i 2>/dev/null)" ]; do
        n=$((n + 1))
        [ "$n" -lt $(($2 * 5)) ] || fail "the array job $1 did not finish in $2 s: $(squeue -j "$1")"
        sleep 0.2
    done
}
