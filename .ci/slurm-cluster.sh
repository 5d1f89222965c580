#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for the tests of stoss's Slurm executor:
# installs Debian's slurm-wlm daemons and munge if missing, writes a slurm.conf (this host,
# its CPUs, accounting off, state and spool folders under one directory) and starts munged,
# slurmctld and slurmd without systemd. Needs root.
#
# Usage (sourced):  . .ci/slurm-cluster.sh; slurm_cluster_start DIR; ...; slurm_cluster_stop
# `slurm_cluster_start` exports SLURM_CONF, so sbatch/squeue/scancel of the caller use the
# cluster; it waits (bounded) until the node is idle and fails with a message otherwise.

slurm_cluster_dir=""

slurm_cluster_log() {
    printf 'slurm-cluster: %s\n' "$*" >&2
}

slurm_cluster_install() {
    local missing=()
    command -v slurmctld >/dev/null 2>&1 || missing+=(slurmctld)
    command -v slurmd >/dev/null 2>&1 || missing+=(slurmd)
    command -v sbatch >/dev/null 2>&1 || missing+=(slurm-client)
    command -v munged >/dev/null 2>&1 || missing+=(munge)
    if [[ ${#missing[@]} -gt 0 ]]; then
        slurm_cluster_log "installing ${missing[*]}"
        DEBIAN_FRONTEND=noninteractive apt-get update -qq
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" \
            >/dev/null
    fi
}

# slurm_cluster_start DIR: bring the cluster up with its files under DIR.
slurm_cluster_start() {
    slurm_cluster_dir="$1"
    if [[ "$(id -u)" -ne 0 ]]; then
        slurm_cluster_log "needs root (slurmd runs jobs as their users)"
        return 1
    fi
    slurm_cluster_install
    mkdir -p "$slurm_cluster_dir"/{state,spool,log,munge}
    # munged runs as the munge user: it must reach its folder.
    chmod 755 "$slurm_cluster_dir" "$(dirname "$slurm_cluster_dir")"
    local node cpus memory
    node="$(hostname -s)"
    cpus="$(nproc)"
    memory="$(slurmd -C 2>/dev/null | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')"
    memory="${memory:-1000}"

    # munge: a key of its own, a socket and pid under the cluster folder.
    local key="$slurm_cluster_dir/munge/munge.key"
    dd if=/dev/urandom of="$key" bs=1 count=1024 status=none
    chown -R munge:munge "$slurm_cluster_dir/munge"
    chmod 700 "$slurm_cluster_dir/munge"
    chmod 400 "$key"
    local socket="$slurm_cluster_dir/munge/munge.socket"
    mkdir -p /run/munge && chown munge:munge /run/munge
    su -s /bin/sh munge -c "munged --force --key-file=$key --socket=$socket \
        --pid-file=$slurm_cluster_dir/munge/munged.pid --log-file=$slurm_cluster_dir/munge/munged.log" \
        || { slurm_cluster_log "munged did not start"; return 1; }

    export SLURM_CONF="$slurm_cluster_dir/slurm.conf"
    cat >"$SLURM_CONF" <<EOF
ClusterName=stoss-ci
SlurmctldHost=$node
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=1
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
MinJobAge=600
KillWait=2
InactiveLimit=0
StateSaveLocation=$slurm_cluster_dir/state
SlurmdSpoolDir=$slurm_cluster_dir/spool
SlurmctldPidFile=$slurm_cluster_dir/slurmctld.pid
SlurmdPidFile=$slurm_cluster_dir/slurmd.pid
SlurmctldLogFile=$slurm_cluster_dir/log/slurmctld.log
SlurmdLogFile=$slurm_cluster_dir/log/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
NodeName=$node CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=ci Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    slurmctld -c -f "$SLURM_CONF" || { slurm_cluster_log "slurmctld did not start"; return 1; }
    slurmd -f "$SLURM_CONF" || { slurm_cluster_log "slurmd did not start"; return 1; }
    local waited=0
    until sinfo -h -o '%t' 2>/dev/null | grep -qx 'idle'; do
        if [[ $waited -ge 60 ]]; then
            slurm_cluster_log "the node is not idle after 60 s; sinfo says:"
            sinfo >&2 || true
            tail -n 20 "$slurm_cluster_dir/log/slurmctld.log" "$slurm_cluster_dir/log/slurmd.log" >&2 || true
            return 1
        fi
        sleep 1
        waited=$((waited + 1))
    done
    slurm_cluster_log "up: node $node, $cpus CPUs, partition ci ($SLURM_CONF)"
}

# slurm_cluster_stop: cancel every job, stop the daemons (bounded), keep the logs.
slurm_cluster_stop() {
    [[ -n "$slurm_cluster_dir" ]] || return 0
    scancel --full --quiet --partition=ci 2>/dev/null || true
    local pidfile pid
    for pidfile in "$slurm_cluster_dir/slurmd.pid" "$slurm_cluster_dir/slurmctld.pid" \
        "$slurm_cluster_dir/munge/munged.pid"; do
        [[ -f "$pidfile" ]] || continue
        pid="$(cat "$pidfile")"
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 1 20); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.25
        done
        kill -9 "$pid" 2>/dev/null || true
    done
    slurm_cluster_dir=""
}
