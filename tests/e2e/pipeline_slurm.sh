#!/usr/bin/env bash
# pipelines/character.mk through a real scheduler: a single-node SLURM (slurmctld + slurmd +
# munged, Debian's slurm-wlm and munge) started on localhost in a temporary directory, the tiny
# pipeline run with SUBMIT="srun ..." and the alignment as registration jobs (REGISTER_JOBS=2: a
# trunk job, two shard jobs, the merge), its outputs byte-identical to a local run with one
# registration job, and every heavy step a SLURM job; then a cut of the long capture through
# histograms, similarity, tree and three registration shards on SLURM against one local job. Installs slurm-wlm and munge when they are
# missing and it runs as root with apt; otherwise, or when the daemons cannot start here, it is
# skipped (exit 77) with the reason (SURFCAP_REQUIRE_SLURM=1 turns a daemon that does not start
# into a failure).
# Usage: bash pipeline_slurm.sh <build_dir> <source_dir>
set -euo pipefail
build=$1
source=$2
# shellcheck source=pipeline_lib.bash
. "$source/tests/e2e/pipeline_lib.bash"
pipeline_require_tools

export PATH=$PATH:/usr/sbin
missing() {
  local daemon
  for daemon in munged munge slurmctld slurmd srun sinfo scontrol; do command -v "$daemon" >/dev/null || return 0; done
  return 1
}
if missing; then
  if [[ $(id -u) -ne 0 ]] || ! command -v apt-get >/dev/null; then
    echo "SKIP: slurm-wlm and munge are not installed (apt-get install slurm-wlm munge, as root, enables this test)"
    exit 77
  fi
  echo "installing slurm-wlm and munge"
  export DEBIAN_FRONTEND=noninteractive
  apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends slurm-wlm munge > /dev/null 2>&1 \
    || { apt-get -o DPkg::Lock::Timeout=600 update -qq && apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends slurm-wlm munge > /dev/null; } \
    || { echo "SKIP: apt-get could not install slurm-wlm and munge"; exit 77; }
fi
[[ $(id -u) -eq 0 ]] || { echo "SKIP: the single-node SLURM of this test runs its daemons as root"; exit 77; }

