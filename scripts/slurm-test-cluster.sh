#!/usr/bin/env bash
# A private one-node Slurm cluster for tests: munged, slurmctld and slurmd of Debian's
# slurm-wlm and munge packages, every file (configuration, key, state, logs, sockets) under
# one directory, on free ports, in the foreground of processes this script records.
#
#   scripts/slurm-test-cluster.sh start DIR   start it; DIR/env.sh sets SLURM_CONF for clients
#   scripts/slurm-test-cluster.sh stop DIR    cancel its jobs, stop the daemons it started
#
# Works as root in a container without systemd (cgroups are not used: proctrack/linuxproc,
# task/none; no accounting daemon). Every wait has a deadline; a failed start prints the
# reason (and the end of the daemon's log), stops what it started and exits 1.
set -euo pipefail

START_DEADLINE_S=${SLURM_TEST_START_DEADLINE_S:-60}
STOP_DEADLINE_S=10

die() { echo "slurm-test-cluster: $*" >&2; exit 1; }

usage() { die "usage: $0 start|stop DIR"; }

[ $# -eq 2 ] || usage
action=$1
dir=$2
case "$dir" in /*) ;; *) dir="$PWD/$dir" ;; esac

pid_file() { echo "$dir/run/started-$1.pid"; }

alive() {  # alive NAME: the process this script started for NAME runs (zombies do not count)
  local f; f=$(pid_file "$1")
  [ -f "$f" ] || return 1
  local pid state; pid=$(cat "$f")
  state=$(ps -o stat= -p "$pid" 2>/dev/null || true)
  [ -n "$state" ] && [ "${state:0:1}" != Z ]
}

stop_one() {  # stop_one NAME: SIGTERM, then SIGKILL after the deadline
  local f; f=$(pid_file "$1")
  [ -f "$f" ] || return 0
  local pid; pid=$(cat "$f")
  if alive "$1"; then
    kill -TERM "$pid" 2>/dev/null || true
    local waited=0
    while alive "$1" && [ $waited -lt $((STOP_DEADLINE_S * 10)) ]; do sleep 0.1; waited=$((waited + 1)); done
    if alive "$1"; then
      echo "slurm-test-cluster: $1 (pid $pid) ignored SIGTERM; killing it" >&2
      kill -KILL "$pid" 2>/dev/null || true
    fi
  fi
  rm -f "$f"
}

stop_cluster() {
  if [ -f "$dir/etc/slurm.conf" ] && alive slurmctld; then
    SLURM_CONF="$dir/etc/slurm.conf" timeout 10 scancel --user="$(id -un)" 2>/dev/null || true
  fi
  stop_one slurmd
  stop_one slurmctld
  stop_one munged
}

port_in_use() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

free_port() {
  local p
  for _ in $(seq 1 200); do
    p=$((20000 + RANDOM % 40000))
    port_in_use "$p" || { echo "$p"; return 0; }
  done
  die "no free TCP port found"
}

fail_start() {  # fail_start REASON [LOG]: print why, stop what started, exit 1
  echo "slurm-test-cluster: cannot start the cluster: $1" >&2
  if [ -n "${2:-}" ] && [ -f "$2" ]; then
    echo "--- last lines of $2:" >&2
    tail -n 20 "$2" >&2
  fi
  stop_cluster
  exit 1
}

start_daemon() {  # start_daemon NAME LOG COMMAND...: in the background, its pid recorded
  local name=$1 log=$2; shift 2
  "$@" >>"$log" 2>&1 &
  echo $! >"$(pid_file "$name")"
}

start_cluster() {
  for tool in munged munge unmunge slurmctld slurmd sinfo sbatch squeue scancel timeout; do
    command -v "$tool" >/dev/null || [ -x "/usr/sbin/$tool" ] ||
      die "$tool not found: install slurm-wlm and munge (scripts/install-deps.sh)"
  done
  export PATH="$PATH:/usr/sbin"
  for name in munged slurmctld slurmd; do
    alive "$name" && die "$dir: a cluster runs there already ($name); stop it first"
  done
  mkdir -p "$dir"/{etc,state,spool,log,run,munge}
  chmod 755 "$dir" "$dir"/*

  # munge: a private key, socket, pid, log and seed file.
  local key="$dir/munge/munge.key" socket="$dir/munge/munge.socket"
  head -c 1024 /dev/urandom >"$key"
  chmod 600 "$key"
  start_daemon munged "$dir/log/munged.out" munged --foreground --force \
    --key-file="$key" --socket="$socket" --pid-file="$dir/run/munged.pid" \
    --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed"
  local waited=0
  until [ -S "$socket" ] && timeout 5 munge -S "$socket" -n 2>/dev/null | timeout 5 unmunge -S "$socket" >/dev/null 2>&1; do
    alive munged || fail_start "munged exited" "$dir/log/munged.log"
    [ $waited -lt $((START_DEADLINE_S * 10)) ] || fail_start "munged did not answer within ${START_DEADLINE_S} s" "$dir/log/munged.log"
    sleep 0.1; waited=$((waited + 1))
  done

  local cpus memory_mb ctld_port slurmd_port
  cpus=$(nproc)
  memory_mb=$(awk '/^MemTotal:/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
  ctld_port=$(free_port)
  slurmd_port=$(free_port)
  [ "$ctld_port" != "$slurmd_port" ] || slurmd_port=$(free_port)
  cat >"$dir/etc/slurm.conf" <<EOF
# A private one-node cluster of scripts/slurm-test-cluster.sh.
ClusterName=tissutest
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
SchedulerParameters=batch_sched_delay=0
NodeName=localhost CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/etc/slurm.conf"
  echo "export SLURM_CONF='$SLURM_CONF'" >"$dir/env.sh"

  start_daemon slurmctld "$dir/log/slurmctld.out" slurmctld -D -f "$SLURM_CONF"
  start_daemon slurmd "$dir/log/slurmd.out" slurmd -D -N localhost -f "$SLURM_CONF"
  waited=0
  until [ "$(timeout 5 sinfo -h -o %T 2>/dev/null | head -n 1)" = idle ]; do
    alive slurmctld || fail_start "slurmctld exited" "$dir/log/slurmctld.log"
    alive slurmd || fail_start "slurmd exited" "$dir/log/slurmd.log"
    [ $waited -lt $((START_DEADLINE_S * 5)) ] ||
      fail_start "the node was not idle within ${START_DEADLINE_S} s (sinfo: $(timeout 5 sinfo -h -o %T 2>&1 | head -n 1))" "$dir/log/slurmctld.log"
    sleep 0.2; waited=$((waited + 1))
  done
  echo "slurm-test-cluster: running in $dir (ports $ctld_port, $slurmd_port); source $dir/env.sh"
}

case "$action" in
  start) start_cluster ;;
  stop) stop_cluster ;;
  *) usage ;;
esac
