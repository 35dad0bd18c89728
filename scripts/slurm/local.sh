#!/usr/bin/env bash
# A one-node Slurm on this Debian 12 machine, without systemd, for the tests and CI
# `local.sh start|stop|status`.
#
# start: installs slurmctld slurmd slurm-client munge when missing (apt-get, as root),
# makes a munge key when there is none, writes /etc/slurm/slurm.conf (only when there
# is none or it is one this script wrote) with the node as `slurmd -C` reports it
# (proctrack/linuxproc, task/none, select/cons_tres with cores and memory), starts
# munged, slurmctld and slurmd with pid files in $UAVIP_SLURM_DIR (default
# /tmp/uavip-slurm) and waits until the node is idle.
# stop: stops only the daemons whose pid files are there (what start started).
# status: those daemons and `sinfo`.
set -euo pipefail
STATE=${UAVIP_SLURM_DIR:-/tmp/uavip-slurm}
CONF=/etc/slurm/slurm.conf
MARK="# written by uavip scripts/slurm/local.sh"
say() { echo "slurm-local: $*"; }

alive() { [[ -f $1 ]] && kill -0 "$(cat "$1")" 2>/dev/null; }

install_packages() {
  local missing=()
  for p in slurmctld slurmd slurm-client munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    say "installing ${missing[*]}"
    apt-get update -qq >/dev/null
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
  fi
}

write_conf() {
  if [[ -f $CONF ]] && ! grep -q "^$MARK" "$CONF"; then
    say "$CONF exists and is not ours; using it as it is"
    return
  fi
  local node host
  host=$(hostname -s)
  # "NodeName=vm CPUs=2 Boards=1 ... RealMemory=24105" without the UpTime line.
  node=$(slurmd -C | head -n 1)
  mkdir -p /etc/slurm
  cat >"$CONF" <<CONF
$MARK
ClusterName=uavip
SlurmctldHost=$host
AuthType=auth/munge
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
ReturnToService=2
StateSaveLocation=$STATE/state
SlurmdSpoolDir=$STATE/spool
SlurmctldPidFile=$STATE/slurmctld.pid
SlurmdPidFile=$STATE/slurmd.pid
SlurmctldLogFile=$STATE/slurmctld.log
SlurmdLogFile=$STATE/slurmd.log
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
MinJobAge=3600
SchedulerType=sched/backfill
$node
PartitionName=uavip Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
}

start() {
  [[ $(id -u) == 0 ]] || { say "start needs root (apt-get, daemons)"; exit 2; }
  install_packages
  mkdir -p "$STATE/state" "$STATE/spool" /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge
  if [[ ! -s /etc/munge/munge.key ]]; then
    say "making a munge key"
    mungekey --create --keyfile=/etc/munge/munge.key
    chown munge:munge /etc/munge/munge.key
    chmod 600 /etc/munge/munge.key
  fi
  if [[ -S /run/munge/munge.socket.2 ]] && munge -n >/dev/null 2>&1; then
    say "munged already running (not ours)"
  elif ! alive "$STATE/munged.pid"; then
    rm -f /run/munge/munged.pid
    runuser -u munge -- munged --force
    # munged (user munge) writes its pid file in /run/munge; ours is a root-owned copy.
    for _ in $(seq 50); do [[ -s /run/munge/munged.pid ]] && break; sleep 0.1; done
    cp /run/munge/munged.pid "$STATE/munged.pid"
  fi
  write_conf
  alive "$STATE/slurmctld.pid" || slurmctld
  alive "$STATE/slurmd.pid" || slurmd
  local state=""
  for _ in $(seq 60); do
    state=$(sinfo -h -o %T 2>/dev/null | head -n 1 || true)
    [[ $state == idle* || $state == mixed* || $state == allocated* ]] && break
    sleep 0.5
  done
  if [[ $state != idle* && $state != mixed* && $state != allocated* ]]; then
    say "the node did not come up (state '${state}'); logs: $STATE/slurmctld.log, $STATE/slurmd.log"
    exit 1
  fi
  say "up: $(sinfo -h -o '%P %D node(s) %c CPUs %m MB %T')"
}

stop() {
  local name pid
  for name in slurmd slurmctld munged; do
    if alive "$STATE/$name.pid"; then
      pid=$(cat "$STATE/$name.pid")
      kill "$pid"
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      say "stopped $name ($pid)"
    fi
    rm -f "$STATE/$name.pid"
  done
}

status() {
  local name
  for name in munged slurmctld slurmd; do
    if alive "$STATE/$name.pid"; then echo "$name: running ($(cat "$STATE/$name.pid"))"; else echo "$name: not started here"; fi
  done
  sinfo 2>/dev/null || echo "sinfo: no controller answers"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
