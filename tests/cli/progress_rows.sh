# Sourced by the command-line tests. A run's progress.csv without its wall-clock columns, Time (7)
# and MsPerPlan (12): what two runs of one seed and config share row for row, however they were
# stopped, resumed or scheduled.
# Usage: deterministic_rows PROGRESS_CSV
deterministic_rows() { cut -d, -f1-6,8-11,13- "$1"; }
