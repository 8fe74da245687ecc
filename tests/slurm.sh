#!/bin/sh
# tests/slurm.sh - polarcam dataset under a real scheduler: a single-node Slurm cluster (Debian
# 12's slurmctld, slurmd and munge) started here with a temporary configuration, run by
# tests/netns.sh in private network and PID namespaces (loopback only; every daemon dies with
# the namespace).
#
#   1. the dataset made locally in one shard (the reference);
#   2. a 4-task array job (sbatch --array=0-3) of `polarcam dataset`, each task taking its shard
#      from SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT; task 1 is killed mid-way (it has made one
#      of its samples) by `scontrol requeue` and runs again from where it stopped;
#   3. `polarcam dataset merge`: the merged manifest is byte-identical to the local one, and
#      `polarcam dataset verify` passes.
# Exit 77 with the reason when Slurm is missing or cannot start.
# Environment: POLARCAM (the CLI), PC_SOURCE_DIR (the source tree).
set -u
skip() {
	echo "SKIP: $*" >&2
	exit 77
}
start=$(date +%s)
: "${POLARCAM:?POLARCAM not set (run through ctest)}" "${PC_SOURCE_DIR:?PC_SOURCE_DIR not set}"
for b in slurmctld slurmd munged sbatch scontrol squeue; do
	command -v $b >/dev/null 2>&1 ||
		skip "$b not installed (Debian 12: slurmctld slurmd munge slurm-client)"
done
[ "$(id -u)" = 0 ] || skip "slurmd starts jobs as their owner: it needs root"
[ $$ -lt 1000 ] || skip "no private PID namespace (the daemons could outlive the test)"

