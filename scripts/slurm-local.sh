#!/usr/bin/env bash
# A one-node Slurm cluster on this machine (munge + slurmctld + slurmd on localhost), for `chcrt farm` and its
# tests (docs/farm.md):
#   scripts/slurm-local.sh start    install slurm-wlm and munge with apt-get when missing, write the
#                                   configuration, start the daemons and wait until the node is idle
#   scripts/slurm-local.sh stop     stop the daemons this script started
#   scripts/slurm-local.sh status   print sinfo; exit 0 when the cluster answers, 1 otherwise
# The node offers every CPU of the machine (nproc) with consumable CPUs (select/cons_tres, CR_CPU), so tasks of
# one CPU run side by side. Process tracking is proctrack/linuxproc and tasks are not confined (task/none): they
# work in containers without cgroups. The configuration goes to /etc/slurm/slurm.conf (where sbatch, squeue and
# sinfo look for it) unless a configuration not written by this script is already there; state and logs live in
# $CHCRT_SLURM_DIR (default /tmp/chcrt-slurm). Needs root (as the daemons do).
set -euo pipefail

state_dir=${CHCRT_SLURM_DIR:-/tmp/chcrt-slurm}
conf=/etc/slurm/slurm.conf
marker="# written by chcrt scripts/slurm-local.sh"

log() { echo "slurm-local: $*" >&2; }

cluster_answers() { timeout 10 sinfo -h >/dev/null 2>&1; }

install_packages() {
  local missing=()
  for p in slurm-wlm munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  if [[ $(id -u) -ne 0 ]]; then
    log "not root; run as root: apt-get install -y ${missing[*]}"
    exit 1
  fi
  log "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

write_config() {
  if [[ -f $conf ]] && ! grep -qF "$marker" "$conf"; then
    log "$conf exists and was not written by this script; using it as it is"
    return 0
  fi
  local host cpus memory_mb
  host=$(hostname -s)
  cpus=$(nproc)
  memory_mb=$(awk '/MemTotal/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)
  mkdir -p /etc/slurm "$state_dir/state" "$state_dir/spool"
  cat >"$conf" <<EOF
$marker
ClusterName=chcrt-local
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$state_dir/state
SlurmdSpoolDir=$state_dir/spool
SlurmctldPidFile=$state_dir/slurmctld.pid
SlurmdPidFile=$state_dir/slurmd.pid
SlurmctldLogFile=$state_dir/slurmctld.log
SlurmdLogFile=$state_dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
MinJobAge=300
NodeName=$host CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

start_munge() {
  if pgrep -x munged >/dev/null; then return 0; fi
  # The package's /etc/munge can be missing on a machine whose /etc was not restored with its packages; munged
  # refuses a key directory that others can write, so it is made owner-only.
  mkdir -p /etc/munge
  chmod 700 /etc/munge
  if [[ ! -s /etc/munge/munge.key ]]; then
    if command -v mungekey >/dev/null; then mungekey --create --keyfile=/etc/munge/munge.key; else
      dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
    fi
  fi
  chown munge:munge /etc/munge /etc/munge/munge.key 2>/dev/null || true
  chmod 400 /etc/munge/munge.key
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge 2>/dev/null || true
  if id munge >/dev/null 2>&1; then
    runuser -u munge -- /usr/sbin/munged
  else
    /usr/sbin/munged --force
  fi
}

start() {
  if cluster_answers && sinfo -h -o %t | grep -qE '^(idle|mix|alloc)'; then
    log "already running"
    return 0
  fi
  install_packages
  write_config
  start_munge
  pgrep -x slurmctld >/dev/null || /usr/sbin/slurmctld -c
  pgrep -x slurmd >/dev/null || /usr/sbin/slurmd -c
  for _ in $(seq 1 60); do
    if cluster_answers && sinfo -h -o %t | grep -qE '^(idle|mix|alloc)'; then
      log "node $(hostname -s) is up ($(nproc) CPUs)"
      return 0
    fi
    # A node that registered as down (an earlier unclean stop) is returned to service.
    scontrol update nodename="$(hostname -s)" state=resume >/dev/null 2>&1 || true
    sleep 1
  done
  log "the cluster did not come up; logs in $state_dir"
  tail -n 20 "$state_dir"/slurm*.log >&2 || true
  exit 1
}

stop() {
  for daemon in slurmd slurmctld; do
    local pid_file=$state_dir/$daemon.pid
    if [[ -s $pid_file ]]; then kill "$(cat "$pid_file")" 2>/dev/null || true; fi
  done
  for _ in $(seq 1 20); do
    pgrep -x slurmctld >/dev/null || pgrep -x slurmd >/dev/null || break
    sleep 0.5
  done
  log "stopped"
}

case ${1:-} in
  start) start ;;
  stop) stop ;;
  status)
    if cluster_answers; then sinfo; else
      log "no cluster answers"
      exit 1
    fi
    ;;
  *)
    echo "usage: $0 start|stop|status" >&2
    exit 2
    ;;
esac
