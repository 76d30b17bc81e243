#!/usr/bin/env bash
# A single-node Slurm cluster on loopback for the tests, without systemd: munged, slurmctld and
# slurmd run as this user from a generated slurm.conf in DIR, on free ports, and stop again.
#   cluster.sh start DIR   starts the daemons, waits until the node takes jobs, prints
#                          `export SLURM_CONF=DIR/slurm.conf` for the caller to eval
#   cluster.sh stop DIR    stops every daemon started from DIR (nothing is left running)
# Debian's slurm-wlm 22.05 and munge must be installed (scripts/install-deps.sh --with-slurm).
set -euo pipefail

usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[[ $# -eq 2 ]] || usage
cmd=$1
dir=$(realpath -m "$2")

stop() {
  for name in slurmd slurmctld munged; do
    local pidfile=$dir/$name.pid
    [[ -f $pidfile ]] || continue
    local pid
    pid=$(cat "$pidfile")
    if kill -0 "$pid" 2>/dev/null; then
      kill -TERM "$pid" 2>/dev/null || true
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -KILL "$pid" 2>/dev/null || true
    fi
    rm -f "$pidfile"
  done
  # slurmstepd processes of jobs that were still running when slurmd went.
  pkill -KILL -f "slurmstepd.*$dir" 2>/dev/null || true
}

free_port() {
  python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'
}

wait_for() {  # wait_for SECONDS WHAT COMMAND...
  local seconds=$1 what=$2
  shift 2
  for _ in $(seq $((seconds * 10))); do
    if "$@" >/dev/null 2>&1; then return 0; fi
    sleep 0.1
  done
  echo "cluster.sh: $what did not come up in ${seconds} s; its log:" >&2
  tail -n 20 "$dir"/*.log >&2 || true
  stop
  exit 1
}

start() {
  for exe in munged mungekey slurmctld slurmd sinfo; do
    command -v "$exe" >/dev/null || { echo "cluster.sh: $exe not found (install slurm-wlm and munge)" >&2; exit 3; }
  done
  mkdir -p "$dir"/{state,spool,munge}
  chmod 700 "$dir"/munge
  local user host cpus memory
  user=$(id -un)
  host=$(hostname -s)
  cpus=$(nproc)
  memory=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512 ))

  mungekey --create --keyfile="$dir/munge/munge.key" --force
  chmod 600 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/socket" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munge/seed"
  wait_for 10 munged test -S "$dir/munge/socket"

  cat > "$dir/slurm.conf" <<EOF
ClusterName=deformflow-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/%n
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/pgid
TaskPlugin=task/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobRequeue=1
ReturnToService=2
KillWait=10
MinJobAge=300
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -i -f "$SLURM_CONF"
  wait_for 20 slurmctld scontrol ping
  slurmd -f "$SLURM_CONF" -N "$host"
  wait_for 30 "slurmd (node $host idle)" bash -c "sinfo -h -n $host -o %t | grep -qx idle"
  echo "export SLURM_CONF=$SLURM_CONF"
}

case $cmd in
  start) start ;;
  stop) stop ;;
  *) usage ;;
esac
