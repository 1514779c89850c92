# Sourced by the command-line tests. A run's progress.csv without its clock columns, Time,
# MsPerPlan and CpuTime, found by name in its header (any family): what two runs of one seed and
# config share row for row, however they were stopped, resumed or scheduled.
# Usage: deterministic_rows PROGRESS_CSV
deterministic_rows() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) drop[i] = ($i == "Time" || $i == "MsPerPlan" ||
                                                          $i == "CpuTime") }
           { out = ""; for (i = 1; i <= NF; ++i) if (!drop[i]) out = out $i ","; print out }' "$1"
}

# Trains CUT_DIR with the train arguments given, checkpointing after every step, kills it with
# SIGKILL at its first checkpoint in the middle of an episode, resumes it, and fails (exit 1,
# naming the difference) unless it was killed there and its rows are WHOLE_DIR's.
# Usage: killed_mid_episode_resumes CMBRL WHOLE_DIR CUT_DIR TRAIN_ARGUMENTS...
killed_mid_episode_resumes() {
  local cmbrl=$1 whole=$2 cut=$3
  shift 3
  "$cmbrl" train "$@" --out "$cut" --checkpoint-seconds 0 > /dev/null 2>&1 &
  local pid=$! seen=0 status=0
  for _ in $(seq 1 3000); do
    [ -f "$cut/checkpoint/episode.json" ] && { seen=1; break; }
    sleep 0.02
  done
  kill -9 $pid 2> /dev/null || true
  wait $pid 2> /dev/null || status=$?
  # A run that finished, failed or never checkpointed mid-episode resumes nothing: not a pass.
  [ "$seen" = 1 ] || { echo "no checkpoint inside an episode within 60 s"; exit 1; }
  [ "$status" = 137 ] || { echo "the run was not killed mid-way (exit status $status)"; exit 1; }
  # A resume that fails says why (under set -e it would end the test without a word).
  if ! "$cmbrl" train --resume "$cut" > "$cut.resume.log" 2>&1; then
    echo "the resume failed:"; cat "$cut.resume.log"; ls -la "$cut/checkpoint"; exit 1
  fi
  if ! diff <(deterministic_rows "$whole/progress.csv") <(deterministic_rows "$cut/progress.csv"); then
    echo "resumed rows differ"; exit 1
  fi
}