work=$(mktemp -d "${TMPDIR:-/tmp}/pipeline_slurm.XXXXXX")
chmod 755 "$work"
cluster=$work/slurm
mkdir -p "$cluster"/{state,spool,log,munge}
export SLURM_CONF=$cluster/slurm.conf
stop_cluster() {
  scontrol shutdown >/dev/null 2>&1 || true
  for pidfile in "$cluster/slurmd.pid" "$cluster/slurmctld.pid" "$cluster/munge/munged.pid"; do
    [[ -s $pidfile ]] || continue
    local pid
    pid=$(cat "$pidfile")
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; kill "$pid" 2>/dev/null || true; sleep 0.1; done
  done
}
trap 'stop_cluster; rm -rf "$work"' EXIT
cannot_start() {  # cannot_start WHAT: skip (or fail) with the daemons' log
  echo "$1"
  tail -n 20 "$cluster"/log/*.log "$cluster"/munge/munged.log 2>/dev/null || true
  if [[ ${SURFCAP_REQUIRE_SLURM:-0} == 1 ]]; then exit 1; fi
  echo "SKIP: SLURM cannot run in this environment"
  exit 77
}

# munge: a fresh key and socket of our own, so a system munged (if any) is left alone.
socket=$cluster/munge/munge.socket
head -c 1024 /dev/urandom > "$cluster/munge/munge.key"
chmod 400 "$cluster/munge/munge.key"
munged --force --socket="$socket" --key-file="$cluster/munge/munge.key" --log-file="$cluster/munge/munged.log" \
  --pid-file="$cluster/munge/munged.pid" --seed-file="$cluster/munge/munged.seed" \
  || cannot_start "munged did not start"
for _ in $(seq 50); do [[ -S $socket ]] && break; sleep 0.1; done
echo ok | munge -S "$socket" | unmunge -S "$socket" > /dev/null || cannot_start "munge cannot encode/decode a credential"

read -r controller_port node_port < <(python3 -c '
import socket
ports = []
sockets = [socket.socket() for _ in range(2)]
for s in sockets:
    s.bind(("127.0.0.1", 0)); ports.append(s.getsockname()[1])
print(*ports)')
node=$(hostname -s)
cat > "$SLURM_CONF" <<EOF
ClusterName=surfcap
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$controller_port
SlurmdPort=$node_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$cluster/state
SlurmdSpoolDir=$cluster/spool
SlurmctldPidFile=$cluster/slurmctld.pid
SlurmdPidFile=$cluster/slurmd.pid
SlurmctldLogFile=$cluster/log/slurmctld.log
SlurmdLogFile=$cluster/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld || cannot_start "slurmctld did not start"
slurmd || cannot_start "slurmd did not start"
for _ in $(seq 100); do
  [[ $(sinfo --noheader --nodes="$node" --format=%t 2>/dev/null) == idle ]] && break
  sleep 0.2
done
[[ $(sinfo --noheader --nodes="$node" --format=%t 2>/dev/null) == idle ]] || cannot_start "the node did not become idle"
[[ $(srun --quiet -n1 -c1 echo ok 2>&1) == ok ]] || cannot_start "srun cannot run a job"
sinfo

"$build/tools/surfcap-synth" --preset tiny --seed 1 --no-images --out "$work/capture" --log-level warn
read -r -a targets <<< "$(pipeline_targets)"
echo "targets: ${targets[*]} alignment"
# The whole chain from the capture, with a quick alignment (accuracy is not the point here).
common=(DATABASE=aligned BLOCKS=2 THREADS=1 SPACES_OPTIONS="--sweep-mm 5 --validation-samples 2"
        REGISTER_OPTIONS="--levels 1 --rotation-iterations 1 --dense-iterations 1 --surface-model --no-evaluation")
pipeline_make "$work/local" "${common[@]}" -j2 "${targets[@]}" alignment
jobs_before=$(scontrol show jobs --oneline 2>/dev/null | grep -c JobId= || true)
pipeline_make "$work/slurm" "${common[@]}" -j2 SUBMIT="srun --quiet --ntasks=1 --cpus-per-task=1" REGISTER_JOBS=2 \
  "${targets[@]}" alignment
pipeline_same "$work/local" "$work/slurm"
[[ $(grep -c $'^align\.register\.shard\t' "$work/slurm/out/report/steps.tsv") -eq 2 ]] \
  || { echo "the alignment did not run as two shard jobs"; exit 1; }

# Every heavy step (all but merge, tree and graph) ran as a SLURM job, and they all completed.
heavy=$(cut -f1 "$work/slurm/out/report/steps.tsv" | grep -cvE '^(align\.merge|align\.tree|precompute\.graph)$')
jobs=$(scontrol show jobs --oneline | grep -c JobId=)
completed=$(scontrol show jobs --oneline | grep -c 'JobState=COMPLETED')
echo "$heavy heavy steps, $((jobs - jobs_before)) SLURM jobs ($completed completed)"
[[ $((jobs - jobs_before)) -eq $heavy && $completed -eq $jobs ]] || { scontrol show jobs --oneline; exit 1; }

# A cut of the long capture (the first 2 frames of each of its 28 takes, ~10,000-vertex
# reconstructions): histograms → similarity → tree → registration as a trunk job and three shard
# jobs on SLURM, byte-identical to one local registration job.
"$build/tools/surfcap-synth" --preset long --frames-per-sequence 2 --out "$work/long/capture" --log-level warn
long=(DATABASE=aligned BLOCKS=2 THREADS=1
      REGISTER_OPTIONS="--levels 1 --rotation-iterations 1 --dense-iterations 1 --no-evaluation")
pipeline_make "$work/long/local" "${long[@]}" -j2 alignment
pipeline_make "$work/long/slurm" "${long[@]}" -j2 SUBMIT="srun --quiet --ntasks=1 --cpus-per-task=1" REGISTER_JOBS=3 \
  alignment
pipeline_same "$work/long/local" "$work/long/slurm"
python3 - "$work/long/slurm/out/aligned/report" <<'PY'
import json, sys
report = json.load(open(sys.argv[1] + "/alignment.json"))
assert report["summary"]["frames"] == 56, report["summary"]["frames"]
for k in (1, 2, 3):
    shard = json.load(open(f"{sys.argv[1]}/register-shard-{k}-of-3.json"))
    assert shard["job"]["frames"] > 0, f"shard {k} of 3 has no frames"
PY
[[ $(grep -c $'^align\.register\.shard\t' "$work/long/slurm/out/report/steps.tsv") -eq 3 ]] \
  || { echo "the long cut did not register as three shard jobs"; exit 1; }
echo "pipeline_slurm: ok"
