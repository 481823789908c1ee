#!/usr/bin/env bash
# The pipeline end to end, after `make reproduce PRESET=quick` (make
# test-pipeline): every output exists and is complete, a second `make
# reproduce` reruns nothing, a changed stage setting reruns only that stage
# and what depends on it, and missing inputs get messages naming the file and
# what to run.  Usage: tests/pipeline_test.sh results/quick  (from the repo root)
set -uo pipefail
R=$1
PY=${PYTHON:-/usr/bin/python3}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# --- outputs -----------------------------------------------------------------
$PY - "$R" <<'PYEOF' || fail "outputs of $R"
import json, re, sys, tomllib
from pathlib import Path
from pipeline.stages import load
r = Path(sys.argv[1])
m = json.load(open(r / "metrics.json"))
for stage in [s.name for s in load()]:
    assert isinstance(m.get(stage), dict) and m[stage], f"metrics.json: no {stage}"
    assert m["cost"][stage]["wall_seconds"] > 0, f"cost of {stage}"
assert m["cost"]["pulloff"]["ns_per_particle_step"] > 0
targets = tomllib.load(open("data/paper_targets.toml", "rb"))["target"]
tests = [t for s in json.load(open(r / "check.json"))["testsuites"] for t in s["testsuite"]]
assert len(tests) == len(targets), f"check.json: {len(tests)} tests for {len(targets)} targets"
assert all(t["verdict"] in ("pass", "fail", "undetermined") and t["metric"] for t in tests)
index = json.load(open(r / "figures" / "index.json"))
assert len(index) >= 10, f"{len(index)} figures"
report = (r / "report.md").read_text()
for fig in index:
    png = (r / "figures" / fig["file"]).read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000, fig["file"]
    assert f"figures/{fig['file']}" in report, f"report.md misses {fig['file']}"
    assert fig["caption"] and fig["title"]
for heading in ["## Metrics against the paper", "## Deviations from the paper", "## Cost", "## Figures"]:
    assert heading in report, heading
for t in tests:
    assert f"`{t['metric']}`" in report, t["metric"]
# report.html: the same report in one self-contained page: every figure embedded, nothing fetched
html = (r / "report.html").read_text()
assert html.count('src="data:image/png;base64,') == len(index), "report.html does not embed every figure"
assert not re.search(r'(src|href)="(?!data:|#|https?:)', html), "report.html refers to a file beside it"
assert html.count("<table>") >= 3 and "<h2>Metrics against the paper</h2>" in html
print(f"pipeline outputs: {len(m)} metric groups, {len(tests)} targets, {len(index)} figures, report.md and "
      f"report.html ({len(html) // 1024} KiB) complete")
PYEOF

# --- staleness: nothing reruns; a stage's setting reruns that stage and what follows
ran() { grep -E "dem2d run|analysis/[a-z_]+ |pipeline\.report\.[a-z_]+|check_paper_targets" "$1" | sed 's/ .*//' | sort -u; }
make --no-print-directory reproduce PRESET=quick >"$WORK/again" 2>&1 || fail "second make reproduce: $(cat "$WORK/again")"
[ -z "$(ran "$WORK/again")" ] || fail "a second make reproduce reran: $(ran "$WORK/again")"
make --no-print-directory reproduce PRESET=quick -W data/friction.toml >"$WORK/friction" 2>&1 ||
  fail "make reproduce after a friction setting changed: $(cat "$WORK/friction")"
