#!/usr/bin/env bash
# Command-line tests of dem2d: exit codes and messages, a complete run,
# resuming after SIGKILL and SIGTERM with results identical to an
# uninterrupted run, and a full disk.  Usage: cli_test.sh DEM2D TESTS_DIR
set -uo pipefail
DEM2D=$1
TESTS=$2
PY=${PYTHON:-/usr/bin/python3}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
# run files are checked against the program's own schema
"$DEM2D" inspect --schema >"$WORK/schema.json" || { echo "FAIL: dem2d inspect --schema exited $?"; exit 1; }
CHECK="$PY $TESTS/check_run_file.py --schema $WORK/schema.json"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect CODE PATTERN -- command...: exit code and a pattern in stderr
expect() {
  local code=$1 pattern=$2; shift 3
  "$@" >"$WORK/out" 2>"$WORK/err"
  local rc=$?
  [ "$rc" -eq "$code" ] || fail "$* exited $rc, expected $code: $(cat "$WORK/err")"
  grep -q -- "$pattern" "$WORK/err" "$WORK/out" || fail "$*: no '$pattern' in: $(cat "$WORK/err" "$WORK/out")"
}

expect 0 "valid" -- "$DEM2D" check "$TESTS/scenes/valid_minimal.toml"
# the effects, from the program's one list (sim/core/effects.hpp): each bit its place, what it needs among
# them; the scene format's documentation names the same, in the same order
"$DEM2D" --list-effects >"$WORK/effects.json" || fail "dem2d --list-effects exited $?"
$PY - "$WORK/effects.json" "$TESTS/../docs/scene_format.md" <<'PYEOF' || fail "dem2d --list-effects: $(cat "$WORK/effects.json")"
import json, re, sys
effects = json.load(open(sys.argv[1]))
keys = [e["key"] for e in effects]
assert [e["bit"] for e in effects] == [1 << k for k in range(len(effects))], effects
assert all(e["needs"] is None or e["needs"] in keys for e in effects) and all(e["what"] for e in effects), effects
assert {e["key"]: e["needs"] for e in effects}["rotating_bodies"] == "moving_bodies", effects
doc = open(sys.argv[2]).read()
listed = doc[doc.index("### `[effects]`"):doc.index("(the bits of")].split("default `false`:", 1)[1]
assert re.findall(r"`(\w+)`", listed) == keys, (keys, listed)
PYEOF
# the run-file format's page names the program's effects and ledger terms, and the ledger's page its balance,
# each term with the sign the schema gives it (energy_balance)
$PY - "$WORK/schema.json" "$TESTS/../docs/run_file.md" "$TESTS/../docs/energy.md" <<'PYEOF' || fail "docs/run_file.md or docs/energy.md: not the program's lists"
import json, re, sys
schema = json.load(open(sys.argv[1]))
lines = open(sys.argv[2]).read().splitlines()
effects = next(l for l in lines if l.startswith("| `effects` |")).split("comma-separated:", 1)[1].split("(`sim/", 1)[0]
assert re.findall(r"`(\w+)`", effects) == schema["effects"], (effects, schema["effects"])
signs = schema["energy_balance"]
energy = next(l for l in lines if l.startswith("| `energy/<term>` |"))
count, names = re.search(r"(\d+) terms \(([^;]*);", energy).groups()
assert int(count) == len(signs) and re.findall(r"`(\w+)`", names) == list(signs), (energy, signs)
doc = open(sys.argv[3]).read()
balance = doc[doc.index("with\n\n") + 6:doc.index("=  constant")]
written = {name: -1 if sign == "−" else 1 for sign, name in re.findall(r"(^|[+−])\s*(\w+)", balance.strip(), re.M)}
assert written == signs, (written, signs)
PYEOF
sed 's/^kn = .*/kn = -5.0/' "$TESTS/scenes/valid_minimal.toml" >"$WORK/bad.toml"
expect 2 "bad.toml:[0-9]*:[0-9]*: contact.kn = -5: must be > 0" -- "$DEM2D" check "$WORK/bad.toml"
expect 2 "bad.toml:[0-9]*:[0-9]*: contact.kn = -5" -- "$DEM2D" run "$WORK/bad.toml" --out "$WORK/bad"
[ -e "$WORK/bad/run.h5" ] && fail "a rejected scene left a run file"
expect 2 "nowhere.toml: cannot read the scene file" -- "$DEM2D" check "$WORK/nowhere.toml"
# a device that never ends is refused, not read until memory runs out
expect 2 "/dev/zero: cannot read the scene file: not a regular file" -- timeout 20 "$DEM2D" check /dev/zero
expect 0 "valid" -- bash -c "\"$DEM2D\" check <(cat \"$TESTS/scenes/valid_minimal.toml\")"  # a pipe is read
# a FIFO is read while its writer writes (here one that starts late); one nobody writes to is refused
mkfifo "$WORK/late.toml" "$WORK/unwritten.toml"
(sleep 2; cat "$TESTS/scenes/valid_minimal.toml" >"$WORK/late.toml") &
expect 0 "valid" -- timeout 30 "$DEM2D" check "$WORK/late.toml"
wait
expect 2 "unwritten.toml: cannot read the scene file: a pipe that nothing wrote to within 10 s" -- \
  timeout 30 "$DEM2D" check "$WORK/unwritten.toml"
