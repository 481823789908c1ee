#!/usr/bin/env bash
# Submits an ensemble to Slurm (make ensemble EXECUTOR=slurm; docs/ensemble.md):
# the members as one array job, one task per member, each running the same
# make target as the local executor (ENSEMBLE/member_NNN/metrics.json) on
# one CPU, and the aggregate (ENSEMBLE/table.md) as a job that runs when all
# members have succeeded (it is cancelled if one fails).
#
#   submit_ensemble.sh ENSEMBLE_DIR MEMBERS WAIT [MAKE_VARIABLE=VALUE ...]
#
# WAIT = 1: wait for the aggregate job and exit with its status. Logs:
# ENSEMBLE_DIR/slurm/member_<k>.log, aggregate.log. The jobs run make in
# this directory: the nodes must see it (a shared file system) and have the
# build's dependencies. Extra sbatch options: SBATCH_OPTIONS (e.g.
# "--partition=short --time=04:00:00").
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 ENSEMBLE_DIR MEMBERS WAIT [VAR=VALUE ...]" >&2; exit 2; }
E=$1; K=$2; WAIT=$3; shift 3
command -v sbatch >/dev/null || { echo "submit_ensemble: sbatch not found: is this a Slurm login node?" >&2; exit 2; }
mkdir -p "$E/slurm"
vars=$(printf ' %q' "$@")
# shellcheck disable=SC2086
members=$(sbatch --parsable --job-name=dem2d-members --array=0-$((K - 1)) --cpus-per-task=1 --chdir="$PWD" \
  --output="$E/slurm/member_%a.log" ${SBATCH_OPTIONS:-} \
  --wrap "make --no-print-directory \"$E/member_\$(printf %03d \$SLURM_ARRAY_TASK_ID)/metrics.json\"$vars")
members=${members%%;*}
wait_opt=(); [ "$WAIT" = 1 ] && wait_opt=(--wait)
echo "submit_ensemble: $K members: array job $members; logs in $E/slurm/"
# shellcheck disable=SC2086
aggregate=$(sbatch --parsable "${wait_opt[@]}" --job-name=dem2d-aggregate --dependency=afterok:"$members" \
  --kill-on-invalid-dep=yes --cpus-per-task=1 --chdir="$PWD" --output="$E/slurm/aggregate.log" ${SBATCH_OPTIONS:-} \
  --wrap "make --no-print-directory \"$E/table.md\"$vars") || {
  echo "submit_ensemble: the aggregate job failed or was cancelled (a member failed?): see $E/slurm/*.log" >&2
  exit 1
}
echo "submit_ensemble: aggregate: job ${aggregate%%;*}$([ "$WAIT" = 1 ] && echo ", done: $E/table.md")"
