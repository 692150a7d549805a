#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs COMMAND against a Slurm cluster (docs/sharded-compile.md "Slurm"):
#   scripts/slurm-local.sh COMMAND [ARGS...]
# By default a private single-node cluster: munged, slurmctld and slurmd of Debian's packages
# (slurm-wlm, munge; installed when missing), run as the current user from a state folder of
# their own (a new munge key, slurm.conf, spool, state and logs; ports that are free), with this
# machine's CPUs and memory as node "localhost" in partition "debug". COMMAND runs with
# SLURM_CONF pointing at it, so sbatch, squeue and scontrol talk to that cluster; when COMMAND
# ends (or on Ctrl-C) the daemons are stopped and the folder is removed. The exit status is
# COMMAND's, or 1 when the cluster does not come up (the end of the daemons' logs is printed).
#   NAVMAP_SLURM=existing    start nothing: COMMAND runs against the cluster this machine's Slurm
#                            client is configured for (SLURM_CONF, else /etc/slurm/slurm.conf),
#                            after checking that its controller answers
#   NAVMAP_SLURM_DIR=DIR     the state folder (default: a new one under ${TMPDIR:-/tmp})
#   NAVMAP_SLURM_KEEP=1      keep the state folder (logs) after the cluster has stopped
#   NAVMAP_SLURM_START_TIMEOUT=S   seconds to wait for the node to come up (default 60)
# `scripts/slurm-local.sh bash` gives a shell with a cluster to try sbatch in by hand.
set -euo pipefail
me="slurm-local"
[ $# -ge 1 ] || {
  echo "usage: $0 COMMAND [ARGS...]   (NAVMAP_SLURM=existing: use the configured cluster)" >&2
  exit 2
}

if [ "${NAVMAP_SLURM:-local}" = existing ]; then
  command -v sbatch >/dev/null 2>&1 || { echo "$me: NAVMAP_SLURM=existing, but sbatch is not installed" >&2; exit 1; }
  [ -z "${SLURM_CONF:-}" ] || [ -f "$SLURM_CONF" ] || { echo "$me: SLURM_CONF=$SLURM_CONF: no such file" >&2; exit 1; }
  if ! ping_out="$(scontrol ping 2>&1)" || ! grep -q "is UP" <<<"$ping_out"; then
    echo "$me: NAVMAP_SLURM=existing, but the cluster's controller does not answer (scontrol ping):" >&2
    echo "$ping_out" >&2
    exit 1
  fi
  echo "$me: using the configured cluster ($(scontrol show config 2>/dev/null | sed -n 's/^ClusterName *= *//p'))"
  exec "$@"
fi

case "${NAVMAP_SLURM:-local}" in
  local) ;;
  *) echo "$me: NAVMAP_SLURM is 'local' (default) or 'existing', not '$NAVMAP_SLURM'" >&2; exit 2 ;;
esac

