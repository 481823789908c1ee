#!/usr/bin/env bash
# Submits make targets to Slurm as array jobs (make ensemble / make params
# EXECUTOR=slurm; docs/ensemble.md, docs/params.md): each line of TARGETS_FILE
# is "WAVE TARGET MINUTES"; the targets of a wave run as one array job, one
# task per target, each `make TARGET` on one CPU (the same rules as the local
# executor) with a time limit of the wave's largest MINUTES (the plan's cost
# estimate, with a margin) and --requeue: a task whose node is lost is
# requeued and, rerun, resumes from its checkpoint; one that overruns its
# limit ends. A wave starts when the previous one has succeeded; FINAL (the
# aggregate, the report) runs last. A failed task cancels what depends on it.
#
#   submit_targets.sh LOG_DIR WAIT FINAL TARGETS_FILE [MAKE_VARIABLE=VALUE ...]
#
# WAIT = 1: wait, at most SLURM_WAIT_MINUTES (default: what the jobs may
# take at their limits on the partition's CPUs), then check that every task
# and FINAL ran and succeeded (each writes its exit status into
# LOG_DIR/status/; Slurm's own exit code says nothing of a job cancelled
# before it ran): exit 0 only then, else 1 naming each failed, unfinished or
# never-run target and its log. A submission into LOG_DIR is refused while
# jobs of an earlier one there are still queued or running (LOG_DIR/jobs).
# Logs: LOG_DIR/wave<w>_<k>.log, final.log. The jobs run make in this
# directory: the nodes must see it (a shared file system) and have the
# build's dependencies. Extra sbatch options: SBATCH_OPTIONS (e.g.
# "--partition=short"); FINAL_MINUTES: FINAL's limit (default 30).
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 LOG_DIR WAIT FINAL TARGETS_FILE [VAR=VALUE ...]" >&2; exit 2; }
L=$1; WAIT=$2; FINAL=$3; TARGETS=$4; shift 4
FINAL_MINUTES=${FINAL_MINUTES:-30}
for c in sbatch squeue sinfo; do
  command -v $c >/dev/null || { echo "submit_targets: $c not found: is this a Slurm login node?" >&2; exit 2; }
done
[ -s "$TARGETS" ] || { echo "submit_targets: $TARGETS: no targets" >&2; exit 2; }
for v in "$@"; do  # make's variables, passed on to every task
  [[ $v =~ ^[A-Za-z_][A-Za-z0-9_]*= ]] || { echo "submit_targets: '$v': expected VAR=VALUE (a make variable)" >&2; exit 2; }
done
bad=$(awk 'NF != 3 || $1 !~ /^[0-9]+$/ || $3 !~ /^[1-9][0-9]*$/ {print NR": "$0; exit}' "$TARGETS")
[ -z "$bad" ] || { echo "submit_targets: $TARGETS:$bad: expected 'WAVE TARGET MINUTES' (integers > 0)" >&2; exit 2; }
mkdir -p "$L/status"
# an earlier submission's jobs still listed: refused (two would write the same files)
if [ -s "$L/jobs" ]; then
  listed=$(squeue -h -j "$(paste -sd, "$L/jobs")" -o "%i %T" 2>/dev/null || true)
  if [ -n "$listed" ]; then
    echo "submit_targets: jobs of an earlier submission into $L are still queued or running:" >&2
    printf '  %s\n' "$listed" >&2
    echo "  wait for them, or cancel them first: scancel $(paste -sd' ' "$L/jobs")" >&2
    exit 2
  fi
