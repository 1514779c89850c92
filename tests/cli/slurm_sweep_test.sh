#!/usr/bin/env bash
# A sweep through a real Slurm: a single-node cluster on localhost (munged, slurmctld and slurmd,
# all configured inside WORK_DIR and stopped at the end), a tiny sweep submitted to it with
# `cmbrl sweep --engine slurm --wait`, one task requeued and one cancelled while they train, and
# the sweep submitted again; then a task warned that its time limit is near. Every run must
# finish with the rows of the same sweep run locally (the clock columns Time, MsPerPlan and
# CpuTime aside), and the interrupted runs must have been resumed, not restarted. The sweep's
# folder has spaces and non-ASCII letters in its name. Exits 77 (skipped), saying why, only where
# the daemons cannot start.
# Usage: slurm_sweep_test.sh CMBRL CONFIG WORK_DIR
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/progress_rows.sh"
cmbrl=$1 config=$2 work=$3
export PATH="$PATH:/usr/sbin:/sbin"
skip() {
  echo "SKIPPED: $*"
  exit 77
}
for program in munged slurmctld slurmd sbatch squeue scontrol scancel sinfo; do
  command -v "$program" > /dev/null ||
    skip "'$program' is not installed (scripts/install-deps.sh installs slurm-wlm and munge)"
done
rm -rf "$work" && mkdir -p "$work/configs" "$work/munge" "$work/state" "$work/spool"
work=$(cd "$work" && pwd)
for planner in rce random; do
  sed "s/^planner: .*/planner: $planner/" "$config" > "$work/configs/pointgoal1-$planner.yaml"
done

# --- The cluster: one node, this machine, on two free ports. ---
free_port() {
  local port
  while :; do
    port=$((20000 + RANDOM % 40000))
    (exec 3<> "/dev/tcp/127.0.0.1/$port") 2> /dev/null || { echo "$port"; return; }
  done
}
host=$(hostname -s)
user=$(id -un)
stop_cluster() {
  if [ "${SLURM_CONF:-}" = "$work/slurm.conf" ]; then  # never another cluster's jobs
    scancel --quiet --jobname=cmbrl-sweep 2> /dev/null || true
  fi
  for daemon in slurmd slurmctld; do
    [ -f "$work/$daemon.pid" ] && kill "$(cat "$work/$daemon.pid")" 2> /dev/null || true
  done
  munged --stop --socket="$work/munge/munge.sock" > /dev/null 2>&1 || true
}
trap stop_cluster EXIT
chmod 700 "$work/munge"
head -c 1024 /dev/urandom > "$work/munge/munge.key" && chmod 400 "$work/munge/munge.key"
munged --force --socket="$work/munge/munge.sock" --key-file="$work/munge/munge.key" \
  --log-file="$work/munge/munged.log" --pid-file="$work/munge/munged.pid" \
  --seed-file="$work/munge/munged.seed" 2> "$work/munged.err" ||
  skip "munged did not start: $(tail -n 3 "$work/munged.err" "$work/munge/munged.log" 2> /dev/null)"
cat > "$work/slurm.conf" << EOF
ClusterName=cmbrl-test
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
slurmctld -f "$SLURM_CONF" 2> "$work/slurmctld.err" ||
  skip "slurmctld did not start: $(tail -n 3 "$work/slurmctld.err" "$work/slurmctld.log" 2> /dev/null)"
slurmd -f "$SLURM_CONF" 2> "$work/slurmd.err" ||
  skip "slurmd did not start: $(tail -n 3 "$work/slurmd.err" "$work/slurmd.log" 2> /dev/null)"
for _ in $(seq 60); do
  [ "$(sinfo --noheader --format=%T 2> /dev/null)" = idle ] && break
  sleep 0.5
done
[ "$(sinfo --noheader --format=%T 2> /dev/null)" = idle ] ||
  skip "the Slurm node never became idle: $(tail -n 3 "$work/slurmd.log" "$work/slurmctld.log")"

# --- The same sweep here and through Slurm. ---
sweep=(sweep --tasks PointGoal1 --planners rce random --seeds 0 1 --config-dir "$work/configs"
       --steps 2000)
