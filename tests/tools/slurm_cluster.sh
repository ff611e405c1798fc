#!/usr/bin/env bash
# A throw-away single-node Slurm cluster in a folder: slurmctld and slurmd on 127.0.0.1 with
# their own ports, configuration, state, spool and logs, run as root (directly or through
# `sudo -n`), no munge key (auth/none). Sourced by the tests that need a scheduler.
#
#   . slurm_cluster.sh; slurm_start DIR || exit 77; ...; slurm_stop
# slurm_start returns 1 (and says why) when Slurm cannot run here; it exports SLURM_CONF so that
# sbatch, squeue, scontrol talk to this cluster only.

SLURM_DIR=""
SLURM_SUDO=""

slurm_free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

slurm_start() {
  SLURM_DIR=$1
  local cmd
  for cmd in slurmctld slurmd sbatch squeue scontrol sacct python3; do
    command -v "$cmd" >/dev/null 2>&1 || PATH=$PATH:/usr/sbin command -v "$cmd" >/dev/null 2>&1 ||
      { echo "slurm: $cmd not installed (Debian: slurm-wlm)"; return 1; }
  done
  if [ "$(id -u)" != 0 ]; then
    sudo -n true 2>/dev/null || { echo "slurm: the daemons need root and sudo -n is refused"; return 1; }
    SLURM_SUDO="sudo -n"
  fi
  local ctld=$(PATH=$PATH:/usr/sbin command -v slurmctld) slurmd=$(PATH=$PATH:/usr/sbin command -v slurmd)
  local cpus=$(nproc)
  [ "$cpus" -ge 2 ] || cpus=2
  mkdir -p "$SLURM_DIR/state" "$SLURM_DIR/spool"
  cat >"$SLURM_DIR/slurm.conf" <<CONF
ClusterName=ramtktest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$(slurm_free_port)
SlurmdPort=$(slurm_free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/none
# Credentials live 10 s, not 120: a requeued job waits that long before it may start again.
AuthInfo=cred_expire=10
CredType=cred/none
StateSaveLocation=$SLURM_DIR/state
SlurmdSpoolDir=$SLURM_DIR/spool
SlurmctldPidFile=$SLURM_DIR/slurmctld.pid
SlurmdPidFile=$SLURM_DIR/slurmd.pid
SlurmctldLogFile=$SLURM_DIR/slurmctld.log
SlurmdLogFile=$SLURM_DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/builtin
# The main scheduling pass every 2 s, not 60: a requeued job starts when it becomes eligible.
SchedulerParameters=sched_interval=2
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MinJobAge=600
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=ramtk1 NodeHostname=$(hostname -s) NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=8192 State=UNKNOWN
PartitionName=test Nodes=ramtk1 Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$SLURM_DIR/slurm.conf
  $SLURM_SUDO env SLURM_CONF="$SLURM_CONF" "$ctld" -i || { echo "slurm: slurmctld did not start"; slurm_logs; return 1; }
  $SLURM_SUDO env SLURM_CONF="$SLURM_CONF" "$slurmd" -N ramtk1 || { echo "slurm: slurmd did not start"; slurm_logs; slurm_stop; return 1; }
  local i
  for i in $(seq 1 60); do
    if sinfo -h -n ramtk1 -o %t 2>/dev/null | grep -q '^idle'; then return 0; fi
    sleep 0.5
  done
  echo "slurm: the node did not become idle in 30 s ($(sinfo -h -o %t 2>&1))"
  slurm_logs
  slurm_stop
  return 1
}

slurm_logs() {
  local f
  for f in "$SLURM_DIR/slurmctld.log" "$SLURM_DIR/slurmd.log"; do
    [ -r "$f" ] && { echo "--- $f"; tail -n 20 "$f"; }
  done
}

# Cancels this cluster's jobs, then stops the two daemons this folder started (by their pid
# files), nothing else.
slurm_stop() {
  [ -n "$SLURM_DIR" ] || return 0
  local f pid
  if [ -r "$SLURM_DIR/slurmctld.pid" ]; then
    scancel -u "$(id -un)" 2>/dev/null
    for _ in $(seq 1 40); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.25; done
  fi
  for f in "$SLURM_DIR/slurmd.pid" "$SLURM_DIR/slurmctld.pid"; do
    pid=$(cat "$f" 2>/dev/null) || continue
    [ -n "$pid" ] && $SLURM_SUDO kill "$pid" 2>/dev/null
  done
  for f in "$SLURM_DIR/slurmd.pid" "$SLURM_DIR/slurmctld.pid"; do
    pid=$(cat "$f" 2>/dev/null) || continue
    for _ in $(seq 1 20); do $SLURM_SUDO kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
  done
  # Under sudo the daemons wrote root-owned files: hand the folder back so it can be removed.
  [ -n "$SLURM_SUDO" ] && $SLURM_SUDO chown -R "$(id -u):$(id -g)" "$SLURM_DIR"
  SLURM_DIR=""
}
