# A one-node Slurm cluster on this machine, for tools/farm/test_cluster.sh.
# Source it, then:
#
#   cluster_start DIR   writes DIR/slurm.conf, starts munged, slurmctld and
#                       slurmd with all their state in DIR, exports SLURM_CONF
#                       so that sbatch, squeue, ... talk to this cluster, and
#                       waits until sinfo shows the node idle
#   node_kill           kills slurmd and every process of the jobs on the node
#                       at once (SIGKILL), as a node that dies would lose them
#   node_start          starts slurmd again
#   cluster_stop        cancels the jobs, stops the three daemons; safe to call
#                       twice and after a failed start (call it from a trap)
#
# Debian's slurm-wlm and munge run as root here, as this cluster's own
# processes: no systemd, no /etc/slurm, no /etc/munge/munge.key. Nothing
# outside DIR is written. The functions return non-zero on failure and do
# not exit: under `set -e`, cluster_stop still stops what it can.

# Ports of our own: a Slurm already on this machine uses 6817 and 6818.
CLUSTER_CTLD_PORT=${CLUSTER_CTLD_PORT:-16817}
CLUSTER_SLURMD_PORT=${CLUSTER_SLURMD_PORT:-16818}
# A node silent this long is down and its jobs are requeued (Slurm's default
# is 300 s); a requeued job may start again after cred_expire (default 120 s).
CLUSTER_SLURMD_TIMEOUT=5
CLUSTER_CRED_EXPIRE=10

cluster_dir=""

cluster_log() { echo "cluster: $*" >&2; }

# Waits up to $1 seconds for the command after it to succeed.
cluster_wait() {
    local seconds=$1
    shift
    local deadline=$((SECONDS + seconds))
    until "$@"; do
        ((SECONDS < deadline)) || return 1
        sleep 0.5
    done
}

cluster_write_conf() {
    local d=$cluster_dir
    cat >"$d/slurm.conf" <<EOF
ClusterName=sturmray-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$CLUSTER_CTLD_PORT
SlurmdPort=$CLUSTER_SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$d/munge/munge.socket,cred_expire=$CLUSTER_CRED_EXPIRE
StateSaveLocation=$d/slurmctld
SlurmdSpoolDir=$d/slurmd
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/slurmctld.log
SlurmdLogFile=$d/slurmd.log
MailProg=/bin/true
# No cgroups in a container: track processes by their parents, bind nothing.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
# Start queued jobs within a second of a free CPU (the default waits up to a minute).
SchedulerParameters=sched_interval=1,bf_interval=1
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdTimeout=$CLUSTER_SLURMD_TIMEOUT
MessageTimeout=3
# A node that comes back after it was down takes jobs again.
ReturnToService=2
# The node as configured, whatever the machine has (CI machines differ).
SlurmdParameters=config_overrides
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 RealMemory=1000 State=UNKNOWN
PartitionName=farm Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
}

cluster_node_idle() {
    [[ $(sinfo --noheader --nodes=localhost --format=%T 2>/dev/null) == idle ]]
}

cluster_no_jobs() {
    [[ -z $(squeue --noheader 2>/dev/null) ]]
}

cluster_start() {
    cluster_dir=$1
    mkdir -p "$cluster_dir"/{munge,slurmctld,slurmd}
    # munged wants a socket every user can reach: no 0700 folder on its path.
    chmod 755 "$cluster_dir" "$cluster_dir/munge"
    cluster_write_conf
    export SLURM_CONF=$cluster_dir/slurm.conf

    local m=$cluster_dir/munge
    (umask 077 && head -c 1024 /dev/urandom >"$m/munge.key")
    munged --foreground --key-file="$m/munge.key" --socket="$m/munge.socket" \
        --pid-file="$m/munged.pid" --log-file="$m/munged.log" --seed-file="$m/munged.seed" \
        >"$m/munged.out" 2>&1 &
    cluster_munged=$!
    cluster_wait 10 test -S "$m/munge.socket" ||
        { cluster_log "munged did not start: $(cat "$m/munged.out")"; return 1; }

    slurmctld -D -f "$SLURM_CONF" >"$cluster_dir/slurmctld.out" 2>&1 &
    cluster_slurmctld=$!
    node_start || return 1
}

node_start() {
    slurmd -D -N localhost -f "$SLURM_CONF" >>"$cluster_dir/slurmd.out" 2>&1 &
    cluster_slurmd=$!
    cluster_wait 60 cluster_node_idle || {
        cluster_log "the node is not idle after 60 s: $(sinfo --noheader --Node --long 2>&1)"
        cluster_log "slurmctld.log: $(tail -n 5 "$cluster_dir/slurmctld.log" 2>&1)"
        cluster_log "slurmd.log: $(tail -n 5 "$cluster_dir/slurmd.log" 2>&1)"
        return 1
    }
}

# The jobs' processes (scontrol listpids, while slurmd answers) and the
# slurmstepd that runs each (its parent, when that is one), then slurmd: all
# at once.
node_kill() {
    local pids=() pid parent
    for pid in $(scontrol listpids 2>/dev/null | awk 'NR > 1 && $1 ~ /^[0-9]+$/ {print $1}'); do
        pids+=("$pid")
        parent=$(awk '{print $4}' "/proc/$pid/stat" 2>/dev/null) || continue
        [[ $(cat "/proc/$parent/comm" 2>/dev/null) != slurmstepd ]] || pids+=("$parent")
    done
    kill -KILL "$cluster_slurmd" "${pids[@]}" 2>/dev/null || true
    wait "$cluster_slurmd" 2>/dev/null || true
    cluster_slurmd=""
}

cluster_stop() {
    [[ -n $cluster_dir ]] || return 0
    if [[ -n ${cluster_slurmctld:-} ]]; then
        scancel --full --quiet --user="$(id -un)" 2>/dev/null || true
        # Give the jobs' processes their SIGTERM and the time to exit.
        cluster_wait 20 cluster_no_jobs ||
            cluster_log "jobs still listed at stop: $(squeue --noheader 2>&1)"
    fi
    local pid
    for pid in ${cluster_slurmd:-} ${cluster_slurmctld:-} ${cluster_munged:-}; do
        kill -TERM "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true
    done
    cluster_slurmd="" cluster_slurmctld="" cluster_munged="" cluster_dir=""
}
