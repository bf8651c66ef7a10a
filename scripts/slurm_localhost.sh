#!/usr/bin/env bash
# A single-node SLURM cluster on this machine, to run the workflow through the SLURM executor
# (workflow/profiles/slurm) without a real cluster; tests/test_slurm.py uses it.
#
#   bash scripts/slurm_localhost.sh start
#   bash scripts/slurm_localhost.sh stop
#   bash scripts/slurm_localhost.sh status
#
# Needs root (the daemons run as root, munged as the munge user) and the Debian packages
# slurm-wlm and munge, installed here with apt-get when missing. Everything but the configuration
# lives in one state directory (PYFRUSTRATE_SLURM_DIR, default /var/tmp/pyfrustrate-slurm): spool
# and state directories, pid files, logs, the job-completion log. The configuration is
# /etc/slurm/slurm.conf, the place every SLURM client reads by default: a SLURM_CONF elsewhere
# would not reach the job steps, because the SLURM executor clears SLURM_* variables before its
# nested srun. A slurm.conf this script did not write is never overwritten; `stop` removes ours.
# Both commands are idempotent: `start` on a running cluster checks it and returns, `stop` on a
# stopped one does nothing.
set -euo pipefail
STATE="${PYFRUSTRATE_SLURM_DIR:-/var/tmp/pyfrustrate-slurm}"
CONF=/etc/slurm/slurm.conf
MARK="# Written by scripts/slurm_localhost.sh"
CTLD_PORT="${PYFRUSTRATE_SLURMCTLD_PORT:-6817}"
SLURMD_PORT="${PYFRUSTRATE_SLURMD_PORT:-6818}"
DEBIAN_PACKAGES=(slurm-wlm munge)

say() { echo "[slurm-localhost] $*"; }
die() { echo "[slurm-localhost] error: $*" >&2; exit 1; }

