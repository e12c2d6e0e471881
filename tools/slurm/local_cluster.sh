# shellcheck shell=bash
# A throwaway single-node Slurm cluster on this machine, for tests and benchmarks: munged,
# slurmctld and slurmd started from a private directory, and stopped again by pid.
#
#   source tools/slurm/local_cluster.sh
#   cluster_install                 # apt-get install slurm-wlm munge where missing (root only)
#   cluster_start "$(mktemp -d)"    # exports SLURM_CONF; returns once the node is idle
#   ...sbatch, squeue, scontrol...
#   cluster_stop                    # cancels its jobs, stops its daemons; safe to call twice
#
# Everything lives under the given directory: munge key, socket and log, slurm.conf, state,
# spool, pid files and logs. The daemons listen on free ports above 20000 chosen at start, so a
# system Slurm (port 6817/6818, /etc/slurm, /run/munge) is neither used nor disturbed, and only
# the pids this file started are ever signalled. The caller removes the directory.
#
# Sourced, not run: the caller's trap must be able to call cluster_stop. Every step checks its
# own status (`|| return 1`), because `set -e` is off inside a function called as
# `cluster_start ... || fail`.

# Pids of the daemons cluster_start started, newest last; cluster_stop stops them in reverse.
CLUSTER_PIDS=()
CLUSTER_DIR=
# The binaries a cluster needs; all come from Debian's slurm-wlm and munge packages.
CLUSTER_PROGRAMS=(munged slurmctld slurmd sbatch squeue scontrol scancel sinfo)

# Installs slurm-wlm and munge with apt-get when any program is missing. Fails, loudly, when
# something is missing and apt-get or root is not available: CI must not skip the test.
cluster_install() {
    local missing=() p
    for p in "${CLUSTER_PROGRAMS[@]}"; do
        command -v "$p" > /dev/null || missing+=("$p")
    done
    [ "${#missing[@]}" -eq 0 ] && return 0
    if [ "$(id -u)" != 0 ] || ! command -v apt-get > /dev/null; then
        echo "local_cluster: missing ${missing[*]}, and cannot install slurm-wlm munge" \
            "(needs root and apt-get)" >&2
        return 1
    fi
    echo "local_cluster: installing slurm-wlm munge (missing: ${missing[*]})" >&2
    # The packages' maintainer scripts start their system services; a policy-rc.d that denies
    # every start keeps them from doing so (this cluster runs its own daemons, and a system
    # munged or slurmctld left behind would outlive the test). Only one we created is removed.
    local policy=/usr/sbin/policy-rc.d created_policy=0 status=0 log
    log=$(mktemp)
    if [ ! -e "$policy" ]; then
        printf '#!/bin/sh\n# made by lumis tools/slurm/local_cluster.sh for apt-get\nexit 101\n' \
            > "$policy" && chmod 755 "$policy" || return 1
        created_policy=1
    fi
    {
        apt-get update -qq &&
            DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
                slurm-wlm munge
    } > "$log" 2>&1 || status=$?
    [ "$created_policy" = 0 ] || rm -f "$policy"
    if [ "$status" != 0 ]; then
        tail -n 20 "$log" >&2
        rm -f "$log"
        echo "local_cluster: apt-get install slurm-wlm munge failed" >&2
        return 1
    fi
    rm -f "$log"
    for p in "${CLUSTER_PROGRAMS[@]}"; do
        if ! command -v "$p" > /dev/null; then
            echo "local_cluster: $p still missing after installing slurm-wlm munge" >&2
            return 1
        fi
    done
}

# Prints a TCP port on 127.0.0.1 that nothing listens on, from a random start above 20000.
_cluster_free_port() {
    local port=$((20000 + RANDOM % 20000)) tries
    for ((tries = 0; tries < 100; tries++)); do
        # A connection that succeeds means a listener: try the next one.
        if ! (exec 3<> "/dev/tcp/127.0.0.1/$port") 2> /dev/null; then
            echo "$port"
            return 0
        fi
        port=$((port + 1))
    done
    echo "local_cluster: no free port found near $port" >&2
    return 1
}

# Waits up to $2 seconds for the pid file $1 and prints the pid it holds.
_cluster_wait_pid_file() {
    local file=$1 deadline=$((SECONDS + $2)) pid
    while [ "$SECONDS" -lt "$deadline" ]; do
        if [ -s "$file" ]; then
            pid=$(tr -dc '0-9' < "$file")
            if [ -n "$pid" ] && kill -0 "$pid" 2> /dev/null; then
                echo "$pid"
                return 0
            fi
        fi
        sleep 0.2
    done
    return 1
}