fi
: >"$L/jobs"
rm -f "$L"/status/*.status  # (this script's own files, from an earlier submission)
vars=""  # (printf of no arguments would give one empty word: make read it as a file name)
[ $# -eq 0 ] || vars=$(printf ' %q' "$@")
# the command of a task: make TARGET, its exit status written where this script looks for it
status_of() { echo "rc=\$?; echo \$rc > $(printf %q "$L/status")/$1.status; exit \$rc"; }
cpus=$(sinfo -h -o %C | awk -F/ '{n += $4} END {print (n > 0 ? n : 1)}')  # the partition's CPUs
budget=$FINAL_MINUTES  # minutes the whole submission may take at its limits
dependency=()
for wave in $(awk '{print $1}' "$TARGETS" | sort -n | uniq); do
  list="$L/wave$wave.txt"
  awk -v w="$wave" '$1 == w {print $2}' "$TARGETS" >"$list"
  n=$(wc -l <"$list")
  minutes=$(awk -v w="$wave" '$1 == w && $3 > m {m = $3} END {print m}' "$TARGETS")
  budget=$((budget + (n + cpus - 1) / cpus * minutes))
  # shellcheck disable=SC2086
  job=$(sbatch --parsable --job-name="dem2d-wave$wave" --array=0-$((n - 1)) --cpus-per-task=1 --chdir="$PWD" \
    --time="$minutes" --requeue --output="$L/wave${wave}_%a.log" --open-mode=append "${dependency[@]}" \
    ${SBATCH_OPTIONS:-} \
    --wrap "make --no-print-directory \"\$(sed -n \"\$((SLURM_ARRAY_TASK_ID + 1))p\" $(printf %q "$list"))\"$vars; $(status_of "wave${wave}_\$SLURM_ARRAY_TASK_ID")")
  job=${job%%;*}
  echo "$job" >>"$L/jobs"
  echo "submit_targets: wave $wave: $n targets, array job $job (limit $minutes min a task); logs in $L/"
  dependency=(--dependency=afterok:"$job" --kill-on-invalid-dep=yes)
done
# shellcheck disable=SC2086
final=$(sbatch --parsable --job-name=dem2d-final "${dependency[@]}" --cpus-per-task=1 --time="$FINAL_MINUTES" \
  --requeue --chdir="$PWD" --output="$L/final.log" --open-mode=append ${SBATCH_OPTIONS:-} \
  --wrap "make --no-print-directory \"$FINAL\"$vars; $(status_of final)")
final=${final%%;*}
echo "$final" >>"$L/jobs"
[ "$WAIT" = 1 ] || { echo "submit_targets: $FINAL: job $final submitted"; exit 0; }
# wait, with a bound: until no job of this submission is listed, or the budget is spent
limit=${SLURM_WAIT_MINUTES:-$budget}
wait_s=$( [[ $limit =~ ^([0-9]{1,6}(\.[0-9]*)?|\.[0-9]+)$ ]] && awk -v m="$limit" 'BEGIN { printf "%d", m * 60 + 0.5 }' || echo 0)
[ "$wait_s" -gt 0 ] || { echo "submit_targets: SLURM_WAIT_MINUTES=$limit: expected minutes > 0 (at least 1 s)" >&2; exit 2; }
echo "submit_targets: waiting for job $final and the waves, at most $limit min"
deadline=$(($(date +%s) + wait_s))
jobs=$(paste -sd, "$L/jobs")
# the jobs still listed, into `listed`; returns 1 when the controller does not
# answer (squeue fails for another reason than jobs it no longer knows: those
# ended long enough ago to be purged, which is no different from unlisted)
poll_jobs() {
  local err
  if listed=$(squeue -h -j "$jobs" -o "%i %T %r" 2>"$L/squeue.err"); then return 0; fi
  err=$(head -c 300 "$L/squeue.err")
  if grep -qi "invalid job id" <<<"$err"; then listed=""; return 0; fi
  listed=$err
  return 1
}
silent_since=""  # when the controller stopped answering (empty: it answers)
while :; do
  if poll_jobs; then
    [ -z "$silent_since" ] || echo "submit_targets: the controller answers again"
    silent_since=""
    [ -n "$listed" ] || break
  elif [ -z "$silent_since" ]; then
    silent_since=$(date '+%H:%M:%S')
    echo "submit_targets: squeue fails ($listed): is slurmctld down? waiting for it to answer" >&2
  fi
  if [ "$(date +%s)" -ge "$deadline" ]; then
    if [ -n "$silent_since" ]; then
      echo "submit_targets: the controller has not answered since $silent_since, and $limit min have passed:" \
        "what the jobs are doing is unknown" >&2
    else
      echo "submit_targets: still queued or running after $limit min (a lost node? a limit too tight?):" >&2
      printf '  %s\n' "$listed" >&2
    fi
    break
  fi
  sleep "${SLURM_POLL_SECONDS:-5}"
done
# every task and the final job: ran, and exited 0
failed=()
for wave in $(awk '{print $1}' "$TARGETS" | sort -n | uniq); do
  k=0
  while read -r target; do
    st="$L/status/wave${wave}_$k.status"
    if [ ! -s "$st" ] && [ -n "$silent_since" ]; then
      failed+=("$target: not finished when the controller stopped answering (it may still be running): $L/wave${wave}_$k.log")
    elif [ ! -s "$st" ]; then failed+=("$target: never ran or did not finish (cancelled, over its time limit, or its node was lost): $L/wave${wave}_$k.log")
    elif [ "$(cat "$st")" != 0 ]; then failed+=("$target: failed (exit $(cat "$st")): $L/wave${wave}_$k.log"); fi
    k=$((k + 1))
  done <"$L/wave$wave.txt"
done
if [ ! -s "$L/status/final.status" ] && [ -n "$silent_since" ]; then
  failed+=("$FINAL: not finished when the controller stopped answering (it may still run): $L/final.log")
elif [ ! -s "$L/status/final.status" ]; then failed+=("$FINAL: never ran (a target it needs failed or did not finish)")
elif [ "$(cat "$L/status/final.status")" != 0 ]; then failed+=("$FINAL: failed: $L/final.log"); fi
if [ ${#failed[@]} -gt 0 ]; then
  echo "submit_targets: ${#failed[@]} of the jobs' targets did not succeed:" >&2
  printf '  %s\n' "${failed[@]}" >&2
  listed=$(squeue -h -j "$jobs" -o %i 2>/dev/null | paste -sd' ' || true)
  [ -z "$listed" ] || echo "  still listed (a resubmission is refused until they end): scancel $listed" >&2
  exit 1
fi
echo "submit_targets: $FINAL: job $final, done (every target succeeded)"
