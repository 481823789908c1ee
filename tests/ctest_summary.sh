#!/usr/bin/env bash
# The counts of a ctest run from its output (make test's: LOG), and a skip
# made a failure: in `make test` a test that did not run proves nothing, and
# a green run must not hide one. Exit 1 if any test failed, did not run or
# was skipped. Usage: ctest_summary.sh LOG WHAT
set -uo pipefail
LOG=$1
WHAT=$2
passed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* Passed ' "$LOG")
failed=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*(\*\*\*Failed|\*\*\*Timeout|\*\*\*Exception|Not Run|\*\*\*Not Run)' "$LOG")
skipped=$(grep -cE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .*\*\*\*Skipped' "$LOG")
echo "$WHAT: $passed passed, $failed failed, $skipped skipped"
if [ "$skipped" -gt 0 ]; then
  echo "$WHAT: a skipped test is a failure in make test:" >&2
  grep -E '\*\*\*Skipped' "$LOG" >&2
fi
[ "$failed" -eq 0 ] && [ "$skipped" -eq 0 ] && [ "$passed" -gt 0 ]