grep -q "analysis/friction " "$WORK/friction" || fail "friction did not rerun"
grep -q "pipeline.report.report" "$WORK/friction" || fail "the report was not rewritten"
# every other stage of the registry (none reads friction's outputs) stays as it was
others=$($PY -c 'from pipeline import stages
print("|".join(s.program for s in stages.load() if s.name != "friction" and "friction" not in s.after()))')
[ -n "$others" ] || fail "the registry lists no stage besides friction"
grep -qE "dem2d run|analysis/($others) " "$WORK/friction" &&
  fail "a changed friction setting reran other stages: $(ran "$WORK/friction")"

# --- an ensemble of two members: member 0 is the single run, member 1 another
# bed; the aggregate, its tolerance tests and table; a rerun runs nothing
make --no-print-directory ensemble PRESET=quick MEMBERS=2 >"$WORK/ens" 2>&1 || fail "make ensemble: $(tail -20 "$WORK/ens")"
E=$R/ensemble
for s in fill pulloff; do
  $PY tests/tools/same_run.py "$E/member_000/$s/run.h5" "$R/$s/run.h5" --ignore-attr scene_text >/dev/null ||
    fail "ensemble member 0's $s differs from the single run's"
done
$PY tests/tools/same_run.py "$E/member_001/fill/run.h5" "$R/fill/run.h5" --ignore-attr scene_text >/dev/null &&
  fail "ensemble member 1's bed is the single run's: its seeds did not change"
$PY - "$E" <<'PYEOF' || fail "ensemble outputs of $E"
import json, sys
from pathlib import Path
e = Path(sys.argv[1])
st = json.load(open(e / "stats.json"))
assert st["members"] == ["member_000", "member_001"], st["members"]
s = st["metrics"]["fill.solid_fraction"]
assert s["n"] == 2 and len(s["values"]) == 2 and s["values"][0] != s["values"][1], s
assert s["ci95"][0] <= s["mean"] <= s["ci95"][1] and min(s["values"]) <= s["ci95"][0], s
assert abs(s["mean"] - sum(s["values"]) / 2) < 1e-12
m = json.load(open(e / "metrics.json"))
assert m["fill"]["solid_fraction"] == s["mean"]
table = (e / "table.md").read_text()
assert "| R1 | `fill.solid_fraction` |" in table, table[:400]
import re
c = re.search(r"\*\*(\d+) hold, (\d+) fail, (\d+) undetermined\*\* \(of (\d+) targets\)", table)
assert c and sum(map(int, c.groups()[:3])) == int(c.group(4)), table[:600]
# the CG-versus-PIV comparison across the members: each member's own mean over its pairs
row = re.search(r"^\| β, PIV − CG \(paired\) \| ([^|]+) \| ([^|]+) \|", table, re.M)
assert "## Synthetic PIV against coarse-graining, across the members" in table and row, table[-1500:]
d = st["metrics"]["piv.cone_angle_deg.difference.mean"]
assert row.group(1).strip() == ", ".join("—" if v is None else f"{v:.4g}" for v in d["values"]) and row.group(2).strip() == f"{d['mean']:.4g}", row.group(0)
assert (e / "drag.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
print(f"ensemble outputs: {len(st['metrics'])} metrics over {len(st['members'])} members")
PYEOF
make --no-print-directory ensemble PRESET=quick MEMBERS=2 >"$WORK/ens2" 2>&1 || fail "second make ensemble"
grep -q "dem2d run\|analysis/" "$WORK/ens2" && fail "a second make ensemble reran a member: $(grep 'dem2d run\|analysis/' "$WORK/ens2")"

# --- missing or corrupt inputs: the message names the file and what to run
Q=$WORK/quick  # a results folder named after its preset, as results/quick is
mkdir -p "$Q"
expect_msg() {  # expect_msg PATTERN -- command...: exit code 2 and PATTERN in stderr
  local pattern=$1; shift 2
  "$@" >"$WORK/out" 2>"$WORK/err"; local rc=$?
  [ "$rc" -eq 2 ] || fail "$* exited $rc, expected 2"
  grep -q -- "$pattern" "$WORK/err" || fail "$*: no '$pattern' in: $(cat "$WORK/err")"
}
expect_msg "quick/metrics.json: no such file: run \`make reproduce PRESET=quick\`" -- \
  $PY -m pipeline.report.report "$Q" quick
expect_msg "quick/fill/metrics.json: no such file: run \`make fill PRESET=quick\`" -- \
  $PY -m pipeline.report.merge_metrics "$Q" quick
expect_msg "quick/fill/metrics.json missing: run \`make fill PRESET=quick\`" -- $PY -m pipeline.report.figures "$Q"
# the registry of stages: an added entry is a make target; a bad one is named
cp pipeline/stages.toml "$WORK/more.toml"
printf '[[stage]]\nname = "friction_again"\nprogram = "friction"\nrun = "pulloff"\n%s\n' \
  'config = "data/friction.toml"
outputs = ["friction.h5", "metrics.json"]' >>"$WORK/more.toml"
make --no-print-directory "$R/friction_again/metrics.json" PRESET=quick STAGE_REGISTRY="$WORK/more.toml" \
  >"$WORK/more.out" 2>&1 || fail "a stage added to the registry did not run: $(cat "$WORK/more.out")"
grep -q "analysis/friction .*--out $R/friction_again" "$WORK/more.out" || fail "the added stage ran no program"
[ -s "$R/friction_again/metrics.json" ] || fail "the added stage wrote no metrics.json"
rm -rf "$R/friction_again" "build/release/registries$WORK/more.toml.mk"
sed 's|"spectrum/metrics.json"|"spectra/metrics.json"|' pipeline/stages.toml >"$WORK/bad.toml"
expect_msg "stage\[4\] (network): inputs = .*'spectra/metrics.json': not an output of an earlier stage" -- \
  $PY -m pipeline.stages make "$WORK/bad.toml"
echo '{"fill": ' >"$Q/metrics.json"
expect_msg "quick/metrics.json: not valid JSON" -- build/release/tests/paper_targets/check_paper_targets \
  "$Q/metrics.json" data/paper_targets.toml
cp -r "$R/fill" "$R/pulloff" "$Q/" && printf 'not an HDF5 file' >"$Q/pulloff/run.h5"
make --no-print-directory "$Q/spectrum/metrics.json" PRESET=quick RESULTS="$Q" >"$WORK/out" 2>"$WORK/err" &&
  fail "make spectrum on a corrupt run file succeeded"
grep -q "quick/pulloff/run.h5: cannot open as HDF5" "$WORK/err" || fail "corrupt run file not named: $(cat "$WORK/err")"
grep -q "delete it and run \`make reproduce PRESET=quick\`" "$WORK/err" || fail "no remedy given: $(cat "$WORK/err")"
[ -e "$Q/spectrum/metrics.json" ] && fail "a failed stage left metrics behind"

[ "$failures" -eq 0 ] && echo "pipeline_test: all checks passed" || echo "pipeline_test: $failures failed"
[ "$failures" -eq 0 ]
