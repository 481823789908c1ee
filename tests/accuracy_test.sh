#!/usr/bin/env bash
# The accuracy sweep's plan (pipeline/accuracy/plan.py): every overlay it
# writes is a valid scene with the intended knob (checked by dem2d itself),
# times given in travel scale with 1/V, slices last slice_mm of travel, and bad
# sweep files are refused with a message naming the file and the key. Then the
# table's comparison functions (tests/test_accuracy_table.py) and an ensemble's
# against the reference (tests/test_ensemble_vs_reference.py).
# Usage: accuracy_test.sh DEM2D REPO_DIR
set -uo pipefail
DEM2D=$1
REPO=$2
PY=${PYTHON:-/usr/bin/python3}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$REPO" || exit 1
# one grain stands in for a bed, so the checks need no run file (dt_c: the smallest grain, 2 mm)
printf '[[particle]]\nx = 0.02\ny = 0.05\nd = 0.002\n' >"$WORK/grain.toml"

$PY -m pipeline.accuracy.plan data/accuracy.toml "$WORK/acc" || fail "plan.py on data/accuracy.toml"
[ -s "$WORK/acc/plan.mk" ] || fail "no plan.mk"

# every point's overlay, over its preset, is a valid pull-off scene; dt and dt/dt_c as intended
$PY - "$WORK/acc" data/accuracy.toml >"$WORK/points" <<'PYEOF' || fail "listing the points"
import sys, tomllib
cfg = tomllib.load(open(sys.argv[2], "rb"))
for p in cfg["point"]:
    print(p["name"], p.get("preset", cfg["sweep"]["base_preset"]), p["knob"], p["extent"],
          p.get("kn", 0), p.get("dt_over_critical", 0), p.get("V_mm_s", 1.2))
PYEOF
while read -r name preset knob extent kn ratio v; do
  out=$("$DEM2D" check pipeline/pulloff.toml --overlay "pipeline/presets/$preset.toml" \
        --overlay "$WORK/acc/points/$name/overlay.toml" --overlay "$WORK/grain.toml" 2>&1) ||
    { fail "$name: dem2d check: $out"; continue; }
  # slices: duration x V = slice length (10 mm); whole runs: 170 s at 1.2 mm/s = 204 mm of travel
  $PY - "$out" "$extent" "$v" "$knob" "$ratio" <<'PYEOF' || fail "$name: $out"
import re, sys
out, extent, v, knob, ratio = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4], float(sys.argv[5])
m = re.search(r"dt = ([0-9.e+-]+) s = dt_c/([0-9.]+).* ([0-9]+) steps for ([0-9.e+-]+) s", out)
dt, inv, steps, duration = float(m[1]), float(m[2]), int(m[3]), float(m[4])
travel_mm = duration * v
assert abs(travel_mm - (10.0 if extent == "slice" else 204.0)) < 1e-3, travel_mm
if knob == "dt":
    assert abs(1.0 / inv - ratio) < 1e-3 * ratio, (inv, ratio)