"$cmbrl" "${sweep[@]}" --jobs 2 --out "$work/local" > /dev/null
# The Slurm sweep's folder has spaces and non-ASCII letters: every path in its script is quoted.
out="$work/slurm sweep é ü"
slurm=("${sweep[@]}" --out "$out" --engine slurm --wait --poll 0.5
       --sbatch=--cpus-per-task=1)
"$cmbrl" "${slurm[@]}" > "$work/submit-1.log" 2>&1 &
submitter=$!
rows() { local file="$out/runs/$1/progress.csv"; [ -f "$file" ] && wc -l < "$file" || echo 0; }
task_of() {
  sed -n "s/.*\"run\":\"$1\",\"status\":\"submitted\".*\"job\":\"\([0-9_]*\)\".*/\1/p" \
    "$work/submit-1.log"
}
wait_for_rows() {
  for _ in $(seq 1200); do
    [ "$(rows "$1")" -ge 3 ] && return
    kill -0 "$submitter" 2> /dev/null || break
    sleep 0.1
  done
  echo "FAILED: $1 never wrote two rows through Slurm"; cat "$work/submit-1.log"; exit 1
}
# Requeue the first seed of RCE mid-run. Slurm holds a requeued task back for about two minutes;
# release it sooner, but not within the second its old credential was revoked (a task started
# then fails with "Job credential revoked"), and late enough for the sweep to see it wait.
wait_for_rows pointgoal1-rce-s0
requeued=$(task_of pointgoal1-rce-s0)
scontrol requeue "$requeued"
for _ in $(seq 300); do
  if [ "$(squeue --noheader --jobs="$requeued" --format=%T 2> /dev/null)" = PENDING ]; then
    scontrol update JobId="$requeued" StartTime=now+5 && break
  fi
  sleep 0.1
done
# ... and cancel the second while it trains.
wait_for_rows pointgoal1-rce-s1
cancelled=$(task_of pointgoal1-rce-s1)
scancel "$cancelled"
if wait "$submitter"; then
  echo "FAILED: the sweep said every run finished though $cancelled was cancelled"
  cat "$work/submit-1.log"; exit 1
fi
grep -q '"run":"pointgoal1-rce-s1","status":"failed".*"state":"CANCELLED"' "$work/submit-1.log" ||
  { echo "FAILED: the cancelled run was not reported failed"; cat "$work/submit-1.log"; exit 1; }
# The cancellation's SIGTERM reached the run, which checkpointed and stopped (not killed with
# its script).
grep -q "SIGTERM stopped the run" "$out/logs/slurm-${cancelled#*_}.log" ||
  { echo "FAILED: the cancelled run did not stop at a checkpoint"; exit 1; }
grep -q '"run":"pointgoal1-rce-s0","status":"finished"' "$work/submit-1.log" ||
  { echo "FAILED: the requeued run did not finish"; cat "$work/submit-1.log"; exit 1; }
grep -q '"run":"pointgoal1-rce-s0","status":"requeued"' "$work/submit-1.log" ||
  { echo "FAILED: the requeue was not reported"; cat "$work/submit-1.log"; exit 1; }
grep -q 'did not finish: pointgoal1-rce-s1; .*run the same sweep again' "$work/submit-1.log" ||
  { echo "FAILED: the sweep's error does not name the run and what to do"; exit 1; }
# Submitting again sends only the unfinished run, which resumes.
"$cmbrl" "${slurm[@]}" > "$work/submit-2.log"
grep -q '"already_finished":3,"submitted":1,.*"finished_now":1,"failed":\[\]' \
  "$work/submit-2.log" || { echo "FAILED: the second submission"; cat "$work/submit-2.log"; exit 1; }

