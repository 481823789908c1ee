#!/usr/bin/env bash
# Submits make targets to Slurm as array jobs (make ensemble / make params
# EXECUTOR=slurm; docs/ensemble.md, docs/params.md): each line of TARGETS_FILE
# is "WAVE TARGET"; the targets of a wave run as one array job, one task per
# target, each `make TARGET` on one CPU (the same rules as the local
# executor); a wave starts when the previous one has succeeded; FINAL (the
# aggregate, the report) runs last. A failed task cancels what depends on it.
#
#   submit_targets.sh LOG_DIR WAIT FINAL TARGETS_FILE [MAKE_VARIABLE=VALUE ...]
#
# WAIT = 1: wait for FINAL, then check that every task and FINAL ran and
# succeeded (each writes its exit status into LOG_DIR/status/; Slurm's own
# exit code says nothing of a job cancelled before it ran): exit 0 only then,
# else 1 naming each failed or never-run target and its log. Logs:
# LOG_DIR/wave<w>_<k>.log, final.log. The jobs run make in this directory: the nodes must see it (a
# shared file system) and have the build's dependencies. Extra sbatch options:
# SBATCH_OPTIONS (e.g. "--partition=short --time=04:00:00").
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 LOG_DIR WAIT FINAL TARGETS_FILE [VAR=VALUE ...]" >&2; exit 2; }
L=$1; WAIT=$2; FINAL=$3; TARGETS=$4; shift 4
command -v sbatch >/dev/null || { echo "submit_targets: sbatch not found: is this a Slurm login node?" >&2; exit 2; }
[ -s "$TARGETS" ] || { echo "submit_targets: $TARGETS: no targets" >&2; exit 2; }
mkdir -p "$L/status"
rm -f "$L"/status/*.status  # (this script's own files, from an earlier submission)
vars=$(printf ' %q' "$@")
# the command of a task: make TARGET, its exit status written where this script looks for it
status_of() { echo "rc=\$?; echo \$rc > $(printf %q "$L/status")/$1.status; exit \$rc"; }
dependency=()
for wave in $(awk '{print $1}' "$TARGETS" | sort -n | uniq); do
  list="$L/wave$wave.txt"
  awk -v w="$wave" '$1 == w {print $2}' "$TARGETS" >"$list"
  n=$(wc -l <"$list")
  # shellcheck disable=SC2086
  job=$(sbatch --parsable --job-name="dem2d-wave$wave" --array=0-$((n - 1)) --cpus-per-task=1 --chdir="$PWD" \
    --output="$L/wave${wave}_%a.log" "${dependency[@]}" ${SBATCH_OPTIONS:-} \
    --wrap "make --no-print-directory \"\$(sed -n \"\$((SLURM_ARRAY_TASK_ID + 1))p\" $(printf %q "$list"))\"$vars; $(status_of "wave${wave}_\$SLURM_ARRAY_TASK_ID")")
  job=${job%%;*}
  echo "submit_targets: wave $wave: $n targets, array job $job; logs in $L/"
  dependency=(--dependency=afterok:"$job" --kill-on-invalid-dep=yes)
done
wait_opt=(); [ "$WAIT" = 1 ] && wait_opt=(--wait)
# shellcheck disable=SC2086
final=$(sbatch --parsable "${wait_opt[@]}" --job-name=dem2d-final "${dependency[@]}" --cpus-per-task=1 \
  --chdir="$PWD" --output="$L/final.log" ${SBATCH_OPTIONS:-} \
  --wrap "make --no-print-directory \"$FINAL\"$vars; $(status_of final)") || true
[ "$WAIT" = 1 ] || { echo "submit_targets: $FINAL: job ${final%%;*} submitted"; exit 0; }
# every task and the final job: ran, and exited 0
failed=()
for wave in $(awk '{print $1}' "$TARGETS" | sort -n | uniq); do
  k=0
  while read -r target; do
    st="$L/status/wave${wave}_$k.status"
    if [ ! -s "$st" ]; then failed+=("$target: never ran or did not finish (cancelled, or its node was lost): $L/wave${wave}_$k.log")
    elif [ "$(cat "$st")" != 0 ]; then failed+=("$target: failed (exit $(cat "$st")): $L/wave${wave}_$k.log"); fi
    k=$((k + 1))
  done <"$L/wave$wave.txt"
done
if [ ! -s "$L/status/final.status" ]; then failed+=("$FINAL: never ran (a target it needs failed)")
elif [ "$(cat "$L/status/final.status")" != 0 ]; then failed+=("$FINAL: failed: $L/final.log"); fi
if [ ${#failed[@]} -gt 0 ]; then
  echo "submit_targets: ${#failed[@]} of the jobs' targets did not succeed:" >&2
  printf '  %s\n' "${failed[@]}" >&2
  exit 1
fi
echo "submit_targets: $FINAL: job ${final%%;*}, done (every target succeeded)"