PYEOF
done <"$WORK/points"
for bed in "$WORK"/acc/beds/*/; do
  "$DEM2D" check pipeline/accuracy/resettle.toml --overlay pipeline/presets/default.toml \
    --overlay "$bed/overlay.toml" --overlay "$WORK/grain.toml" >/dev/null 2>&1 || fail "bed $bed"
done
# the V overlay: every time given in travel scales with 1/V (V = 29 mm/s: x 1.2/29)
$PY - "$WORK/acc/points/V_29/overlay.toml" <<'PYEOF' || fail "V_29 overlay scaling"
import sys, tomllib
o = tomllib.load(open(sys.argv[1], "rb"))
s = 1.2 / 29.0
assert o["body"] == [{"name": "intruder", "velocity": [0.0, 0.029]}], o["body"]
for table, key, base in [("output", "series_interval", 0.02), ("output", "snapshot_interval", 0.125),
                         ("output", "displacement_window", 0.05), ("stop", "free_time", 2.0), ("time", "duration", 170.0)]:
    assert abs(o[table][key] - base * s) < 1e-12, (key, o[table][key])
PYEOF
# the k_n overlay: k_t and k_r keep the preset's ratios
grep -q "^kt = 9600000.0" "$WORK/acc/points/kn_1.92e7/overlay.toml" || fail "kn_1.92e7: k_t is not k_n/2"
grep -q "^rolling_stiffness = 0.01728" "$WORK/acc/points/kn_1.92e7/overlay.toml" || fail "kn_1.92e7: k_r"
# a replica is the point it names with only dt / dt_c changed: the same contact law, the same bed
$PY - data/accuracy.toml "$WORK/acc" <<'PYEOF' || fail "replica overlays"
import sys, tomllib
cfg = tomllib.load(open(sys.argv[1], "rb"))
def overlay(name):
    return tomllib.load(open(f"{sys.argv[2]}/points/{name}/overlay.toml", "rb"))
replicas = [p for p in cfg["point"] if p["knob"] == "replica"]
assert replicas, "no replica in data/accuracy.toml"
for p in replicas:
    o, r = overlay(p["replica_of"]), overlay(p["name"])
    assert r.pop("time") == {"dt_over_critical": p["dt_over_critical"]}, p["name"]
    o.get("time", {}).pop("dt_over_critical", None)
    assert r == {k: v for k, v in o.items() if v}, (p["name"], r, o)
PYEOF
grep -q "points/kn_1.92e8_replica/metrics.json: $WORK/acc/beds/kn_1.92e8/run.h5 " "$WORK/acc/plan.mk" ||
  fail "kn_1.92e8_replica does not start from kn_1.92e8's bed"
# rewriting an unchanged plan keeps the files' times (make reruns nothing)
before=$(stat -c %Y.%N "$WORK/acc/points/V_29/overlay.toml")
sleep 1
$PY -m pipeline.accuracy.plan data/accuracy.toml "$WORK/acc"
[ "$(stat -c %Y.%N "$WORK/acc/points/V_29/overlay.toml")" = "$before" ] || fail "an unchanged overlay was rewritten"

# bad sweep files: exit 2, the file and the key named
bad() {
  local pattern=$1; shift
  "$@" >"$WORK/out" 2>&1
  local rc=$?
  [ $rc -eq 2 ] || fail "$*: exit $rc, expected 2"
  grep -q -- "$pattern" "$WORK/out" || fail "no '$pattern' in: $(cat "$WORK/out")"
}
sed 's/^knob = "kn"$/knob = "stiffness"/' data/accuracy.toml >"$WORK/bad_knob.toml"
bad "bad_knob.toml: point\[[0-9]*\] (kn_[0-9.e]*): knob = 'stiffness'" $PY -m pipeline.accuracy.plan "$WORK/bad_knob.toml" "$WORK/b1"
sed 's/^kn = 1.92e5$/kn = -1.92e5/' data/accuracy.toml >"$WORK/bad_kn.toml"
bad "bad_kn.toml: point\[[0-9]*\] (kn_1.92e5): kn = -192000.0: must be a number > 0" $PY -m pipeline.accuracy.plan "$WORK/bad_kn.toml" "$WORK/b2"
sed 's/^V_mm_s = 2.4$/V_mm_s = -2.4/' data/accuracy.toml >"$WORK/bad_v.toml"
bad "bad_v.toml: point\[[0-9]*\] (V_2.4): V_mm_s = -2.4: must be a number > 0" $PY -m pipeline.accuracy.plan "$WORK/bad_v.toml" "$WORK/b3"

sed 's/^replica_of = "default"$/replica_of = "nowhere"/' data/accuracy.toml >"$WORK/bad_replica.toml"
bad "bad_replica.toml: point\[[0-9]*\] (replica): replica_of = 'nowhere': must name another point" \
  $PY -m pipeline.accuracy.plan "$WORK/bad_replica.toml" "$WORK/b4"
sed '/^replica_of = "default"$/d' data/accuracy.toml >"$WORK/no_replica_of.toml"
bad "no_replica_of.toml: point\[[0-9]*\] (replica): replica_of is given for knob = \"replica\"" \
  $PY -m pipeline.accuracy.plan "$WORK/no_replica_of.toml" "$WORK/b5"

$PY tests/test_accuracy_table.py || fail "tests/test_accuracy_table.py"
$PY tests/test_ensemble_vs_reference.py || fail "tests/test_ensemble_vs_reference.py"
grep -q "^ACCURACY_REFERENCE_TARGETS := $WORK/acc/points/kn_1.92e8/metrics.json $WORK/acc/points/kn_1.92e8_replica/metrics.json\$" \
  "$WORK/acc/plan.mk" || fail "plan.mk: the whole-run reference's targets"

[ $failures -eq 0 ] && echo "accuracy_test: all checks passed"
exit $((failures > 0))