# Starts a daemon ($1: name for messages, $2: pid file, $3: log, rest: command) and records
# its pid; prints its log and fails if it does not come up.
_cluster_daemon() {
    local name=$1 pid_file=$2 log=$3 pid
    shift 3
    if ! "$@"; then
        echo "local_cluster: $name did not start" >&2
        [ ! -f "$log" ] || tail -n 30 "$log" >&2
        return 1
    fi
    if ! pid=$(_cluster_wait_pid_file "$pid_file" 30); then
        echo "local_cluster: $name wrote no pid file ($pid_file)" >&2
        [ ! -f "$log" ] || tail -n 30 "$log" >&2
        return 1
    fi
    CLUSTER_PIDS+=("$pid")
    echo "local_cluster: $name running, pid $pid" >&2
}

# Starts munged, slurmctld and slurmd with everything under directory $1, created 0755 if
# missing. munged insists that its socket be reachable by every user (so $1 and each directory
# above it must be searchable by all: chmod 755 a mktemp -d) and that its key be private.
# Exports SLURM_CONF, so that sbatch, squeue, ... of this shell talk to this cluster only.
# Returns once the node is idle (60 s at most).
cluster_start() {
    mkdir -p -- "$1" && chmod 755 "$1" || return 1
    CLUSTER_DIR=$(realpath -- "$1") || return 1
    local d=$CLUSTER_DIR host cpus ctld_port slurmd_port
    mkdir -p "$d/munge" "$d/munge-key" "$d/state" "$d/spool" "$d/log" "$d/run" &&
        chmod 755 "$d/munge" && chmod 700 "$d/munge-key" || return 1
    host=$(hostname -s) && cpus=$(nproc) || return 1

    # munge: a fresh key, and a socket of our own so that the system munged (if any) and its
    # key play no part. mungekey is munge >= 0.5.14; older ones had create-munge-key.
    if command -v mungekey > /dev/null; then
        mungekey --create --keyfile="$d/munge-key/munge.key" --force || return 1
    else
        dd if=/dev/urandom of="$d/munge-key/munge.key" bs=1024 count=1 status=none || return 1
    fi
    chmod 400 "$d/munge-key/munge.key" || return 1
    _cluster_daemon munged "$d/munge/munged.pid" "$d/munge/munged.log" \
        munged --socket="$d/munge/munge.socket" --key-file="$d/munge-key/munge.key" \
        --pid-file="$d/munge/munged.pid" --log-file="$d/munge/munged.log" \
        --seed-file="$d/munge-key/munged.seed" || return 1

    ctld_port=$(_cluster_free_port) && slurmd_port=$(_cluster_free_port) || return 1
    [ "$slurmd_port" != "$ctld_port" ] || slurmd_port=$((ctld_port + 1))
    # The smallest configuration that runs batch jobs as root without cgroups or accounting.
    # NodeAddr/SlurmctldHost 127.0.0.1: the host name need not resolve. CR_Core: cores are the
    # only consumable, so jobs need not state memory. config_overrides: the node's CPUs are
    # taken from this file, not from the hardware (a container's nproc may differ from what
    # slurmd detects, which would drain the node). batch_sched_delay=0: a job that becomes
    # runnable (submitted, or its dependency met) starts at the controller's next 1 s tick
    # instead of up to 3 s later, which a chain of short jobs (tiles, then a merge) feels.
    cat > "$d/slurm.conf" << CONF
ClusterName=lumis-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$d/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool/slurmd-%n
SlurmctldPidFile=$d/run/slurmctld.pid
SlurmdPidFile=$d/run/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmdParameters=config_overrides
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
MailProg=/bin/true
SchedulerParameters=batch_sched_delay=0
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    [ -s "$d/slurm.conf" ] || return 1
    export SLURM_CONF=$d/slurm.conf

    _cluster_daemon slurmctld "$d/run/slurmctld.pid" "$d/log/slurmctld.log" \
        slurmctld -f "$SLURM_CONF" || return 1
    _cluster_daemon slurmd "$d/run/slurmd.pid" "$d/log/slurmd.log" \
        slurmd -f "$SLURM_CONF" || return 1

    local deadline=$((SECONDS + 60)) state=
    while [ "$SECONDS" -lt "$deadline" ]; do
        state=$(sinfo -h -N -n "$host" -o %T 2> /dev/null || true)
        [ "$state" = idle ] && {
            echo "local_cluster: node $host idle ($cpus CPUs), SLURM_CONF=$SLURM_CONF" >&2
            return 0
        }
        sleep 0.5
    done
    echo "local_cluster: node $host not idle after 60 s (state: ${state:-none})" >&2
    sinfo -R >&2 || true
    tail -n 20 "$d/log/slurmctld.log" "$d/log/slurmd.log" >&2 || true
    return 1
}

