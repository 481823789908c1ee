#!/usr/bin/env bash
# make install into a temporary prefix, then the installed programs used from
# there: they find their data and code version beside themselves
# (share/dem2d), not in the source or build tree, and no source-tree path is
# compiled into them.   tests/install_test.sh BUILD_DIR [paths|no-paths]
# (no-paths: a debug or sanitizer build, whose debug information names the
# sources by design: the path check is left out, and said so)
set -uo pipefail
unset DEM2D_SHARE  # (the programs must find their own)
BUILD=$(realpath "$1")
SRC=$(cd "$(dirname "$0")/.." && pwd)
P=$(mktemp -d /tmp/dem2d_install.XXXXXX)
trap 'rm -rf "$P"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cmake --install "$BUILD" --prefix "$P/prefix" >"$P/install.log" 2>&1 || { cat "$P/install.log"; exit 1; }
# moved after installing: a relocated installation must work too
mv "$P/prefix" "$P/moved"
I=$P/moved
# every stage of the registry: its program and its settings file (pipeline/stages.toml)
registered=$(cd "$SRC" && ${PYTHON:-/usr/bin/python3} -c 'from pipeline import stages
print(" ".join(sorted({f"libexec/dem2d/{s.program}" for s in stages.load()}
                      | {f"share/dem2d/{s.config}" for s in stages.load() if s.config})))') ||
  { echo "FAIL: the stage registry cannot be read"; exit 1; }
[ -n "$registered" ] || { echo "FAIL: the stage registry lists no stage"; exit 1; }
for f in bin/dem2d $registered share/dem2d/data/study.toml share/dem2d/data/bench/settled_bed.toml \
  share/dem2d/code_version.txt share/dem2d/python/dem2d/run.py share/dem2d/python/dem2d/run_file_schema.json; do
  [ -e "$I/$f" ] || fail "not installed: $f"
done
"$I/bin/dem2d" bench --help | grep -q -- "--scene TEXT=$I/share/dem2d/data/bench/settled_bed.toml" ||
  fail "dem2d bench's default scene is not the installed one: $("$I/bin/dem2d" bench --help | grep -- --scene)"
"$I/libexec/dem2d/cg" --help | grep -q -- "--config TEXT=$I/share/dem2d/data/cg.toml" ||
  fail "cg's default settings are not the installed ones: $("$I/libexec/dem2d/cg" --help | grep -- --config)"
if [ "${2:-paths}" = paths ]; then
  for f in "$I"/bin/dem2d "$I"/libexec/dem2d/*; do
    grep -q -a -F "$SRC/" "$f" && fail "$f holds the source path $SRC/"
    grep -q -a -F "$BUILD/" "$f" && fail "$f holds the build path $BUILD/"
  done
else
  echo "install_test: NOT checked that the binaries hold no source path (a debug/sanitizer build names its sources)"
fi
cd "$P" && "$I/bin/dem2d" run "$SRC/tests/scenes/valid_minimal.toml" --out "$P/run" >"$P/run.log" 2>&1 ||
  fail "the installed dem2d did not run a scene: $(tail -3 "$P/run.log")"
# sets that no line of sim/engine/kernel_sets.inc declares run too (on the generic kernel), and say so
MIN="$SRC/tests/scenes/valid_minimal.toml"
sed -e '/^normal_damping = true/d' -e '/^restitution = /d' "$MIN" >"$P/undamped.toml"  # {gravity,friction,walls}
sed -e 's/^walls = true/walls = true\ncohesion = true/' -e 's/^friction = 0.5/friction = 0.5\ncohesion_force = 0.02\ncohesion_range = 1e-4/' \
  "$MIN" >"$P/cohesive.toml"  # {gravity,normal_damping,friction,walls,cohesion}
sed -e 's/^walls = true/walls = true\nrolling_resistance = true\ntangential_damping = true/' \
  -e 's/^friction = 0.5/friction = 0.5\nrolling_friction = 1.5e-5\nrolling_stiffness = 1.7e-6\ntangential_damping_ratio = 0.3/' \
  "$MIN" >"$P/rolling.toml"  # {gravity,normal_damping,friction,rolling_resistance,walls,tangential_damping}
for s in undamped cohesive rolling; do
  "$I/bin/dem2d" check "$P/$s.toml" >"$P/$s.check" 2>&1 && grep -q "runs on the generic kernel for {" "$P/$s.check" ||
    fail "the installed dem2d check of an undeclared set ($s): $(cat "$P/$s.check")"
  "$I/bin/dem2d" run "$P/$s.toml" --out "$P/$s" >"$P/$s.log" 2>&1 && [ -s "$P/$s/run.h5" ] &&
    grep -q "generic kernel for {" "$P/$s/run.log" || fail "the installed dem2d run of an undeclared set ($s): $(tail -3 "$P/$s.log")"
done
version=$(${PYTHON:-/usr/bin/python3} -c 'import h5py, sys; print(h5py.File(sys.argv[1], "r").attrs["code_version"])' \
  "$P/run/run.h5" 2>&1) || fail "cannot read the installed run's code version: $version"
case $version in *+unknown | "") fail "the installed dem2d has no code version: '$version'" ;; esac
# the Python reader, installed: reads the installed dem2d's run
PYTHONPATH="$I/share/dem2d/python" ${PYTHON:-/usr/bin/python3} -c '
import sys, dem2d
with dem2d.open_run(sys.argv[1]) as run:
    assert run.n_particles > 0 and len(run) > 0 and run.units("contacts/fn") == "N/m", run
' "$P/run/run.h5" 2>"$P/python.err" || fail "the installed Python reader: $(tail -3 "$P/python.err")"
# its own data missing: an error naming where they belong and DEM2D_SHARE, never another installation's
# share above the prefix or ./share in the current folder (both were taken, with their code version)
mkdir -p "$P/share/dem2d/data" "$P/cwd/share/dem2d/data"
cp "$I/share/dem2d/data/"*.toml "$P/share/dem2d/data/" && cp "$I/share/dem2d/data/"*.toml "$P/cwd/share/dem2d/data/"
mv "$I/share" "$I/share.away"
for cmd in "$I/bin/dem2d check $SRC/tests/scenes/valid_minimal.toml" "$I/libexec/dem2d/spectrum $P/run/run.h5 --out $P/sp"; do
  out=$(cd "$P/cwd" && $cmd 2>&1); rc=$?
  [ "$rc" -eq 2 ] || fail "$cmd without its share/ exited $rc, expected 2: $out"
  grep -qF "no $I/share/dem2d/data, where its installation" <<<"$out" && grep -qF DEM2D_SHARE <<<"$out" ||
    fail "$cmd without its share/ said: $out"
done
DEM2D_SHARE="$I/share.away/dem2d" "$I/bin/dem2d" check "$SRC/tests/scenes/valid_minimal.toml" >/dev/null 2>&1 ||
  fail "DEM2D_SHARE did not name the share/ to use"
# its code version read bounded from a regular file: a device, a pipe or a long file is not read (a link to
# /dev/zero aborted every program, even --version; a pipe blocked it; 20 MB were stamped into run files)
cp -r "$P/share/dem2d" "$P/vshare"
for damage in "ln -s /dev/zero" "mkfifo" "head -c 20000000 /dev/urandom >"; do
  rm -f "$P/vshare/code_version.txt"
  case $damage in ln*) ln -s /dev/zero "$P/vshare/code_version.txt" ;; mkfifo) mkfifo "$P/vshare/code_version.txt" ;;
    *) head -c 20000000 /dev/urandom >"$P/vshare/code_version.txt" ;; esac
  out=$(DEM2D_SHARE="$P/vshare" timeout 20 "$I/bin/dem2d" --version 2>&1); rc=$?
  [ "$rc" -eq 0 ] && [[ $out == *+unknown* ]] && [ ${#out} -lt 200 ] ||
    fail "dem2d --version with code_version.txt made by '$damage': exit $rc: ${out:0:200}"
done
out=$(DEM2D_SHARE="$P/cwd" "$I/bin/dem2d" check "$SRC/tests/scenes/valid_minimal.toml" 2>&1); rc=$?
[ "$rc" -eq 2 ] && grep -qF "DEM2D_SHARE=$P/cwd holds no data/ folder" <<<"$out" ||
  fail "DEM2D_SHARE naming a folder without data/ gave exit $rc: $out"
mv "$I/share.away" "$I/share"
# another project: find_package(dem2d) from the (moved) prefix, link the engine, run a scene, read it back
for f in lib/libdem2d_core.a lib/libdem2d_runfile.a lib/cmake/dem2d/dem2dConfig.cmake include/dem2d/run/run.hpp \
  include/dem2d/runfile/run_reader.hpp; do
  [ -e "$I/$f" ] || fail "not installed: $f"
done
if cmake -S "$SRC/tests/install_consumer" -B "$P/consumer" -DCMAKE_PREFIX_PATH="$I" -DCMAKE_BUILD_TYPE=Release \
     >"$P/consumer.log" 2>&1 && cmake --build "$P/consumer" -j 2 >>"$P/consumer.log" 2>&1; then
  out=$("$P/consumer/consumer" "$SRC/tests/scenes/valid_minimal.toml" "$P/consumer_run" 2>&1) ||
    fail "the consumer of find_package(dem2d) failed: $out"
  echo "$out" | grep -q "^consumer: [1-9][0-9]* particles, [1-9][0-9]* snapshots" || fail "consumer said: $out"
else
  fail "find_package(dem2d) and a build against it failed: $(grep -A6 -i error "$P/consumer.log" | head -30)"
fi
[ "$failures" -eq 0 ] && echo "install_test: all checks passed ($I)" || echo "install_test: $failures failed"
[ "$failures" -eq 0 ]
