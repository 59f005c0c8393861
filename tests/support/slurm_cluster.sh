#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, for tests and benchmarks of `penumbra submit`:
#
#   tests/support/slurm_cluster.sh start DIR [WATCH_PID]   # prints "export SLURM_CONF=DIR/slurm.conf"
#   tests/support/slurm_cluster.sh stop DIR
#
# `start` writes a minimal slurm.conf and a fresh MUNGE key into DIR (which must be empty or
# absent), starts munged, slurmctld and slurmd (Debian 12: munge, slurm-wlm 22.05) on localhost
# ports that are free now, and waits until the node is idle. It exits 3, having stopped whatever
# it started, when the daemons cannot run here (the caller skips), and 2 when they are not
# installed. With WATCH_PID a watchdog stops the cluster when that process is gone, so that a
# test that crashes or is killed leaves no daemons behind. `stop` cancels every job, stops the
# daemons (by the pids they recorded in DIR) and removes DIR.
#
# What works in a container (and so here): proctrack/linuxproc (processes tracked by parent pid,
# no cgroup), task/none (no CPU binding), jobacct_gather/none, no accounting database; the
# daemons run as the user who starts them (root in CI), munged with --force to allow root.
set -uo pipefail

action=${1:?usage: slurm_cluster.sh start|stop DIR [WATCH_PID]}
dir=${2:?usage: slurm_cluster.sh start|stop DIR [WATCH_PID]}

stop_cluster() {
    [ -f "$dir/slurm.conf" ] || { rm -rf "$dir"; return 0; }
    export SLURM_CONF="$dir/slurm.conf"
    if [ -f "$dir/slurmctld.pid" ]; then
        scancel --me >/dev/null 2>&1 || true
        for _ in $(seq 1 20); do
            [ -z "$(squeue --me --noheader 2>/dev/null)" ] && break
            sleep 0.5
        done
    fi
    # The daemons and the watchdog (unless it is the one stopping the cluster: bash -c may exec
    # this script in its own process), by their pids.
    pids=()
    for name in slurmd slurmctld munge/munged watchdog; do
        pid=$(cat "$dir/$name.pid" 2>/dev/null)
        [ -n "$pid" ] && [ "$pid" != "$$" ] && [ "$pid" != "$PPID" ] && pids+=("$pid")
    done
    [ ${#pids[@]} -gt 0 ] && kill "${pids[@]}" 2>/dev/null
    for pid in "${pids[@]}"; do
        for _ in $(seq 1 40); do kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
        kill -KILL "$pid" 2>/dev/null || true
    done
    rm -rf "$dir"
}

if [ "$action" = stop ]; then
    stop_cluster
    exit 0
fi
[ "$action" = start ] || { echo "slurm_cluster.sh: unknown action '$action'" >&2; exit 1; }

for program in munged mungekey slurmctld slurmd sbatch squeue scancel sinfo; do
    command -v "$program" >/dev/null || PATH="$PATH:/usr/sbin:/sbin" command -v "$program" >/dev/null || {
        echo "slurm_cluster.sh: $program is not installed (scripts/install-deps.sh installs munge and slurm-wlm)" >&2
        exit 2
    }
done
export PATH="$PATH:/usr/sbin:/sbin"

fail() {
    echo "slurm_cluster.sh: $1" >&2
    for log in "$dir"/log/*.log "$dir"/munge/munged.log; do
        [ -f "$log" ] && { echo "--- $log" >&2; tail -n 15 "$log" >&2; }
    done
    stop_cluster
    exit 3
}

mkdir -p "$dir" && [ -z "$(ls -A "$dir")" ] || { echo "slurm_cluster.sh: $dir is not empty" >&2; exit 1; }
dir=$(cd "$dir" && pwd)
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
chmod 755 "$dir" "$dir/munge"
mkdir -m 700 "$dir/munge/key"
touch "$dir/plugstack.conf"

# Two ports free on localhost now (the OS picks them; a clash in the moment after is unlikely).
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')

mungekey --create --keyfile="$dir/munge/key/munge.key" || fail "mungekey could not create a key"
chmod 400 "$dir/munge/key/munge.key"
munged --force --key-file="$dir/munge/key/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" \
    || fail "munged did not start"

cpus=$(nproc)
cat > "$dir/slurm.conf" <<CONF
# A single-node cluster on localhost for penumbra's tests (tests/support/slurm_cluster.sh).
ClusterName=penumbra
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
AuthType=auth/munge
CredType=cred/munge
# cred_expire: how long a requeued job waits before it may start again (default 120 s).
AuthInfo=socket=$dir/munge/munge.socket,cred_expire=5
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
PlugStackConfig=$dir/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
KillWait=5
# A merge whose parts failed is cancelled rather than left pending for ever.
DependencyParameters=kill_invalid_depend
SlurmctldDebug=info
SlurmdDebug=info
NodeName=penumbra0 NodeAddr=127.0.0.1 NodeHostname=localhost CPUs=$cpus State=UNKNOWN
PartitionName=render Nodes=penumbra0 Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"

slurmctld -f "$SLURM_CONF" -i || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" -N penumbra0 || fail "slurmd did not start"
if [ -n "${3:-}" ]; then
    watch_pid=$3
    setsid bash -c "while kill -0 $watch_pid 2>/dev/null; do sleep 1; done; '$0' stop '$dir'" \
        </dev/null >/dev/null 2>&1 &
    echo $! > "$dir/watchdog.pid"
fi
for _ in $(seq 1 60); do
    state=$(sinfo --noheader --format=%T 2>/dev/null)
    [ "$state" = idle ] && { echo "export SLURM_CONF=$SLURM_CONF"; exit 0; }
    sleep 0.5
done
fail "the node did not become idle (state '${state:-none}')"
