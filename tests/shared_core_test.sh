#!/usr/bin/env bash
# Threads that share a core: the 2-thread step loop must neither hang nor
# change the results when one of its threads runs late (preempted), as on a
# loaded machine or an oversubscribed cluster node. Runs scenes with list
# rebuilds, a body removal, hopper taps and the energy ledger on 1 thread,
# then on 2 threads pinned to one core (taskset: every barrier hands the core
# over, so a thread is often late), each under a hard time limit, and asks
# for bitwise identical run files. Usage: shared_core_test.sh DEM2D TESTS_DIR
set -uo pipefail
DEM2D=$1
TESTS=$2
PY=${PYTHON:-/usr/bin/python3}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

LIMIT=${SHARED_CORE_LIMIT:-300}  # s: a run that takes longer hangs
# the first processor this process may use (not always 0 in a container)
CPU=$(awk '/^Cpus_allowed_list/ { split($2, a, /[,-]/); print a[1] }' /proc/self/status)
printf '[time]\nduration = 0.3\n' >"$WORK/short.toml"  # s: the gate goes at 0.1 s
for scene in quick_fill pour_resume; do
  "$DEM2D" run "$TESTS/scenes/$scene.toml" --overlay "$WORK/short.toml" --out "$WORK/$scene-1" --threads 1 \
    >/dev/null 2>&1 || { fail "$scene on 1 thread did not run"; continue; }
  timeout -s KILL "$LIMIT" taskset -c "${CPU:-0}" "$DEM2D" run "$TESTS/scenes/$scene.toml" --overlay "$WORK/short.toml" \
    --out "$WORK/$scene-2" --threads 2 >/dev/null 2>&1
  rc=$?
  if [ "$rc" -eq 137 ]; then fail "$scene on 2 threads sharing one core hung (killed after $LIMIT s)"; continue; fi
  [ "$rc" -eq 0 ] || { fail "$scene on 2 threads sharing one core exited $rc"; continue; }
  "$PY" "$TESTS/tools/same_run.py" "$WORK/$scene-1/run.h5" "$WORK/$scene-2/run.h5" >"$WORK/diff" ||
    fail "$scene: 2 threads sharing one core differ from 1 thread: $(tail -3 "$WORK/diff")"
  echo "$scene: 2 threads on one core = 1 thread, bitwise"
done
[ "$failures" -eq 0 ] && echo "shared_core_test: all passed"
exit $((failures > 0))
