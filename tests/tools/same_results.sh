#!/usr/bin/env bash
# same_results.sh OLD_DEM2D NEW_DEM2D [FILL_RUN]: do two builds of dem2d give
# bitwise the same run files? Runs the tests' scenes (quick fill, quick
# pull-off on 1 and 2 threads, the resumable pour with the energy ledger, the
# minimal scene) and the first 1 s of the study's fill and pull-off (default
# preset; the pull-off from FILL_RUN, default results/default/fill/run.h5,
# skipped if absent) with each, then compares every dataset and attribute
# (tests/tools/same_run.py). For restructurings that must not change results.
# Exit status 0 if all the same. Takes a few minutes on 2 cores.
set -uo pipefail
OLD=$(realpath "$1"); NEW=$(realpath "$2")
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
FILL_RUN=$(realpath -m "${3:-$ROOT/results/default/fill/run.h5}")
PY=${PYTHON:-/usr/bin/python3}
WORK=$(mktemp -d); trap 'rm -rf "$WORK"' EXIT
printf '[time]\nduration = 1.0\n' > "$WORK/short.toml"
run_set() {  # DEM2D OUT: into a fixed directory, so that both scene texts name the same paths
  local D=$1 O=$WORK/runs
  rm -rf "$O"; mkdir -p "$O"
  cd "$ROOT"
  "$D" run tests/scenes/quick_fill.toml --out "$O/qfill" --threads 2 2>/dev/null &&
  "$D" run tests/scenes/quick_pulloff.toml --initial "$O/qfill/run.h5" --out "$O/qpull" --threads 2 2>/dev/null &&
  "$D" run tests/scenes/quick_pulloff.toml --initial "$O/qfill/run.h5" --out "$O/qpull1" --threads 1 2>/dev/null &&
  "$D" run tests/scenes/pour_resume.toml --out "$O/pour" --threads 2 2>/dev/null &&
  "$D" run tests/scenes/valid_minimal.toml --out "$O/minimal" --threads 1 2>/dev/null &&
  "$D" run pipeline/fill.toml --overlay pipeline/presets/default.toml --overlay "$WORK/short.toml" \
    --out "$O/fill" --threads 2 2>/dev/null || return 1
  if [ -f "$FILL_RUN" ]; then
    "$D" run pipeline/pulloff.toml --overlay pipeline/presets/default.toml --overlay "$WORK/short.toml" \
      --initial "$FILL_RUN" --out "$O/pull" --threads 2 2>/dev/null || return 1
  fi
  mv "$O" "$2"
}
run_set "$OLD" "$WORK/old" || { echo "same_results: the old build failed to run the scenes"; exit 2; }
run_set "$NEW" "$WORK/new" || { echo "same_results: the new build failed to run the scenes"; exit 2; }
[ -f "$FILL_RUN" ] || echo "same_results: $FILL_RUN absent: the study's pull-off not compared"
rc=0
for d in "$WORK"/old/*/; do
  name=$(basename "$d")
  "$PY" "$ROOT/tests/tools/same_run.py" "$d/run.h5" "$WORK/new/$name/run.h5" | tail -3 || rc=1
done
exit $rc
