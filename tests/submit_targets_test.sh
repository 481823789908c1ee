#!/usr/bin/env bash
# pipeline/slurm/submit_targets.sh against stand-ins for sbatch, squeue and sinfo
# that record what would be submitted: each task's command is `make TARGET`
# plus exactly the VAR=VALUE arguments given (none given: none passed; an empty
# word made every task fail with "empty string invalid as file name"), and an
# argument that is not VAR=VALUE is refused before anything is submitted.
# Usage: submit_targets_test.sh SOURCE_DIR
set -uo pipefail
SRC=$(cd "$1" && pwd)
W=$(mktemp -d /tmp/dem2d_submit.XXXXXX)
trap 'rm -rf "$W"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
mkdir -p "$W/bin"
cat >"$W/bin/sbatch" <<'STUB'
#!/usr/bin/env bash
while [ $# -gt 0 ]; do [ "$1" = --wrap ] && { printf '%s\n' "$2" >>"$STUB_LOG"; shift; }; shift; done
echo $((RANDOM + 1))
STUB
printf '#!/bin/sh\nexit 0\n' >"$W/bin/squeue"
printf '#!/bin/sh\necho 0/2/0/2\n' >"$W/bin/sinfo"
chmod +x "$W/bin/"*
printf '0 results/a/metrics.json 5\n0 results/b/metrics.json 5\n' >"$W/targets.txt"
submit() { (cd "$W" && STUB_LOG="$W/wrap.log" PATH="$W/bin:$PATH" bash "$SRC/pipeline/slurm/submit_targets.sh" \
  "$W/logs" "${WAIT:-0}" results/report.md "$W/targets.txt" "$@"); }

: >"$W/wrap.log"
submit >"$W/out" 2>&1 || fail "no VAR=VALUE arguments: exit $?: $(cat "$W/out")"
[ "$(wc -l <"$W/wrap.log")" -eq 2 ] || fail "expected a wave and the final job: $(cat "$W/wrap.log")"
grep -q "''" "$W/wrap.log" && fail "an empty word passed to make: $(cat "$W/wrap.log")"
grep -q '^make --no-print-directory "results/report.md"; rc=' "$W/wrap.log" || fail "final job: $(tail -1 "$W/wrap.log")"

: >"$W/wrap.log"
submit PRESET=fast "THREADS=1" >"$W/out" 2>&1 || fail "with VAR=VALUE arguments: exit $?: $(cat "$W/out")"
[ "$(grep -c ' PRESET=fast THREADS=1; rc=' "$W/wrap.log")" -eq 2 ] || fail "variables not passed on: $(cat "$W/wrap.log")"

: >"$W/wrap.log"
out=$(submit PRESET=fast results/x 2>&1); rc=$?
[ "$rc" -eq 2 ] && grep -qF "'results/x': expected VAR=VALUE" <<<"$out" || fail "a target among the variables: exit $rc: $out"
[ -s "$W/wrap.log" ] && fail "something was submitted before the refusal: $(cat "$W/wrap.log")"

# the controller stops answering during the wait (squeue: "Unable to contact slurm controller"), then
# answers again, the jobs having ended meanwhile (their status files written: success): the wait goes on
# through the silence, and the status files decide
cat >"$W/bin/squeue" <<'STUB'
#!/usr/bin/env bash
n=$(($(cat "$STUB_COUNT" 2>/dev/null || echo 0) + 1)); echo $n >"$STUB_COUNT"
if [ "$n" -gt 2 ]; then for f in wave0_0 wave0_1 final; do echo 0 >"$STUB_STATUS/$f.status"; done; exit 0; fi
echo "squeue: error: Unable to contact slurm controller (connect failure)" >&2; exit 1
STUB
chmod +x "$W/bin/squeue"
out=$(STUB_STATUS="$W/logs/status" STUB_COUNT="$W/count1" SLURM_POLL_SECONDS=0.2 WAIT=1 submit 2>&1); rc=$?
[ "$rc" -eq 0 ] && grep -q "squeue fails (squeue: error: Unable to contact" <<<"$out" && grep -q "answers again" <<<"$out" ||
  fail "a controller back after a silence: exit $rc: $out"
# ... and one that never answers again before the bound: what the jobs do is unknown, not "never ran"
printf '#!/bin/sh\necho "squeue: error: Unable to contact slurm controller (connect failure)" >&2\nexit 1\n' >"$W/bin/squeue"
out=$(SLURM_WAIT_MINUTES=0.05 SLURM_POLL_SECONDS=0.5 WAIT=1 submit 2>&1); rc=$?
[ "$rc" -eq 1 ] && grep -q "has not answered since" <<<"$out" &&
  [ "$(grep -c "not finished when the controller stopped answering" <<<"$out")" -eq 3 ] && ! grep -q "never ran" <<<"$out" ||
  fail "a controller silent to the end: exit $rc: $out"
# jobs ended so long ago that the controller no longer knows them: done, as when no longer listed
cat >"$W/bin/squeue" <<'STUB'
#!/bin/sh
for f in wave0_0 wave0_1 final; do echo 0 >"$STUB_STATUS/$f.status"; done
echo "slurm_load_jobs error: Invalid job id specified" >&2; exit 1
STUB
out=$(STUB_STATUS="$W/logs/status" SLURM_POLL_SECONDS=0.2 WAIT=1 submit 2>&1); rc=$?
[ "$rc" -eq 0 ] && ! grep -q "squeue fails" <<<"$out" || fail "purged jobs: exit $rc: $out"
for m in 0 -1 x; do
  out=$(SLURM_WAIT_MINUTES=$m WAIT=1 submit 2>&1); rc=$?
  [ "$rc" -eq 2 ] && grep -q "SLURM_WAIT_MINUTES=$m: expected minutes > 0" <<<"$out" || fail "SLURM_WAIT_MINUTES=$m: exit $rc: $out"
done

[ "$failures" -eq 0 ] && echo "submit_targets_test: all checks passed" || { echo "submit_targets_test: $failures failure(s)"; exit 1; }