runs=0
for whole in "$work"/local/runs/*/progress.csv; do
  name=$(basename "$(dirname "$whole")")
  through_slurm="$out/runs/$name/progress.csv"
  if ! diff <(deterministic_rows "$whole") <(deterministic_rows "$through_slurm"); then
    echo "FAILED: $name through Slurm differs from the local sweep's"
    exit 1
  fi
  runs=$((runs + 1))
done
for name in pointgoal1-rce-s0 pointgoal1-rce-s1; do
  sessions=$(wc -l < "$out/runs/$name/sessions.jsonl")
  [ "$sessions" -ge 2 ] || { echo "FAILED: $name was not resumed ($sessions session)"; exit 1; }
done
grep -q 'DUE TO JOB REQUEUE' "$out/logs/slurm-0.log" ||
  { echo "FAILED: the requeued task's log lost its first part"; exit 1; }
# A task warned of its time limit (Slurm's USR1 to the script, which --signal in slurm.sh asks
# for; sent here by hand) stops its run at a checkpoint and requeues itself; the run goes on to
# the local sweep's rows.
limit=(sweep --tasks PointGoal1 --planners rce --seeds 0 --config-dir "$work/configs" --steps 2000
       --out "$work/limit" --engine slurm --wait --poll 0.5 --sbatch=--cpus-per-task=1)
"$cmbrl" "${limit[@]}" > "$work/limit.log" 2>&1 &
limiter=$!
limit_rows="$work/limit/runs/pointgoal1-rce-s0/progress.csv"
for _ in $(seq 1200); do
  [ -f "$limit_rows" ] && [ "$(wc -l < "$limit_rows")" -ge 3 ] && break
  sleep 0.1
done
warned=$(sed -n 's/.*"status":"submitted".*"job":"\([0-9_]*\)".*/\1/p' "$work/limit.log")
[ -n "$warned" ] || { echo "FAILED: the time-limit sweep was not submitted"; cat "$work/limit.log"; exit 1; }
scancel --batch --signal=USR1 "$warned"
for _ in $(seq 600); do
  if [ "$(squeue --noheader --jobs="$warned" --format=%T 2> /dev/null)" = PENDING ]; then
    scontrol update JobId="$warned" StartTime=now+5 && break
  fi
  sleep 0.1
done
wait "$limiter" || { echo "FAILED: the warned run did not finish"; cat "$work/limit.log"; exit 1; }
grep -q '"run":"pointgoal1-rce-s0","status":"requeued"' "$work/limit.log" ||
  { echo "FAILED: the warned task did not requeue itself"; cat "$work/limit.log"; exit 1; }
grep -q 'the run stopped at a checkpoint (exit 143) and task 0 requeues itself' \
  "$work/limit/logs/slurm-0.log" ||
  { echo "FAILED: the warned task's log"; cat "$work/limit/logs/slurm-0.log"; exit 1; }
diff <(deterministic_rows "$work/local/runs/pointgoal1-rce-s0/progress.csv") \
  <(deterministic_rows "$limit_rows") ||
  { echo "FAILED: the warned run's rows differ from the local sweep's"; exit 1; }
[ "$(wc -l < "$work/limit/runs/pointgoal1-rce-s0/sessions.jsonl")" -ge 2 ] ||
  { echo "FAILED: the warned run was not resumed"; exit 1; }
# Submitted twice, the second submission follows the first's task instead of sending the run again.
twice=(sweep --tasks PointGoal1 --planners rce --seeds 0 --config-dir "$work/configs" --steps 1000
       --out "$work/twice" --engine slurm --poll 0.5 --sbatch=--cpus-per-task=1)
# The first submission is held, so that its task cannot finish before the second one looks (on a
# busy machine it sometimes did); it is released once the second has found it queued.
"$cmbrl" "${twice[@]}" --sbatch=--hold > "$work/twice-1.log"
"$cmbrl" "${twice[@]}" --wait > "$work/twice-2.log" &
second=$!
for _ in $(seq 600); do
  grep -q '"status":"already queued"' "$work/twice-2.log" 2> /dev/null && break
  sleep 0.1
done
for job in $(squeue --noheader --name=cmbrl-sweep --format=%F | sort -u); do
  scontrol release "$job"
done
wait "$second"
grep -q '"status":"already queued"' "$work/twice-2.log" &&
  grep -q '"submitted":0,"already_queued":1,"finished_now":1' "$work/twice-2.log" ||
  { echo "FAILED: a second submission sent a queued run again"; cat "$work/twice-2.log"; exit 1; }
echo "slurm: $runs runs through a single-node Slurm, one requeued and one cancelled then" \
  "resubmitted, one warned of its time limit, rows identical to the local sweep"
