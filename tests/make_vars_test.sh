#!/usr/bin/env bash
# The Makefile's user variables are checked once, as numbers or names
# (pipeline/make_vars.mk): a bad value stops make before anything runs, with
# the variable, the value and what is allowed; a good one is taken as written.
# And a recipe that fails leaves no target behind (.DELETE_ON_ERROR).
# Usage: make_vars_test.sh SOURCE_DIR
set -uo pipefail
cd "$1" || exit 1
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# refused VAR=VALUE MESSAGE: make -n stops at parse time naming them
refused() {
  local out rc
  out=$(timeout 60 make -n --no-print-directory clean "$1" 2>&1); rc=$?  # (MEMBERS=1000000 ran for ever)
  [ "$rc" -ne 0 ] || fail "$1 was accepted"
  grep -qF -- "$2" <<<"$out" || fail "$1: no '$2' in: $out"
}
accepted() {
  local out
  out=$(make -n --no-print-directory clean "$@" 2>&1) || fail "$* was refused: $out"
}

count="must be a whole number from"
refused MEMBERS=010 "MEMBERS=010: $count 1 to 1000"    # was read as octal: 8 members
refused MEMBERS=08 "MEMBERS=08: $count 1 to 1000"      # passed the check, made no member
refused MEMBERS=0 "MEMBERS=0: $count"
refused MEMBERS=-2 "MEMBERS=-2: $count"
refused MEMBERS=1000000 "MEMBERS=1000000: $count"      # make -n ran for ever
refused MEMBERS=99999999999999999999 "MEMBERS=99999999999999999999: $count"
refused "MEMBERS=2 3" "MEMBERS=2 3: $count"
refused "MEMBERS=1; touch x" "$count"
refused JOBS=0 "JOBS=0: $count 1 to 1024"
refused THREADS=two "THREADS=two: $count"
refused PROGRESS=1e3 "PROGRESS=1e3: $count 1 to 86400"
refused PRESET=../../pipeline/presets/fast "PRESET=../../pipeline/presets/fast: must be one of: quick default fast paper"
refused PRESET=nosuch "PRESET=nosuch: must be one of:"
refused "PRESET=fast quick" "must be one of:"
refused "PRESET=fast " "PRESET=fast : must be one of:"   # was "mixed implicit and normal rules"
refused "INTRUDER=square " "INTRUDER=square : must be one of: square"
refused INTRUDER=round "INTRUDER=round: must be one of: square"
refused INTRUDER=../intruders/square "must be one of: square"
refused "PRESET=%" "PRESET=%: must be one of:"
refused "INTRUDER=s%" "INTRUDER=s%: must be one of: square"
[ -e x ] && fail "a value ran a command"

accepted MEMBERS=1000 JOBS=1 THREADS=2 PROGRESS=5 PRESET=fast INTRUDER=square
accepted PRESET=quick MEMBERS=1

# a recipe that fails after writing its target leaves no target that a later make takes as done
# (.DELETE_ON_ERROR, for every rule of the Makefile and of what it includes)
T=$(mktemp -d /tmp/dem2d_delete.XXXXXX)
printf '%s/out:\n\techo partial > $@; exit 1\n' "$T" > "$T/fail.mk"
make --no-print-directory -f Makefile -f "$T/fail.mk" "$T/out" >/dev/null 2>&1 && fail "the failing recipe succeeded"
[ -e "$T/out" ] && fail "a failed recipe left its target behind: $(cat "$T/out")"
rm -rf "$T"

[ "$failures" -eq 0 ] && echo "make_vars_test: all checks passed" || { echo "make_vars_test: $failures failure(s)"; exit 1; }