alive() {  # alive PIDFILE: the process the pid file names is running
  [ -s "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null
}

install_packages() {
  local missing=() pkg
  for pkg in "${DEBIAN_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  ((${#missing[@]})) || return 0
  command -v apt-get >/dev/null || die "missing Debian packages ${missing[*]} and no apt-get to install them"
  say "installing Debian packages: ${missing[*]}"
  apt-get update -qq
  # --no-install-recommends: the daemons and clients only (9 packages), not the MySQL-backed
  # accounting daemon and the rest that slurm-wlm recommends.
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

munge_works() { munge -n 2>/dev/null | unmunge >/dev/null 2>&1; }

start_munge() {
  if munge_works; then
    return 0  # a munged already answers (ours from an earlier start, or the system's): share it
  fi
  if [ ! -s /etc/munge/munge.key ]; then
    say "creating the munge key /etc/munge/munge.key"
    mungekey --create --keyfile=/etc/munge/munge.key
  fi
  chown munge:munge /etc/munge/munge.key
  chmod 0400 /etc/munge/munge.key
  install -d -o munge -g munge -m 0755 /run/munge
  install -d -o munge -g munge -m 0700 /var/lib/munge /var/log/munge
  runuser -u munge -- /usr/sbin/munged
  # Only a munged this script started is stopped by `stop`.
  cp /run/munge/munged.pid "$STATE/munged.pid"
  for _ in $(seq 50); do munge_works && return 0; sleep 0.1; done
  die "munged started but does not answer (log: /var/log/munge/munged.log)"
}

# The state directory named by our slurm.conf, if this script wrote it.
conf_state() { [ -f "$CONF" ] && head -n1 "$CONF" | grep -q "^$MARK" && sed -n 's/^StateSaveLocation=\(.*\)\/ctld$/\1/p' "$CONF"; }

write_conf() {
  local host node other
  if [ -f "$CONF" ]; then
    head -n1 "$CONF" | grep -q "^$MARK" || die "$CONF exists and was not written by this script: not overwriting it"
    other="$(conf_state || true)"
    if [ -n "$other" ] && [ "$other" != "$STATE" ] && alive "$other/slurmctld.pid"; then
      die "another cluster of this script runs (state directory $other): stop it first (PYFRUSTRATE_SLURM_DIR=$other $0 stop)"
    fi
  fi
  host="$(hostname -s)"
  # The node's real CPUs, sockets, cores and memory, as slurmd detects them (e.g.
  # "NodeName=vm CPUs=2 Boards=1 SocketsPerBoard=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=24105").
  node="$(slurmd -C | head -n1)"
  [[ "$node" == NodeName=* ]] || die "slurmd -C did not describe this node: $node"
  mkdir -p "$STATE/ctld" "$STATE/spool" "$STATE/log"
  mkdir -p "$(dirname "$CONF")"
  cat > "$CONF.new" <<EOF
$MARK: a single-node cluster on $host (state in $STATE).
ClusterName=localhost
SlurmctldHost=$host
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
AuthType=auth/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$STATE/ctld
SlurmdSpoolDir=$STATE/spool
SlurmctldPidFile=$STATE/slurmctld.pid
SlurmdPidFile=$STATE/slurmd.pid
SlurmctldLogFile=$STATE/log/slurmctld.log
SlurmdLogFile=$STATE/log/slurmd.log
# Processes tracked by parent pid, no cgroups: works in containers without a delegated cgroup tree.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
# Cores and memory are consumable: jobs share the node up to its CPUs and RealMemory, and a job's
# --mem is what the scheduler reserves for it.
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
# No accounting database (slurmdbd): sacct then asks slurmctld, which keeps finished jobs for
# MinJobAge seconds; the job-completion log keeps a line per finished job for good.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/linux
JobCompType=jobcomp/filetxt
JobCompLoc=$STATE/log/jobcomp.log
MinJobAge=600
ReturnToService=2
SlurmdTimeout=60
$node State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$CONF.new" "$CONF"
}

wait_idle() {
  local state=""
  for _ in $(seq 100); do
    state="$(sinfo -h -N -o %t 2>/dev/null | head -n1 || true)"
    case "$state" in idle|mix|alloc) return 0 ;; esac
    sleep 0.2
  done
  die "the node is not up (state '${state:-none}'); logs in $STATE/log"
}

start() {
  [ "$(id -u)" -eq 0 ] || die "needs root (slurmctld and slurmd run as root here)"
  install_packages
  mkdir -p "$STATE"
  if alive "$STATE/slurmctld.pid" && alive "$STATE/slurmd.pid" && scontrol ping >/dev/null 2>&1; then
    wait_idle
    say "already running: $(sinfo -h -N -o '%N %c CPUs %m MB %t')"
    return 0
  fi
  stop_daemons  # a half-started cluster (one daemon dead) is restarted from scratch
  start_munge
  write_conf
  # -c: a clean start, without the job state of an earlier run of this cluster.
  slurmctld -c -f "$CONF" || die "slurmctld did not start: $(tail -n 5 "$STATE/log/slurmctld.log" 2>/dev/null)"
  for _ in $(seq 50); do scontrol ping >/dev/null 2>&1 && break; sleep 0.2; done
  scontrol ping >/dev/null 2>&1 || die "slurmctld does not answer: $(tail -n 5 "$STATE/log/slurmctld.log" 2>/dev/null)"
  slurmd -f "$CONF" || die "slurmd did not start: $(tail -n 5 "$STATE/log/slurmd.log" 2>/dev/null)"
  wait_idle
  say "running: $(sinfo -h -N -o '%N %c CPUs %m MB %t')"
}

stop_pidfile() {  # stop_pidfile NAME: SIGTERM, then SIGKILL after 10 s
  local file="$STATE/$1.pid" pid
  alive "$file" || { rm -f "$file"; return 0; }
  pid="$(cat "$file")"
  kill "$pid" 2>/dev/null || true
  for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$pid" 2>/dev/null; then
    say "$1 ($pid) ignored SIGTERM for 10 s: killing it"
    kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}

stop_daemons() {
  # Jobs first, while slurmctld and slurmd can still end them (their slurmstepd processes would
  # otherwise outlive slurmd).
  if alive "$STATE/slurmctld.pid" && [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
    scancel --quiet --full $(squeue -h -o %i) 2>/dev/null || true
    for _ in $(seq 100); do [ -z "$(squeue -h -t R,CG,PD -o %i 2>/dev/null)" ] && break; sleep 0.1; done
  fi
  stop_pidfile slurmd
  stop_pidfile slurmctld
  stop_pidfile munged
}

stop() {
  [ -d "$STATE" ] || return 0
  stop_daemons
  # Our configuration goes with our cluster (not one that another state directory's cluster uses).
  [ "$(conf_state || true)" = "$STATE" ] && rm -f "$CONF"
  say "stopped"
}

status() {
  if alive "$STATE/slurmctld.pid" && alive "$STATE/slurmd.pid"; then
    sinfo -N -o '%N %c %m %t'
  else
    echo "not running"
    return 3
  fi
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
