#!/usr/bin/env bash
# make test-cluster: the Slurm executor against a real Slurm. Installs
# Debian's munge and slurm-wlm if missing (as root), starts a one-node
# cluster in a temporary folder (pipeline/slurm/local_cluster.sh), runs a
# 2-member ensemble of the quick scene through it (make ensemble
# EXECUTOR=slurm), checks that an ensemble with a failing member, and one
# whose node is killed under it, end non-zero naming the member, and stops
# the daemons it started; then that every member's run files and the
# aggregate are those of the same ensemble made with the local executor
# (results/quick/ensemble, the pipeline test's, made here when it is not up
# to date).
#   tests/slurm_test.sh                  both parts, in a temporary folder
#   tests/slurm_test.sh --cluster DIR    the cluster part only, its ensemble left in DIR (ctest `cluster`)
#   tests/slurm_test.sh --compare DIR    the comparison only, with the ensemble in DIR (ctest `cluster_same_as_local`)
# The two ctests let the cluster part run beside the pipeline test. Exit 0:
# passed; 1: failed; 77: skipped (said loudly; make test counts it a failure).
set -uo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-/usr/bin/python3}
MEMBERS=2
LOCAL=results/quick
export SLURM_POLL_SECONDS=1  # the submissions' wait polls squeue every second (default 5)
MODE=both
case "${1:-}" in
  --cluster | --compare) MODE=${1#--}; KEEP=${2:?"$1 needs a folder"} ;;
  "") ;;
  *) echo "usage: tests/slurm_test.sh [--cluster DIR | --compare DIR]" >&2; exit 2 ;;
esac
if [ "$MODE" = both ]; then
  WORK=$(mktemp -d /tmp/dem2d_slurm_test.XXXXXX)
  cleanup() { pipeline/slurm/local_cluster.sh stop "$WORK/cluster" >/dev/null 2>&1; rm -rf "$WORK"; }
else
  # a folder this script made (its mark inside), emptied of what an earlier run left
  WORK=$KEEP
  if [ -e "$WORK" ] && [ ! -e "$WORK/.slurm_test" ]; then
    echo "slurm_test: $WORK exists and was not made by this test: not touched" >&2; exit 2
  fi
  [ "$MODE" = cluster ] && rm -rf "$WORK"
  mkdir -p "$WORK" && touch "$WORK/.slurm_test"
  cleanup() { pipeline/slurm/local_cluster.sh stop "$WORK/cluster" >/dev/null 2>&1; }
fi
trap cleanup EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
skip() {
  echo "************************************************************************"
  echo "SKIPPED: the Slurm executor was NOT tested: $*"
  echo "************************************************************************"
  exit 77
}

