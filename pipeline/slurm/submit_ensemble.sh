#!/usr/bin/env bash
# Submits an ensemble to Slurm (make ensemble EXECUTOR=slurm; docs/ensemble.md):
# the members as one array job, one task per member, each running the same
# make target as the local executor (ENSEMBLE/member_NNN/metrics.json) on
# one CPU, and the aggregate (ENSEMBLE/table.md) as a job that runs when all
# members have succeeded (it is cancelled if one fails): submit_targets.sh.
#
#   submit_ensemble.sh ENSEMBLE_DIR MEMBERS WAIT [MAKE_VARIABLE=VALUE ...]
#
# WAIT = 1: wait for the aggregate job and exit with its status. Logs:
# ENSEMBLE_DIR/slurm/wave1_<k>.log (member k), final.log (the aggregate).
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 ENSEMBLE_DIR MEMBERS WAIT [VAR=VALUE ...]" >&2; exit 2; }
E=$1; K=$2; WAIT=$3; shift 3
mkdir -p "$E/slurm"
for ((k = 0; k < K; k++)); do printf '1 %s/member_%03d/metrics.json\n' "$E" "$k"; done >"$E/slurm/targets.txt"
exec "$(dirname "$0")/submit_targets.sh" "$E/slurm" "$WAIT" "$E/table.md" "$E/slurm/targets.txt" "$@"