expect 2 "threads: 65536: must be an integer from 0 (the program chooses) to" -- \
  "$DEM2D" run "$TESTS/scenes/valid_minimal.toml" --out "$WORK/many" --threads 65536
[ -e "$WORK/many" ] && fail "a rejected --threads left an output folder"
expect 2 "threads: -1: must be an integer" -- "$DEM2D" run "$TESTS/scenes/valid_minimal.toml" --out "$WORK/many" --threads -1
# parallel regions made inactive by the environment: the run takes the one thread OpenMP gives and says so
# (it waited at its barriers for a second thread, at 0 % CPU, deaf to SIGTERM)
expect 0 "1 thread, of 2 asked: OpenMP runs parallel regions with fewer" -- \
  env OMP_MAX_ACTIVE_LEVELS=0 timeout 120 "$DEM2D" run "$TESTS/scenes/valid_minimal.toml" --out "$WORK/levels" --threads 2
expect 2 "unknown command 'rnu' (commands: run, check, bench, inspect); did you mean 'run'?" -- "$DEM2D" rnu "$TESTS/scenes/valid_minimal.toml"
"$DEM2D" run --help | grep -q -- "--interrupt-at-step" && fail "the test-only --interrupt-at-step shows in run --help"
# every case of make bench runs on a kernel compiled for its effects (kernel_sets.inc), but the one that
# measures the generic kernel: a set missing there doubled the frictionless rows unnoticed
"$DEM2D" bench --list >"$WORK/bench_list.txt" || fail "dem2d bench --list failed"
[ "$(grep -c "specialised" "$WORK/bench_list.txt")" -ge 9 ] || fail "dem2d bench --list: $(cat "$WORK/bench_list.txt")"
grep "generic" "$WORK/bench_list.txt" | grep -v "^full contact law, generic kernel " &&
  fail "a bench case runs on the generic kernel: declare its set in sim/engine/kernel_sets.inc"

MIN_SCENE=$TESTS/scenes/valid_minimal.toml
# a complete run: run file and XDMF, valid layout, no work directory left
expect 0 "run.h5" -- "$DEM2D" run "$TESTS/scenes/valid_minimal.toml" --out "$WORK/minimal"
[ -d "$WORK/minimal/.run.work" ] && fail "work directory left behind"
$CHECK "$WORK/minimal/run.h5" >/dev/null || fail "check_run_file on the minimal run"
# ... and the check sees what departs from the schema: a dataset it does not know, one of another shape
cp "$WORK/minimal/run.h5" "$WORK/extra.h5"
cp "$WORK/minimal/run.xdmf" "$WORK/extra.xdmf"
$PY -c 'import h5py, sys; h5py.File(sys.argv[1], "a")["series/extra"] = [1.0]' "$WORK/extra.h5"
$CHECK "$WORK/extra.h5" >"$WORK/extra.out" 2>&1 && fail "check_run_file took a dataset the schema does not know"
grep -q "/series/extra: a dataset the schema does not know" "$WORK/extra.out" ||
  fail "check_run_file did not name the unknown dataset: $(cat "$WORK/extra.out")"
