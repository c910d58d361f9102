#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The README's demo needs only CMake and a C compiler: with cmocka absent,
# the default preset configures (with a message saying the tests are not
# built and how to get cmocka), builds the library and the sfit tool, and
# the tool runs the demo. cmocka is made absent by hiding both ways the
# tests look for it: its CMake package (-DCMAKE_DISABLE_FIND_PACKAGE_cmocka=ON)
# and its pkg-config file (PKG_CONFIG_LIBDIR pointing to an empty directory).
# With -DSFIT_TESTS_REQUIRE_CMOCKA=ON (the ci preset) the same configure fails.
# Usage: test_no_cmocka.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd)
name=test_no_cmocka
work="$build/no_cmocka"
rm -rf "$work"
mkdir -p "$work/empty-pc"
fail() { echo "$name: FAIL: $*" >&2; exit 1; }
hide=(env PKG_CONFIG_LIBDIR="$work/empty-pc" PKG_CONFIG_PATH=)

cd "$src"
"${hide[@]}" cmake --preset default -B "$work/b" -DCMAKE_DISABLE_FIND_PACKAGE_cmocka=ON \
  >"$work/configure.log" 2>&1 || { cat "$work/configure.log" >&2; fail "configure without cmocka"; }
grep -q 'cmocka not found: the tests are not built' "$work/configure.log" \
  || { cat "$work/configure.log" >&2; fail "no message about the missing cmocka"; }
grep -q 'libcmocka-dev' "$work/configure.log" || fail "the message does not say how to get cmocka"
cmake --build "$work/b" -j2 >"$work/build.log" 2>&1 || { cat "$work/build.log" >&2; fail "build without cmocka"; }
[ -x "$work/b/bin/sfit" ] || fail "no bin/sfit"
if find "$work/b" -name 'test_*' -type f -perm -u+x | grep -q .; then fail "test executables built without cmocka"; fi
out=$("$work/b/bin/sfit" fit --json "$src/tests/data/mocap/hip_right/RTHI1.csv")
printf '%s\n' "$out" | grep -q '"status":"ok"' || fail "sfit fit: $out"
"$work/b/bin/sfit" joint "$src/tests/data/c3d/biobuddy_right_hip.c3d" --parent RASIS,LASIS,LPSIS,RPSIS \
  --child RTHI1,RTHI2,RTHI3,RLFE,RMFE --frames 0:498 | grep -q '^centre' || fail "the README demo"
echo "without cmocka: configure warns, library and sfit tool build, the README demo runs"

if "${hide[@]}" cmake -S "$src" -B "$work/req" -DCMAKE_DISABLE_FIND_PACKAGE_cmocka=ON \
  -DSFIT_TESTS_REQUIRE_CMOCKA=ON >"$work/req.log" 2>&1; then
  fail "SFIT_TESTS_REQUIRE_CMOCKA=ON configured without cmocka"
fi
grep -q 'cmocka not found' "$work/req.log" || fail "required-cmocka failure without the message"
echo "with SFIT_TESTS_REQUIRE_CMOCKA=ON (ci preset) the configure fails, naming cmocka"
echo "$name: ok"
