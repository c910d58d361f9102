#!/bin/sh
# SPDX-License-Identifier: MIT
#
# build.sh BUILD_DIR SOURCE_DIR [CORE]
#
# Configure (once) and build the Cortex-M project tests/target into
# BUILD_DIR/m4f with port/cortex-m4f/toolchain.cmake and -DSFIT_WERROR=ON.
# CORE (SFIT_ARM_CORE of the toolchain file): cortex-m4f (default, into
# BUILD_DIR/m4f), cortex-m33 (BUILD_DIR/m33) or cortex-m3 (BUILD_DIR/m3).
# Shared by tests/scripts/test_m4f_*.sh and tools/flopcount/run.sh; a lock
# (flock on BUILD_DIR/m4f.lock) serialises concurrent callers (ctest -j).
# The compiler output of this build is kept in BUILD_DIR/m4f/build.log.
#
# Exit status: 0 built; 1 configure/build failed (or any warning);
# 77 arm-none-eabi-gcc (or cmake) missing and CI is not "true" -- in CI a
# missing tool is a failure.
set -u
if [ $# -lt 2 ]; then
    echo "usage: $0 BUILD_DIR SOURCE_DIR" >&2
    exit 2
fi
build=$1
src=$(cd "$2" && pwd)
core=${3:-cortex-m4f}
case $core in
cortex-m4f) sub=m4f ;;
cortex-m33) sub=m33 ;;
cortex-m3) sub=m3 ;;
*) echo "build.sh: unknown core '$core' (cortex-m4f, cortex-m33, cortex-m3)" >&2; exit 2 ;;
esac
out="$build/$sub"

missing=""
for t in arm-none-eabi-gcc arm-none-eabi-nm arm-none-eabi-objdump arm-none-eabi-size cmake; do
    command -v "$t" >/dev/null 2>&1 || missing="$missing $t"
done
if [ -n "$missing" ]; then
    if [ "${CI:-}" = "true" ]; then
        echo "build.sh: FAIL: missing tool(s):$missing (CI=true)" >&2
        exit 1
    fi
    echo "build.sh: SKIP: missing tool(s):$missing (Debian: gcc-arm-none-eabi binutils-arm-none-eabi libnewlib-arm-none-eabi)" >&2
    exit 77
fi

mkdir -p "$out"
run_locked() {
    if [ ! -f "$out/CMakeCache.txt" ]; then
        cmake -S "$src/tests/target" -B "$out" \
            -DCMAKE_TOOLCHAIN_FILE="$src/port/cortex-m4f/toolchain.cmake" \
            -DSFIT_SOURCE_DIR="$src" -DSFIT_WERROR=ON -DSFIT_ARM_CORE="$core" \
            -DCMAKE_BUILD_TYPE=RelWithDebInfo >"$out/configure.log" 2>&1 || {
            cat "$out/configure.log" >&2
            rm -f "$out/CMakeCache.txt"
            return 1
        }
    fi
    cmake --build "$out" -j2 >"$out/build.log" 2>&1
    rc=$?
    if [ "$rc" -ne 0 ]; then
        cat "$out/build.log" >&2
        echo "build.sh: FAIL: the $core build failed (log: $out/build.log)" >&2
        return 1
    fi
    if grep -n 'warning:' "$out/build.log" >&2; then
        echo "build.sh: FAIL: warnings in the $core build (log: $out/build.log)" >&2
        return 1
    fi
    return 0
}

if command -v flock >/dev/null 2>&1; then
    (
        flock 9
        run_locked
    ) 9>"$build/$sub.lock"
else
    run_locked
fi