$PY -c 'import json, sys; s = json.load(open(sys.argv[1]))
next(d for d in s["datasets"] if d["path"] == "particles/mass")["shape"] = "N,2"
json.dump(s, open(sys.argv[2], "w"))' "$WORK/schema.json" "$WORK/other_schema.json"
$PY "$TESTS/check_run_file.py" --schema "$WORK/other_schema.json" "$WORK/minimal/run.h5" >"$WORK/other.out" 2>&1 &&
  fail "check_run_file ignored the schema's shape of /particles/mass"
grep -q "/particles/mass has shape" "$WORK/other.out" || fail "check_run_file: $(cat "$WORK/other.out")"
# with cohesion a contact pulls (fn < 0) and holds across a gap (overlap < 0): a valid run file
sed -e 's/^walls = true/walls = true\nrolling_resistance = true\ncohesion = true/' \
  -e 's/^friction = 0.5/friction = 0.5\nrolling_friction = 0.1\nrolling_stiffness = 1e-3\ncohesion_force = 2.0\ncohesion_range = 1e-5/' \
  "$MIN_SCENE" >"$WORK/cohesive.toml"
expect 0 "run.h5" -- "$DEM2D" run "$WORK/cohesive.toml" --out "$WORK/cohesive"
$PY -c 'import h5py, sys; f = h5py.File(sys.argv[1]); sys.exit(not (f["contacts/fn"][...] < 0).any())' \
  "$WORK/cohesive/run.h5" || fail "the cohesive run has no contact under tension (the check below means nothing)"
$CHECK "$WORK/cohesive/run.h5" >/dev/null || fail "check_run_file on a cohesive run: $($CHECK "$WORK/cohesive/run.h5")"
# a finished run is a result: the same command again has nothing to do; another scene into its folder is
# refused (the run file untouched) unless --overwrite, which says what goes stale
cp "$WORK/minimal/run.h5" "$WORK/minimal_first.h5"
expect 0 "is complete: this scene's run, from the same starting state, by this dem2d version; nothing to do" -- \
  "$DEM2D" run "$MIN_SCENE" --out "$WORK/minimal"
expect 2 "minimal/run.h5 (step [0-9]*, t = .*) is a finished run, not of this command: it ran another scene" -- \
  "$DEM2D" run "$WORK/cohesive.toml" --out "$WORK/minimal"
cmp -s "$WORK/minimal/run.h5" "$WORK/minimal_first.h5" || fail "a finished run was replaced without --overwrite"
cp -r "$WORK/minimal" "$WORK/replaced" && echo "{}" >"$WORK/replaced/metrics.json"
expect 0 "replacing the finished run .*: it ran another scene or other overlays; what was made from it goes stale, beside it: metrics.json" -- \
  "$DEM2D" run "$WORK/cohesive.toml" --out "$WORK/replaced" --overwrite --progress 60
# inspect: the whole file through the analyses' reader; damage is bad input naming the file and dataset
"$DEM2D" inspect "$WORK/minimal/run.h5" | grep -q "a sound run file" || fail "inspect of the minimal run"
expect 2 "not-a-run.h5: no such file" -- "$DEM2D" inspect "$WORK/not-a-run.h5"
expect 2 "valid_minimal.toml: cannot open as HDF5" -- "$DEM2D" inspect "$MIN_SCENE"
mkfifo "$WORK/pipe.h5"  # a pipe where a run file is expected blocked HDF5 for ever
expect 2 "pipe.h5: a pipe, not a regular file" -- timeout 20 "$DEM2D" inspect "$WORK/pipe.h5"
# a file that claims 3e8 grains (every per-grain dataset that wide, chunked: a few kB on disk): where
# its reading runs out of memory, that is what is said, with what the file claims (not "std::bad_alloc")
$PY - "$WORK/minimal/run.h5" "$WORK/huge.h5" <<'PYEOF'
import shutil, sys, h5py
shutil.copy(sys.argv[1], sys.argv[2])
N = 300_000_000
with h5py.File(sys.argv[2], "r+") as f:
    n = int(f.attrs["n_particles"])
    f.attrs["n_particles"] = N
    wide = []
    f.visititems(lambda name, o: wide.append(name) if isinstance(o, h5py.Dataset) and n in o.shape else None)
    for name in wide:
        d = f[name]
        shape, dtype, attrs = tuple(N if s == n else s for s in d.shape), d.dtype, dict(d.attrs)
        del f[name]
        new = f.create_dataset(name, shape=shape, dtype=dtype, chunks=True, compression="gzip")
        for k, v in attrs.items():
            new.attrs[k] = v
