#!/usr/bin/env bash
# A design study through a real Slurm (issue 20 item 6): sets up a one-node cluster on this
# machine (Debian's slurm-wlm and munge, installed by scripts/setup; its own munge key,
# socket, ports and spool under a temporary folder, so nothing of the machine's own
# configuration is used or changed), runs STUDY through scripts/study-slurm as a job array
# of SHARDS tasks and checks that the merged result is byte-identical to `colosim study
# STUDY --json` run here. The daemons are stopped on exit, whatever happens.
#   study_slurm.sh COLOSIM STUDY-SLURM-SCRIPT STUDY.json SHARDS
# Exit 77 (skipped) when the Slurm or munge daemons are not installed or not root.
set -euo pipefail
colosim="$1" script="$2" study="$3" shards="${4:-3}"
for exe in munged slurmctld slurmd sbatch squeue; do
  command -v "$exe" > /dev/null || PATH="$PATH:/usr/sbin"
  command -v "$exe" > /dev/null || { echo "SKIP: $exe not installed (scripts/setup installs slurm-wlm and munge)"; exit 77; }
done
[ "$(id -u)" = 0 ] || { echo "SKIP: the one-node cluster is started as root"; exit 77; }

tmp="$(mktemp -d /tmp/colosim-slurm.XXXXXX)"
chmod 755 "$tmp"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  sleep 0.5
  for p in "${pids[@]}"; do kill -9 "$p" 2> /dev/null || true; done
  if [ "${KEEP:-0}" = 1 ]; then echo "kept $tmp"; else rm -rf "$tmp"; fi
}
trap cleanup EXIT

host="$(hostname -s)"
cpus="$(nproc)"
# Ports away from Slurm's defaults (6817/6818), so that a machine's own Slurm is untouched.
ctl_port=$((17000 + RANDOM % 2000)) d_port=$((19000 + RANDOM % 2000))
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log" "$tmp/run"
chmod 700 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
munged --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/munge.socket" \
  --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/log/munged.log" --seed-file="$tmp/munge/munged.seed"
for _ in $(seq 50); do [ -s "$tmp/munge/munged.pid" ] && break; sleep 0.1; done
pids+=("$(cat "$tmp/munge/munged.pid")")

cat > "$tmp/slurm.conf" <<CONF
ClusterName=colosimtest
SlurmctldHost=$host
SlurmctldPort=$ctl_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=colosim Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$tmp/slurm.conf"
slurmctld -D -f "$SLURM_CONF" > "$tmp/log/slurmctld.out" 2>&1 & pids+=($!)
slurmd -D -f "$SLURM_CONF" > "$tmp/log/slurmd.out" 2>&1 & pids+=($!)
up=0
for _ in $(seq 100); do
  if sinfo -h -o '%T' 2> /dev/null | grep -qE '^(idle|mixed|allocated)'; then up=1; break; fi
  sleep 0.2
done
if [ "$up" != 1 ]; then
  echo "FAIL: the one-node Slurm did not come up"; sinfo 2>&1 || true
  tail -20 "$tmp/log/slurmctld.log" "$tmp/log/slurmd.log" 2> /dev/null || true
  exit 1
fi
echo "one-node Slurm up on $host ($cpus CPUs)"

"$script" "$study" --shards "$shards" --out "$tmp/out" --colosim "$colosim" --cpus-per-task 1 --wait
"$colosim" study "$study" --json --threads "$cpus" > "$tmp/local.json"
ls "$tmp/out/shards"
if ! cmp "$tmp/local.json" "$tmp/out/result.json"; then
  echo "FAIL: the Slurm result differs from the local run"; diff "$tmp/local.json" "$tmp/out/result.json" | head
  exit 1
fi
n_logs="$(ls "$tmp/out/logs" | grep -c '^shard-.*\.out$')"
[ "$n_logs" = "$shards" ] || { echo "FAIL: $n_logs array tasks ran, expected $shards"; exit 1; }
echo "PASS: $shards array tasks merged into the same bytes as the local run"