T=$(mktemp -d /tmp/pc_slurm_XXXXXX)
chmod 755 "$T" # munged wants its socket's directories searchable by all
# Slurm resolves its listening addresses with AI_ADDRCONFIG, which finds nothing when loopback is
# the only interface: a private address on lo (this namespace's own) gives it one.
ip addr add 10.254.0.1/32 dev lo 2>/dev/null || skip "cannot add an address to lo in the namespace"
logs() {
	for f in "$T"/*.log "$T"/out-*.txt; do
		[ -f "$f" ] && { echo "--- $f" >&2; tail -n 25 "$f" >&2; }
	done
}
fail() {
	echo "FAIL: $*" >&2
	logs
	exit 1
}
cleanup() {
	rm -rf "$T"
}
trap cleanup EXIT

SPEC=$PC_SOURCE_DIR/scenes/dataset/demosaic.json
N=12
ARGS="--count $N --seed 3 --resolution 96x64 -t 1"

# 1. the reference, made locally in one shard
"$POLARCAM" dataset "$SPEC" -o "$T/local" $ARGS --shard 0/1 >"$T/local.log" 2>&1 ||
	fail "local run"
"$POLARCAM" dataset merge "$T/local" >>"$T/local.log" 2>&1 || fail "local merge"

# 2. munge with a key of its own, on a socket of its own
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 2>/dev/null
chmod 400 "$T/munge.key"
munged --force --socket="$T/munge.sock" --key-file="$T/munge.key" --pid-file="$T/munged.pid" \
	--log-file="$T/munged.log" --seed-file="$T/munged.seed" 2>>"$T/munged.log" ||
	skip "munged does not start: $(tail -n 3 "$T/munged.log" | tr '\n' ' ')"

host=$(hostname -s 2>/dev/null || hostname)
mkdir -p "$T/state" "$T/spool"
: >"$T/plugstack.conf"
cat >"$T/slurm.conf" <<EOF
ClusterName=polarcam
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=6817
SlurmdPort=6818
AuthType=auth/munge
# a requeued job may start again cred_expire + 1 s after the requeue (default 120 s)
AuthInfo=socket=$T/munge.sock,cred_expire=5
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
PlugStackConfig=$T/plugstack.conf
ProctrackType=proctrack/pgid
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=600
# the scheduler's periodic pass (default every 60 s) starts the requeued task
SchedulerParameters=sched_interval=1
SlurmdTimeout=30
NodeName=pcnode NodeAddr=127.0.0.1 NodeHostname=$host CPUs=2 RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=pcnode Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$T/slurm.conf"
slurmctld -c -i -f "$T/slurm.conf" 2>>"$T/slurmctld.log" ||
	skip "slurmctld does not start: $(tail -n 3 "$T/slurmctld.log" | tr '\n' ' ')"
slurmd -N pcnode -f "$T/slurm.conf" 2>>"$T/slurmd.log" ||
	skip "slurmd does not start: $(tail -n 3 "$T/slurmd.log" | tr '\n' ' ')"
# bounded waits: a client of a controller that is not up retries for long
deadline=$(($(date +%s) + 40))
ok=
while [ "$(date +%s)" -lt "$deadline" ]; do
	if timeout 3 scontrol show node pcnode 2>/dev/null | grep -q 'State=IDLE'; then
		ok=1
		break
	fi
	kill -0 "$(cat "$T/slurmctld.pid" 2>/dev/null)" 2>/dev/null || break
	sleep 0.2
done
[ -n "$ok" ] || skip "the Slurm node did not come up: $(tail -n 2 "$T/slurmctld.log" | tr '\n' ' ') $(tail -n 2 "$T/slurmd.log" | tr '\n' ' ')"
up=$(date +%s)

# 3. the array job; task 1's first run stops after one sample and waits to be killed
cat >"$T/job.sh" <<EOF
#!/bin/sh
if [ "\$SLURM_ARRAY_TASK_ID" = 1 ] && [ "\${SLURM_RESTART_COUNT:-0}" = 0 ]; then
	POLARCAM_DATASET_STOP_AFTER=1 "$POLARCAM" dataset "$SPEC" -o "$T/slurm" $ARGS || exit 1
	touch "$T/task1-paused"
	sleep 600
fi
exec "$POLARCAM" dataset "$SPEC" -o "$T/slurm" $ARGS
EOF
chmod +x "$T/job.sh"
job=$(timeout 20 sbatch --parsable --array=0-3 --requeue -c 1 -o "$T/out-%A_%a.txt" "$T/job.sh" 2>"$T/sbatch.log") ||
	fail "sbatch: $(cat "$T/sbatch.log")"
job=${job%%;*}
for _ in $(seq 1 600); do
	[ -e "$T/task1-paused" ] && break
	sleep 0.1
done
[ -e "$T/task1-paused" ] || fail "task 1 did not reach its pause"
# shard 1 of 4 is samples 1, 5, 9: exactly one made before the kill
n1=0
for i in 00000001 00000005 00000009; do [ -d "$T/slurm/samples/$i" ] && n1=$((n1 + 1)); done
[ "$n1" = 1 ] || fail "task 1 had made $n1 of its samples before the kill, expected 1"
timeout 20 scontrol requeue "${job}_1" 2>"$T/requeue.log" || fail "scontrol requeue: $(cat "$T/requeue.log")"
requeued=$(date +%s)
done_=
deadline=$(($(date +%s) + 300))
while [ "$(date +%s)" -lt "$deadline" ]; do
	if [ -z "$(timeout 5 squeue -h -j "$job" 2>/dev/null)" ]; then
		done_=1
		break
	fi
	sleep 0.1
done
[ -n "$done_" ] || fail "the array job did not finish: $(squeue -j "$job" 2>&1 | tr '\n' ' ')"
for t in 0 1 2 3; do
	grep -q "shard $t/4 from slurm" "$T"/out-"${job}"_$t.txt ||
		fail "task $t did not report its shard: $(cat "$T"/out-"${job}"_$t.txt 2>&1 | tail -n 3)"
done
grep -q "already complete" "$T/out-${job}_1.txt" && grep -q "shard 1/4 from slurm: 2 samples made, 1 already" "$T/out-${job}_1.txt" ||
	fail "task 1's second run did not resume: $(tail -n 2 "$T/out-${job}_1.txt")"

# 4. merged manifest = the local one; verify
"$POLARCAM" dataset merge "$T/slurm" >"$T/merge.log" 2>&1 || fail "merge: $(cat "$T/merge.log")"
cmp "$T/local/manifest.jsonl" "$T/slurm/manifest.jsonl" ||
	fail "the merged manifest differs from the local run's"
"$POLARCAM" dataset verify "$T/slurm" >"$T/verify.log" 2>&1 || fail "verify: $(cat "$T/verify.log")"
end=$(date +%s)
echo "slurm: phases: cluster up $((up - start)) s, array until the requeue $((requeued - up)) s, requeue to merged $((end - requeued)) s" >&2
echo "slurm: 4-task array of polarcam dataset ($N samples, task 1 killed by requeue after 1 of its 3 samples and resumed): merged manifest identical to the local run's; cluster up in $((up - start)) s, test $((end - start)) s"