PYEOF
expect 2 "huge.h5: out of memory reading it (std::bad_alloc): it claims 300000000 grains (4800 MB for one snapshot" -- \
  bash -c 'ulimit -v 1500000; exec "$0" inspect "$1"' "$DEM2D" "$WORK/huge.h5"

# the output folder: a run never replaces or deletes a file it did not make, never writes through a
# link it did not make, never replaces the run it starts from, and a second run into the folder is refused
MIN=$TESTS/scenes/valid_minimal.toml
mkdir -p "$WORK/own" && echo "my notes" >"$WORK/own/run.h5" && echo "my view" >"$WORK/own/run.xdmf"
expect 2 "own/run.h5 is not a dem2d run file: dem2d does not replace a file it did not make" -- \
  "$DEM2D" run "$MIN" --out "$WORK/own"
[ "$(cat "$WORK/own/run.h5")" = "my notes" ] || fail "a user's run.h5 was replaced"
mv "$WORK/own/run.h5" "$WORK/own_notes"
expect 2 "own/run.xdmf is not a dem2d run's XDMF" -- "$DEM2D" run "$MIN" --out "$WORK/own"
expect 0 "run.h5" -- "$DEM2D" run "$MIN" --out "$WORK/own" --overwrite
echo "elsewhere" >"$WORK/elsewhere.log" && mkdir -p "$WORK/link" && ln -s "$WORK/elsewhere.log" "$WORK/link/run.log"
expect 2 "link/run.log is a symbolic link: dem2d does not write through one" -- "$DEM2D" run "$MIN" --out "$WORK/link"
[ "$(cat "$WORK/elsewhere.log")" = "elsewhere" ] || fail "run.log was written through a link"
# a pipe where the run writes its log blocked it for ever (SIGTERM too); a folder silently lost the log
mkdir -p "$WORK/fifo" "$WORK/logdir/run.log" && mkfifo "$WORK/fifo/run.log"
expect 2 "fifo/run.log is a pipe: dem2d writes its own file there" -- timeout 20 "$DEM2D" run "$MIN" --out "$WORK/fifo"
expect 2 "logdir/run.log is a folder: dem2d writes its own file there" -- "$DEM2D" run "$MIN" --out "$WORK/logdir"
mkdir -p "$WORK/work/.run.work" && echo keep >"$WORK/work/.run.work/mine.txt" && echo keep >"$WORK/work/run.h5.tmp"
expect 2 "holds mine.txt, which dem2d did not make" -- "$DEM2D" run "$MIN" --out "$WORK/work"
[ -e "$WORK/work/.run.work/mine.txt" ] || fail "a user's file in .run.work was deleted"
rm "$WORK/work/.run.work/mine.txt"
expect 0 "run.h5" -- "$DEM2D" run "$MIN" --out "$WORK/work"
[ "$(cat "$WORK/work/run.h5.tmp" 2>/dev/null)" = keep ] || fail "a user's run.h5.tmp was replaced or deleted"
cp "$WORK/minimal/run.h5" "$WORK/bed_copy.h5"
# (the quick pull-off's walls stand where the minimal scene's grains lie: accepted, so that the folder is what is refused)
printf 'allow_initial_overlap = true\n' >"$WORK/accept_overlap.toml"
expect 2 "holds the run this one starts from (--initial" -- \
  "$DEM2D" run "$TESTS/scenes/quick_pulloff.toml" --overlay "$WORK/accept_overlap.toml" --initial "$WORK/minimal/run.h5" --out "$WORK/minimal"
