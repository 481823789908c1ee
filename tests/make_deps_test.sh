#!/usr/bin/env bash
# make deps on a machine missing a package, from an account that is not root
# and has no sudo: it needs nothing it installs (no generated rules, no
# build), exits 2 and prints the one command an administrator runs; a build
# there stops the same way (never "sudo: command not found"). As root the
# checks run as the account nobody. Usage: make_deps_test.sh SOURCE_DIR
# Exit 0: passed; 1: failed; 77: skipped (said loudly).
set -uo pipefail
SRC=$(cd "$1" && pwd)
command -v dpkg >/dev/null || { echo "make_deps_test: SKIPPED: not Debian (no dpkg): make deps checks nothing here"; exit 77; }
W=$(mktemp -d /tmp/dem2d_deps.XXXXXX)
trap 'rm -rf "$W"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# a clone's files (no build/), readable by the unprivileged account
git -C "$SRC" ls-files -z | (cd "$SRC" && xargs -0 cp --parents -t "$W") 2>/dev/null || cp -r "$SRC/." "$W"
rm -rf "$W/build" "$W/results"
chmod -R a+rX "$W"
as_user() { if [ "$(id -u)" -eq 0 ]; then setpriv --reuid=65534 --regid=65534 --clear-groups "$@"; else "$@"; fi; }
MISSING=no-such-package-dem2d-test

out=$(cd "$W" && as_user make --no-print-directory deps DEBIAN_PACKAGES="$MISSING make" TEST_PACKAGES= SUDO= 2>&1); rc=$?
[ "$rc" -eq 2 ] || fail "make deps with a package missing, no root, no sudo: exit $rc (expected 2): $out"
grep -qxF "  an administrator installs them with: apt-get install -y --no-install-recommends $MISSING" <<<"$out" ||
  fail "make deps does not print the administrator's command: $out"
grep -q "sudo: command not found\|stages.py\|registries" <<<"$out" && fail "make deps needed more than itself: $out"
[ -e "$W/build" ] && fail "make deps wrote $W/build"

out=$(cd "$W" && as_user make --no-print-directory build DEBIAN_PACKAGES="$MISSING" SUDO= 2>&1); rc=$?
[ "$rc" -eq 2 ] || fail "make build with a package missing: exit $rc (expected 2): $out"
grep -qF "apt-get install -y --no-install-recommends $MISSING" <<<"$out" || fail "make build does not name the command: $out"
grep -q "command not found" <<<"$out" && fail "make build: $out"

out=$(cd "$W" && as_user make --no-print-directory deps DEBIAN_PACKAGES=make TEST_PACKAGES= SUDO= 2>&1); rc=$?
[ "$rc" -eq 0 ] && grep -q "make deps: nothing missing" <<<"$out" || fail "make deps with nothing missing: exit $rc: $out"

[ "$failures" -eq 0 ] && echo "make_deps_test: all checks passed" || echo "make_deps_test: $failures failed"
[ "$failures" -eq 0 ]
