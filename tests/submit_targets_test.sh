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
  "$W/logs" 0 results/report.md "$W/targets.txt" "$@"); }

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

[ "$failures" -eq 0 ] && echo "submit_targets_test: all checks passed" || { echo "submit_targets_test: $failures failure(s)"; exit 1; }