cmp -s "$WORK/minimal/run.h5" "$WORK/bed_copy.h5" || fail "the bed a run starts from was replaced"
mkdir -p "$WORK/minimal/beds" && cp "$WORK/bed_copy.h5" "$WORK/minimal/beds/bed.h5"
expect 2 "holds the run this one starts from (--initial" -- \
  "$DEM2D" run "$TESTS/scenes/quick_pulloff.toml" --overlay "$WORK/accept_overlap.toml" --initial "$WORK/minimal/beds/bed.h5" \
  --out "$WORK/minimal"
cmp -s "$WORK/minimal/beds/bed.h5" "$WORK/bed_copy.h5" || fail "a bed inside --out was touched"
# a bed whose last snapshot has no grain left in the domain: that is what is said, not "no particles"
cp "$WORK/bed_copy.h5" "$WORK/emptied.h5"
$PY -c 'import h5py, sys; f = h5py.File(sys.argv[1], "r+"); f["snapshots/active"][-1, :] = 0' "$WORK/emptied.h5"
expect 2 "cannot start from it: its last snapshot (step [0-9]*) has no active grain: all [0-9]* left the domain" -- \
  "$DEM2D" run "$TESTS/scenes/quick_pulloff.toml" --initial "$WORK/emptied.h5" --out "$WORK/from_emptied"

# reference: the pour, uninterrupted
SCENE=$TESTS/scenes/pour_resume.toml
expect 0 "run.h5" -- "$DEM2D" run "$SCENE" --out "$WORK/ref" --threads 1

# progress when stderr is not a terminal (a batch job): plain lines every --progress seconds,
# the same in DIR/run.log; none with --progress 0
"$DEM2D" run "$SCENE" --out "$WORK/progress" --threads 1 --progress 0.05 2>"$WORK/progress.err" >/dev/null
grep -Eq '^\[dem2d\] t = [0-9.e+-]+ s  step [0-9]+  [0-9.]+ % of [0-9.]+ s \(the duration\) .* ETA [0-9]+:[0-9]{2}:[0-9]{2}  KE [0-9.e+-]+ J/m  contacts/grain [0-9.e+-]+  max overlap/d [0-9.e+-]+  lost [0-9]+$' \
  "$WORK/progress.err" || fail "no progress line on stderr: $(head -3 "$WORK/progress.err")"
[ "$(grep -c ' t = .* ETA ' "$WORK/progress/run.log")" -eq "$(grep -c '^\[dem2d\] t = ' "$WORK/progress.err")" ] ||
  fail "run.log and stderr disagree on the progress lines"
"$DEM2D" run "$SCENE" --out "$WORK/quiet" --threads 1 --progress 0 2>"$WORK/quiet.err" >/dev/null
grep -q '^\[dem2d\] t = ' "$WORK/quiet.err" && fail "--progress 0 still printed progress lines"

# two runs into one folder: the second is refused, naming the first's pid, and the first completes
"$DEM2D" run "$SCENE" --out "$WORK/twice" --threads 1 >/dev/null 2>&1 &
first=$!
for _ in $(seq 100); do [ -e "$WORK/twice/.run.work" ] && break; sleep 0.05; done
expect 2 "another dem2d run (pid $first) is writing into this folder" -- "$DEM2D" run "$SCENE" --out "$WORK/twice" --threads 1
wait "$first" || fail "the first of two runs into one folder failed"
$CHECK "$WORK/twice/run.h5" --same-as "$WORK/ref/run.h5" >/dev/null || fail "the first of two runs into one folder differs"

# start_and_signal SIGNAL DIR [THREADS]: runs the pour into DIR in the background
# (one thread unless THREADS: no test asks for cores it is not testing) and
# sends SIGNAL once its first checkpoint exists; leaves its exit code in $rc
start_and_signal() {
  "$DEM2D" run "$SCENE" --out "$2" --threads "${3:-1}" 2>"$2.err" &
  local pid=$!
  for _ in $(seq 400); do [ -e "$2/.run.work/checkpoint.h5" ] && break; sleep 0.025; done
  kill -"$1" $pid 2>/dev/null
  wait $pid 2>/dev/null  # (no "Killed" notice from the shell)
  rc=$?
}

