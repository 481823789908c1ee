#!/usr/bin/env bash
# The ctest fixture `quick_study`: the quick fill and the pull-off from its
# bed (the runs `make reproduce PRESET=quick` makes), simulated once for every
# test that reads them (tests/quick_study.hpp). One thread: ctest runs tests
# side by side. Usage: quick_study.sh DEM2D TESTS_DIR OUT
set -euo pipefail
DEM2D=$1
TESTS=$2
OUT=$3
"$DEM2D" run "$TESTS/scenes/quick_fill.toml" --out "$OUT/fill" --threads 1 --overwrite --progress 0
"$DEM2D" run "$TESTS/scenes/quick_pulloff.toml" --initial "$OUT/fill/run.h5" --out "$OUT/pulloff" --threads 1 \
  --overwrite --progress 0