cluster_part() {
  if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null; then
    [ "$(id -u)" -eq 0 ] || skip "munge and slurm-wlm are not installed and this is not root (apt-get install munge slurm-wlm)"
    echo "slurm_test: installing munge and slurm-wlm"
    { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends munge slurm-wlm; } \
      >"$WORK/apt.log" 2>&1 || skip "installing munge and slurm-wlm failed: $(tail -3 "$WORK/apt.log")"
  fi
  [ "$(id -u)" -eq 0 ] || skip "the one-node cluster needs root (slurmd)"

  t_start=$(date +%s.%N)
  pipeline/slurm/local_cluster.sh start "$WORK/cluster" >"$WORK/cluster.log" 2>&1 ||
    { cat "$WORK/cluster.log"; fail "the one-node cluster did not start"; exit 1; }
  export SLURM_CONF=$WORK/cluster/slurm.conf
  # a second start in the same folder is refused naming the running daemon (it left a munged after stop)
  out=$(pipeline/slurm/local_cluster.sh start "$WORK/cluster" 2>&1) && fail "a second start in one folder was accepted"
  grep -q "already has a running cluster (munged, pid" <<<"$out" || fail "a second start said: $out"
  t2=$(date +%s.%N)
  make --no-print-directory ensemble PRESET=quick MEMBERS=$MEMBERS RESULTS="$WORK/slurm" EXECUTOR=slurm SLURM_WAIT=1 \
    >"$WORK/slurm.log" 2>&1 || fail "Slurm ensemble: $(tail -20 "$WORK/slurm.log"; tail -5 "$WORK"/slurm/ensemble/slurm/*.log)"
  t3=$(date +%s.%N)
  grep -q "array job" "$WORK/slurm.log" || fail "no array job was submitted: $(cat "$WORK/slurm.log")"
  n_tasks=$(ls "$WORK"/slurm/ensemble/slurm/wave1_*.log 2>/dev/null | wc -l)
  [ "$n_tasks" -eq $MEMBERS ] || fail "$n_tasks array task logs, expected $MEMBERS"

  # a member that fails: the submission exits non-zero naming it and its log, never "done"
  t4=$(date +%s.%N)
  mkdir -p "$WORK/failing/ensemble/member_001"
  # member_000 as made above (its times kept: up to date, its task has nothing to do), so that only the
  # failing member costs anything
  cp -a "$WORK/slurm/ensemble/member_000" "$WORK/failing/ensemble/" 2>/dev/null
  printf '[time]\nnot_a_key = 1\n' >"$WORK/failing/ensemble/member_001/member.toml"  # (newer than what makes it)
  make --no-print-directory ensemble PRESET=quick MEMBERS=2 RESULTS="$WORK/failing" EXECUTOR=slurm SLURM_WAIT=1 \
    >"$WORK/failing.log" 2>&1 && fail "an ensemble with a failing member was reported as a success: $(tail -5 "$WORK/failing.log")"
  grep -q "member_001/metrics.json: failed (exit [1-9][0-9]*): .*wave1_1.log" "$WORK/failing.log" ||
    fail "the failing member is not named: $(tail -8 "$WORK/failing.log")"
  grep -q "table.md: never ran" "$WORK/failing.log" || fail "the aggregate's fate is not said: $(tail -8 "$WORK/failing.log")"
  grep -q ", done" "$WORK/failing.log" && fail "a failed ensemble said done"
  # a node lost under a member (slurmd and the member's processes killed): the wait ends at its bound and the
  # submission exits non-zero naming the member; a resubmission while its jobs are still listed is refused
  t5=$(date +%s.%N)
  tree() { echo "$1"; local p; for p in $(pgrep -P "$1"); do tree "$p"; done; }  # a process, then its descendants
  SLURM_WAIT_MINUTES=1 make --no-print-directory ensemble PRESET=quick MEMBERS=1 \
    RESULTS="$WORK/lost" EXECUTOR=slurm SLURM_WAIT=1 >"$WORK/lost.log" 2>&1 &
  lost_make=$!
  for _ in $(seq 120); do [ -e "$WORK/lost/ensemble/member_000/fill/run.log" ] && break; sleep 0.5; done
  [ -e "$WORK/lost/ensemble/member_000/fill/run.log" ] || fail "the member never started: $(tail -5 "$WORK/lost.log")"
  job=$(head -1 "$WORK/lost/ensemble/slurm/jobs" 2>/dev/null)
  kill -9 "$(cat "$WORK/cluster/slurmd.pid")"
  # the member's processes vanish at once, as with their node: each frozen before its children (so that none
  # sees a child die and writes an exit status, as a slower kill, children first, let the task's shell do on a
  # busy machine), listed again until no new one appeared, then killed
  frozen=""
  for _ in 1 2 3 4 5; do
    procs=$(for stepd in $(pgrep -f "^slurmstepd: \[$job[._]"); do tree "$stepd"; done)
    [ -n "$procs" ] && kill -STOP $procs 2>/dev/null
    [ "$procs" = "$frozen" ] && break
    frozen=$procs
  done
  [ -n "$frozen" ] && kill -9 $frozen 2>/dev/null
  t_lost=$(date +%s)
  wait $lost_make && fail "a member on a lost node was reported as a success: $(tail -5 "$WORK/lost.log")"
  echo "slurm_test: the lost node's submission ended $(( $(date +%s) - t_lost )) s after the node was killed"
  grep -q "member_000/metrics.json: never ran or did not finish (.*node was lost).*wave1_0.log" "$WORK/lost.log" ||
    fail "the member on the lost node is not named: $(tail -8 "$WORK/lost.log")"
  make --no-print-directory ensemble PRESET=quick MEMBERS=1 RESULTS="$WORK/lost" EXECUTOR=slurm \
    >"$WORK/again.log" 2>&1 && fail "a resubmission while the old jobs are listed was accepted"
  grep -q "still queued or running" "$WORK/again.log" || fail "the refused resubmission does not say why: $(tail -5 "$WORK/again.log")"
  t6=$(date +%s.%N)
  awk -v c="$t2" -v d="$t3" -v e="$t4" -v f="$t5" -v g="$t6" -v k=$MEMBERS -v s="$t_start" 'BEGIN {
    printf "slurm_test: %d members through Slurm %.1f s (cluster start %.1f s); the failing member %.1f s, the lost node %.1f s\n",
      k, d - c, c - s, f - e, g - f }'
  pipeline/slurm/local_cluster.sh stop "$WORK/cluster" || fail "the daemons did not stop"
  # a restart in the lost node's folder: the controller recovers the lost job, which keeps the node busy;
  # the refusal names the saved state and the way out, and --clear-state starts with it dropped
  out=$(pipeline/slurm/local_cluster.sh start "$WORK/cluster" 2>&1) && fail "a restart with a lost job's state said idle"
  # (the jobs listed: the array's tasks and the aggregate's job, e.g. "8 7_0")
  grep -Eq "recovered jobs ([0-9_]+ )*${job}(_[0-9]+)?( [0-9_]+)* from the state an earlier cluster saved in $WORK/cluster/state: .*--clear-state" \
    <<<"$out" || fail "a restart on a lost job's state said: $out"
  pipeline/slurm/local_cluster.sh start "$WORK/cluster" --clear-state >"$WORK/clear.log" 2>&1 ||
    fail "a restart with --clear-state: $(cat "$WORK/clear.log")"
  [ -z "$(squeue -h -o %i 2>&1)" ] || fail "jobs listed after --clear-state: $(squeue 2>&1)"
  pipeline/slurm/local_cluster.sh stop "$WORK/cluster" || fail "the daemons did not stop"
  for pidf in "$WORK"/cluster/*.pid; do [ -e "$pidf" ] && fail "left running: $pidf"; done
}

compare_part() {
  # the same ensemble with the local executor: the pipeline test's (made here if not up to date)
  t0=$(date +%s.%N)
  make --no-print-directory ensemble PRESET=quick MEMBERS=$MEMBERS RESULTS="$LOCAL" >"$WORK/local.log" 2>&1 ||
    fail "local ensemble: $(tail -20 "$WORK/local.log")"
  t1=$(date +%s.%N)
  for k in $(seq -f %03g 0 $((MEMBERS - 1))); do
    for s in fill pulloff; do
      $PY tests/tools/same_run.py "$LOCAL/ensemble/member_$k/$s/run.h5" "$WORK/slurm/ensemble/member_$k/$s/run.h5" \
        --ignore-attr scene_text >"$WORK/same.log" 2>&1 || fail "member $k $s: Slurm and local differ: $(tail -3 "$WORK/same.log")"
    done
  done
  $PY - "$LOCAL/ensemble/stats.json" "$WORK/slurm/ensemble/stats.json" <<'PYEOF' || fail "the aggregates differ"
import json, sys
timing = ("seconds", "ns_per_", "per_second", "cost.")  # wall-clock measurements differ run to run
a, b = ({k: v for k, v in json.load(open(p))["metrics"].items() if not any(t in k for t in timing)}
        for p in sys.argv[1:])
assert a == b, [k for k in a if a[k] != b.get(k)][:5]
print(f"slurm_test: aggregates equal ({len(a)} metrics)")
PYEOF
  # (the code version each was made with aside: a local ensemble up to date may come from an earlier build)
  code() { sed -E 's/; code: [^ ]+$//' "$1"; }
  cmp -s <(code "$LOCAL/ensemble/table.md") <(code "$WORK/slurm/ensemble/table.md") ||
    fail "table.md differs: $(diff <(code "$LOCAL/ensemble/table.md") <(code "$WORK/slurm/ensemble/table.md") | head -5)"
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "slurm_test: the local ensemble %.1f s (0 when up to date)\n", b - a }'
}

[ "$MODE" = compare ] || cluster_part
[ "$MODE" = cluster ] || compare_part
[ "$failures" -eq 0 ] && echo "slurm_test: all checks passed" || echo "slurm_test: $failures failed"
[ "$failures" -eq 0 ]