# Debian's packages: the daemons, the client commands, munge (the authentication Slurm uses).
packages=(slurm-wlm munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null 2>&1 || { echo "$me: missing packages (${missing[*]}) and not root" >&2; exit 1; }
    SUDO=(sudo)
  fi
  echo "$me: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${SUDO[@]}" apt-get update -q >&2
  "${SUDO[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
fi
for tool in munged slurmctld slurmd sbatch sinfo scontrol; do
  command -v "$tool" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin"
  command -v "$tool" >/dev/null 2>&1 || { echo "$me: $tool not found after installing ${packages[*]}" >&2; exit 1; }
done

dir="${NAVMAP_SLURM_DIR:-}"
if [ -z "$dir" ]; then dir="$(mktemp -d "${TMPDIR:-/tmp}/navmap-slurm.XXXXXX")"; else mkdir -p "$dir"; fi
dir="$(cd "$dir" && pwd)"
chmod 700 "$dir"
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 700 "$dir/munge"
user="$(id -un)"
pids=()
stop() {
  local status=$?
  trap - EXIT INT TERM
  # Jobs still running (COMMAND interrupted) are cancelled first, so that none outlives slurmd.
  if [ ${#pids[@]} -eq 3 ] && scancel -u "$user" 2>/dev/null; then
    for _ in $(seq 20); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.5; done
  fi
  # slurmd, slurmctld, munged: each given 10 s to stop.
  local i pid
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    pid="${pids[i]}"
    kill "$pid" 2>/dev/null || continue
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  if [ "${NAVMAP_SLURM_KEEP:-0}" = 1 ]; then echo "$me: state and logs kept in $dir" >&2; else rm -rf "$dir"; fi
  exit "$status"
}
trap stop EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
fail() {
  echo "$me: $1" >&2
  for log in "$dir"/munged.log "$dir"/slurmctld.log "$dir"/slurmd.log; do
    [ -s "$log" ] && { echo "--- end of $log:" >&2; tail -n 15 "$log" >&2; }
  done
  exit 1
}

# Two TCP ports nobody listens on (slurmctld's and slurmd's), so that a cluster already running
# on this machine (ports 6817/6818) and this one do not meet.
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
ports=()
for port in $(shuf -i 20000-59999 -n 200); do
  port_free "$port" && port_free $((port + 1)) && { ports=("$port" $((port + 1))); break; }
done
[ ${#ports[@]} -eq 2 ] || fail "no two free TCP ports found"

# munge: a key made for this run and a socket in the state folder (munged refuses a key or a
# folder that others may read or write).
mungekey --create --keyfile="$dir/munge/munge.key" --bits=1024 >/dev/null 2>&1 \
  || dd if=/dev/urandom of="$dir/munge/munge.key" bs=128 count=1 status=none
chmod 400 "$dir/munge/munge.key"
sock="$dir/munge/munge.socket"
munged --foreground --force --socket="$sock" --key-file="$dir/munge/munge.key" \
  --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed" --log-file="$dir/munged.log" \
  >>"$dir/munged.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$sock" ] && break; kill -0 "${pids[0]}" 2>/dev/null || break; sleep 0.1; done
[ -S "$sock" ] || fail "munged did not start"

# The node as slurmd sees this machine (CPUs, sockets, cores, threads, memory), named localhost;
# 95 % of the memory, so that what the kernel reports after boot never falls below it.
node="$(slurmd -C | head -n 1)"
mem="$(sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p' <<<"$node")"
[ -n "$mem" ] || fail "slurmd -C did not report the machine ($node)"
node="$(sed -e 's/^NodeName=[^ ]*/NodeName=localhost NodeAddr=127.0.0.1 NodeHostname=localhost/' \
  -e "s/RealMemory=[0-9]*/RealMemory=$((mem * 95 / 100))/" <<<"$node")"
conf="$dir/slurm.conf"
cat >"$conf" <<EOF
# A private single-node cluster of scripts/slurm-local.sh.
ClusterName=navmap-local
SlurmctldHost=localhost
SlurmctldPort=${ports[0]}
SlurmdPort=${ports[1]}
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
MailProg=/bin/true
MinJobAge=3600
$node State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$conf"

slurmctld -D -i -f "$conf" >>"$dir/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -f "$conf" -N localhost >>"$dir/slurmd.log" 2>&1 &
pids+=($!)

timeout_s="${NAVMAP_SLURM_START_TIMEOUT:-60}"
state=""
for _ in $(seq $((timeout_s * 2))); do
  for pid in "${pids[@]}"; do kill -0 "$pid" 2>/dev/null || fail "a daemon exited while starting"; done
  state="$(sinfo -h -N -n localhost -o %T 2>/dev/null || true)"
  case "$state" in idle*|mixed*|allocated*) break ;; esac
  sleep 0.5
done
case "$state" in
  idle*|mixed*|allocated*) ;;
  *) fail "node localhost not up after $timeout_s s (state: ${state:-no answer from slurmctld})" ;;
esac
echo "$me: cluster navmap-local up (node localhost: $(sed 's/^NodeName=localhost NodeAddr=[^ ]* NodeHostname=[^ ]* //' <<<"$node"); ports ${ports[0]}, ${ports[1]}; SLURM_CONF=$conf)"

status=0
"$@" || status=$?
exit "$status"
