#!/usr/bin/env bash
# Submits an ensemble to Slurm (make ensemble EXECUTOR=slurm; docs/ensemble.md):
# the members as one array job, one task per member, each running the same
# make target as the local executor (ENSEMBLE/member_NNN/metrics.json) on
# one CPU within MINUTES (its cost estimate with a margin:
# member_minutes.py), and the aggregate (ENSEMBLE/table.md) as a job that
# runs when all members have succeeded (it is cancelled if one fails):
# submit_targets.sh.
#
#   submit_ensemble.sh ENSEMBLE_DIR MEMBERS MINUTES WAIT [MAKE_VARIABLE=VALUE ...]
#
# WAIT = 1: wait (bounded) and exit 0 only if every member and the
# aggregate succeeded. Logs: ENSEMBLE_DIR/slurm/wave1_<k>.log (member k),
# final.log (the aggregate).
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 ENSEMBLE_DIR MEMBERS MINUTES WAIT [VAR=VALUE ...]" >&2; exit 2; }
E=$1; K=$2; MINUTES=$3; WAIT=$4; shift 4
mkdir -p "$E/slurm"
for ((k = 0; k < K; k++)); do printf '1 %s/member_%03d/metrics.json %s\n' "$E" "$k" "$MINUTES"; done >"$E/slurm/targets.txt"
exec "$(dirname "$0")/submit_targets.sh" "$E/slurm" "$WAIT" "$E/table.md" "$E/slurm/targets.txt" "$@"