# Waits up to $2 seconds for pid $1 to exit.
_cluster_wait_exit() {
    local pid=$1 deadline=$((SECONDS + $2))
    while kill -0 "$pid" 2> /dev/null; do
        [ "$SECONDS" -lt "$deadline" ] || return 1
        sleep 0.2
    done
}

# Cancels this cluster's jobs, then stops the daemons cluster_start started, newest first:
# SIGTERM, then SIGKILL after 10 s. Only those pids are signalled. Safe to call twice, and
# after a cluster_start that failed half-way.
cluster_stop() {
    local i pid
    if [ "${#CLUSTER_PIDS[@]}" -ge 2 ] && [ "${SLURM_CONF:-}" = "$CLUSTER_DIR/slurm.conf" ]; then
        # Jobs first, while slurmd is there to end their steps: a job left running would keep
        # lumis processes alive after the daemons are gone.
        if [ -n "$(squeue -h -o %i 2> /dev/null || true)" ]; then
            scancel --quiet "--user=$(id -un)" 2> /dev/null || true
            local deadline=$((SECONDS + 20))
            while [ -n "$(squeue -h -t R,CG -o %i 2> /dev/null || true)" ] &&
                [ "$SECONDS" -lt "$deadline" ]; do
                sleep 0.5
            done
        fi
    fi
    for ((i = ${#CLUSTER_PIDS[@]} - 1; i >= 0; i--)); do
        pid=${CLUSTER_PIDS[i]}
        kill -TERM "$pid" 2> /dev/null || continue
        if ! _cluster_wait_exit "$pid" 10; then
            kill -KILL "$pid" 2> /dev/null || true
            _cluster_wait_exit "$pid" 5 || echo "local_cluster: pid $pid did not exit" >&2
        fi
    done
    CLUSTER_PIDS=()
}

# Waits up to $2 seconds for job $1 (a job, or every task of an array) to end. Returns 0 when
# every record is COMPLETED, 1 when one ended otherwise or the time ran out; either way
# CLUSTER_JOB_STATES holds the states seen last (e.g. "COMPLETED FAILED"). Polls scontrol
# (no accounting database here for sacct); ended jobs stay visible for MinJobAge (300 s).
cluster_wait_job() {
    local id=$1 deadline=$((SECONDS + $2)) missing_since=$SECONDS
    CLUSTER_JOB_STATES=
    while [ "$SECONDS" -lt "$deadline" ]; do
        CLUSTER_JOB_STATES=$(scontrol show job -o "$id" 2> /dev/null |
            grep -o 'JobState=[A-Z_]*' | cut -d= -f2 | sort -u | tr '\n' ' ' || true)
        CLUSTER_JOB_STATES=${CLUSTER_JOB_STATES% }
        if [ -z "$CLUSTER_JOB_STATES" ]; then
            # Just submitted and not yet visible, or unknown: give it a few seconds.
            if [ $((SECONDS - missing_since)) -gt 10 ]; then
                CLUSTER_JOB_STATES=UNKNOWN
                return 1
            fi
        else
            missing_since=$SECONDS
            case " $CLUSTER_JOB_STATES " in
                *" PENDING "* | *" CONFIGURING "* | *" RUNNING "* | *" COMPLETING "* | \
                    *" REQUEUED "* | *" REQUEUE_FED "* | *" REQUEUE_HOLD "* | *" RESIZING "* | \
                    *" SUSPENDED "* | *" SIGNALING "* | *" STAGE_OUT "* | *" STOPPED "*) ;;
                " COMPLETED ") return 0 ;;
                *) return 1 ;;
            esac
        fi
        sleep 0.25
    done
    CLUSTER_JOB_STATES="$CLUSTER_JOB_STATES (timed out after $2 s)"
    return 1
}
