#!/usr/bin/env bash
# A real Slurm on this machine: munge, slurmctld and slurmd started on localhost with a private
# configuration in a temporary folder (nothing of the system's is used or changed), then the
# recipe tools/slurm/laserfit-bench-slurm runs the quick benchmark as a 4-task and as a 16-task
# array (12 trials: 4 tasks get none), and GNU parallel runs it as 4 shards. Each merge must
# equal a single run record by record (all but "timing"). Only the daemons started here are
# stopped. Needs the Debian packages of `make deps-slurm`; run as root (the daemons' user).
#
#   tests/slurm/test_slurm.sh BUILD_BIN_DIR
set -euo pipefail
bin="$(realpath "${1:?usage: test_slurm.sh BUILD_BIN_DIR}")"
repo="$(cd "$(dirname "$0")/../.." && pwd)"
tmp="$(mktemp -d /tmp/laserfit-slurm.XXXXXX)"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  for f in "$tmp/slurmctld.pid" "$tmp/slurmd.pid" "$tmp/munge/pid"; do
    [ -f "$f" ] && kill "$(cat "$f")" 2> /dev/null || true
  done
  sleep 1
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "test_slurm: FAILED: $*" >&2; for f in "$tmp"/log/*.log; do echo "== $f"; tail -n 20 "$f"; done >&2; exit 1; }
t0=$(date +%s)

# --- a private Slurm --------------------------------------------------------------------------
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log"
chmod 700 "$tmp/munge"
mungekey -c -k "$tmp/munge/munge.key" -b 1024 > /dev/null
munged -S "$tmp/munge/sock" --key-file="$tmp/munge/munge.key" --pid-file="$tmp/munge/pid" \
  --log-file="$tmp/log/munge.log" --seed-file="$tmp/munge/seed" -f
port=$((20000 + RANDOM % 20000))
node=$(hostname -s)
mem=$(($(awk '/MemTotal/{print $2}' /proc/meminfo) / 1024 - 2048))
cat > "$tmp/slurm.conf" << CONF
ClusterName=laserfit-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
DefMemPerCPU=2048
MpiDefault=none
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$tmp/slurm.conf"
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 60); do sinfo -h -o %t 2> /dev/null | grep -q idle && break; sleep 1; done
sinfo -h -o %t | grep -q idle || fail "slurmd did not come up"
echo "test_slurm: Slurm up on $node (ports $port, $((port + 1))) in $(($(date +%s) - t0)) s"

# --- the runs ---------------------------------------------------------------------------------
bench="$repo/benchmarks/quick.yaml"
"$bin/laserfit" bench "$bench" --out "$tmp/single" --jobs "$(nproc)" --quiet --no-overlays > /dev/null
same() {  # results.jsonl of a merge vs the single run, without "timing"
  python3 - "$tmp/single/results.jsonl" "$1/results.jsonl" << 'PY'
import json, sys
def load(p):
    rs = [json.loads(l) for l in open(p)]
    for r in rs: r.pop("timing", None)
    return rs
a, b = load(sys.argv[1]), load(sys.argv[2])
if a != b:
    print(f"{len(a)} records in the single run, {len(b)} merged; first difference at",
          next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b))))
    sys.exit(1)
print(f"test_slurm: {len(b)} records identical to the single run")
PY
}
wait_job() {  # until job $1 has left the queue; then its state must be COMPLETED
  for _ in $(seq 900); do squeue -h -j "$1" 2> /dev/null | grep -q . || break; sleep 1; done
  state=$(scontrol show job "$1" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -1)
  [ "$state" = COMPLETED ] || fail "job $1 ended $state"
}
for tasks in 4 16; do
  out="$tmp/slurm$tasks"
  # Submitted from another folder: the recipe's paths are absolute.
  line=$(cd / && "$repo/tools/slurm/laserfit-bench-slurm" "$bench" --tasks "$tasks" --out "$out" \
    --laserfit "$bin/laserfit" -- --no-overlays)
  echo "test_slurm: $line"
  merge=$(echo "$line" | sed -n 's/.*merge job \([0-9]*\).*/\1/p')
  wait_job "$merge"
  same "$out/merged" || fail "$tasks-task array merge differs from the single run"
  jobs=$(python3 -c "import json; print(json.load(open('$out/shards/0/run.json'))['jobs_source'])")
  [ "$jobs" = SLURM_CPUS_PER_TASK ] || fail "a task's --jobs came from $jobs, not its allocation"
done
# GNU parallel, locally, as the README's recipe runs it across hosts.
parallel -j 2 "$bin/laserfit" bench "$bench" --shard {}/4 --out "$tmp/par/{}" --quiet --no-overlays \
  ::: 0 1 2 3 > /dev/null
"$bin/laserfit" bench merge "$tmp"/par/{0,1,2,3} -o "$tmp/par/merged" > /dev/null
same "$tmp/par/merged" || fail "GNU parallel merge differs from the single run"
echo "test_slurm: 3 passed, 0 failed in $(($(date +%s) - t0)) s"
