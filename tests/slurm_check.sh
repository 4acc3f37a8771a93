#!/usr/bin/env bash
# A study on a real Slurm: a single-node cluster on localhost (munged,
# slurmctld, slurmd with a minimal slurm.conf in a temporary directory),
# the 4-case study tests/data/study_small.toml submitted with
# `chaindrive study slurm --submit`, the job array waited for, the cases
# collected, and results.parquet read with pyarrow: 4 rows, every case
# finished (ok, or warned where its summary warns), the same table as
# results.csv.
#
#   bash tests/slurm_check.sh [BINARY]
#
# Installs `slurm-wlm` and `munge` from the machine's Debian packages where
# they are missing (needs root and a package index); where it cannot, it
# says so and exits non-zero. Every daemon it starts is stopped by its
# process id when it ends. pyarrow comes from tests/pyarrow_check.sh's
# virtual environment (network access for `pip` the first time). About a
# minute once everything is installed.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-target/release/chaindrive}")
[[ -x $bin ]] || { echo "slurm_check: no binary at $bin (cargo build --release)" >&2; exit 1; }

# --- Slurm and munge from Debian --------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
  || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "slurm_check: FAILED: slurm-wlm and munge are not installed and this is not root; cannot install them (apt-get needs root)" >&2
    exit 1
  fi
  if ! command -v apt-get >/dev/null; then
    echo "slurm_check: FAILED: slurm-wlm and munge are not installed and there is no apt-get to install them" >&2
    exit 1
  fi
  echo "slurm_check: installing slurm-wlm and munge (apt-get)"
  export DEBIAN_FRONTEND=noninteractive
  if ! apt-get install -y --no-install-recommends slurm-wlm munge >/dev/null 2>&1; then
    apt-get update >/dev/null 2>&1 || true
    if ! apt-get install -y --no-install-recommends slurm-wlm munge >/dev/null; then
      echo "slurm_check: FAILED: cannot install slurm-wlm and munge from the package index" >&2
      exit 1
    fi
  fi
fi

# --- pyarrow ------------------------------------------------------------------
source tests/pyarrow_check.sh

# --- a single-node cluster on localhost --------------------------------------
dir=$(mktemp -d /tmp/chaindrive-slurm.XXXXXX)
chmod 700 "$dir"
pids=()
cleanup() {
  local status=$?
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill -TERM "${pids[i]}" 2>/dev/null || true
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  if ((status != 0)); then
    for log in "$dir"/*.log "$dir"/study/slurm/*.out; do
      [[ -f $log ]] && { echo "--- $log" >&2; tail -n 20 "$log" >&2; }
    done
  fi
  rm -rf "$dir"
}
trap cleanup EXIT

# munged with its own key and socket.
dd if=/dev/urandom of="$dir/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge.key"
munged --foreground --force --key-file="$dir/munge.key" --socket="$dir/munge.socket" \
  --pid-file="$dir/munged.pid" --seed-file="$dir/munge.seed" --log-file="$dir/munged.log" \
  >"$dir/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 1 50); do [[ -S $dir/munge.socket ]] && break; sleep 0.1; done
[[ -S $dir/munge.socket ]] || { echo "slurm_check: FAILED: munged did not start" >&2; exit 1; }

ports=$(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
read -r ctld_port slurmd_port <<<"$ports"
host=$(hostname -s)
# The node's real CPUs and memory, as slurmd sees them.
node=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$host/")
mkdir -p "$dir/state" "$dir/spool"
cat >"$dir/slurm.conf" <<EOF
ClusterName=chaindrive
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge.socket
CredType=cred/munge
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
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=check Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$dir/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >"$dir/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$host" >"$dir/slurmd.out" 2>&1 &
pids+=($!)
state=
for _ in $(seq 1 120); do
  state=$(sinfo -h -o %T 2>/dev/null | head -n 1 || true)
  [[ $state == idle ]] && break
  sleep 0.5
done
[[ $state == idle ]] || { echo "slurm_check: FAILED: the node is not idle (state: ${state:-none})" >&2; exit 1; }
echo "slurm_check: cluster up (node $host idle)"

# --- the study ----------------------------------------------------------------
job=$("$bin" study slurm tests/data/study_small.toml --out "$dir/study" \
  --partition check --time 00:05:00 --cpus-per-task 1 --array-limit 2 --submit)
[[ $job =~ ^[0-9]+$ ]] || { echo "slurm_check: FAILED: no job id from --submit: $job" >&2; exit 1; }
echo "slurm_check: submitted job array $job"
for _ in $(seq 1 360); do
  [[ -z $(squeue -h -j "$job" 2>/dev/null) ]] && break
  sleep 0.5
done
[[ -z $(squeue -h -j "$job" 2>/dev/null) ]] || { echo "slurm_check: FAILED: the array did not finish in 3 minutes" >&2; exit 1; }
"$bin" study collect "$dir/study"

check_results "$dir/study" 4 slurm_check
echo "slurm_check: ok"