# SIGKILL after the first checkpoint, then resume with another thread count
start_and_signal KILL "$WORK/killed" 2
if [ -e "$WORK/killed/run.h5" ]; then
  fail "the run finished before it could be killed: the SIGKILL case was not exercised"
else
  [ -e "$WORK/killed/.run.work/checkpoint.h5" ] || fail "no checkpoint before SIGKILL"
  expect 0 "(resumed)" -- "$DEM2D" run "$SCENE" --out "$WORK/killed" --threads 1
  $CHECK "$WORK/killed/run.h5" --same-as "$WORK/ref/run.h5" >/dev/null || fail "run resumed after SIGKILL differs"
fi

# SIGTERM: checkpoint and exit 3, then resume
start_and_signal TERM "$WORK/term"
if [ -e "$WORK/term/run.h5" ]; then
  fail "the run finished before SIGTERM: the case was not exercised"
else
  [ "$rc" -eq 3 ] || fail "SIGTERM: exit $rc, expected 3"
  grep -q "interrupted at step" "$WORK/term.err" || fail "SIGTERM: no message: $(cat "$WORK/term.err")"
  # the checkpoint as a starting state with a changed setting (LAMMPS's read_restart, then new settings)
  cp "$WORK/term/.run.work/checkpoint.h5" "$WORK/term_checkpoint.h5"
  sed -e '/^\[\[generator\]\]/,/^region/d' -e 's/^friction = 0.5/friction = 0.2/' -e 's/^duration = 0.3/duration = 0.05/' \
    "$SCENE" >"$WORK/go_on.toml"
  expect 0 "run.h5" -- "$DEM2D" run "$WORK/go_on.toml" --initial "$WORK/term_checkpoint.h5" --out "$WORK/go_on"
  $PY -c 'import h5py, sys; a = h5py.File(sys.argv[1]).attrs; sys.exit(not (a["initial_source"].startswith("checkpoint at step ")
          and a["initial_run"] == sys.argv[2] and len(a["initial_digest"]) == 16))' "$WORK/go_on/run.h5" "$WORK/term_checkpoint.h5" ||
    fail "the run from a checkpoint does not say where it started"
  expect 0 "(resumed)" -- "$DEM2D" run "$SCENE" --out "$WORK/term"
  $CHECK "$WORK/term/run.h5" --same-as "$WORK/ref/run.h5" >/dev/null || fail "run resumed after SIGTERM differs"
fi

# a full disk (here a file-size limit): a clean error (exit 1, not a crash),
# no run.h5; the rerun without the limit finishes, the same as uninterrupted
( ulimit -f 100; trap '' XFSZ; exec "$DEM2D" run "$SCENE" --out "$WORK/full" --threads 1 ) >"$WORK/full.out" 2>"$WORK/full.err"
rc=$?
[ "$rc" -eq 1 ] || fail "full disk: exit $rc, expected 1: $(tail -3 "$WORK/full.err")"
grep -q "is the disk full?" "$WORK/full.err" || fail "full disk: no message: $(tail -3 "$WORK/full.err")"
[ -e "$WORK/full/run.h5" ] && fail "full disk: a run.h5 exists"
expect 0 "run.h5" -- "$DEM2D" run "$SCENE" --out "$WORK/full" --threads 1
$CHECK "$WORK/full/run.h5" --same-as "$WORK/ref/run.h5" >/dev/null || fail "the run after a full disk differs"

# --fresh discards the checkpoint of another scene; without it, a clear refusal
start_and_signal TERM "$WORK/other"
if [ -e "$WORK/other/.run.work/checkpoint.h5" ]; then
  sed 's/seed = 11/seed = 12/' "$SCENE" >"$WORK/other.toml"
  expect 1 "different scene" -- "$DEM2D" run "$WORK/other.toml" --out "$WORK/other"
  expect 0 "run.h5" -- "$DEM2D" run "$WORK/other.toml" --out "$WORK/other" --fresh
else
  fail "no checkpoint of the interrupted run: the case of another scene was not exercised"
fi

[ "$failures" -eq 0 ] && echo "cli tests: all passed"
exit $((failures > 0))
