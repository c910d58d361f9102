#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m4f_target.sh BUILD_DIR SOURCE_DIR
#
# Runs the on-target tests (tests/target, Cortex-M4F hard float) under
# qemu-system-arm -M mps2-an386 through the cross project's ctest
# (BUILD_DIR/m4f): sfit.target (known-answer and invariant tests, ending
# with "N passed, N failed") and sfit.target.flopdrv (every operation of the
# FLOP-count driver returns SFIT_OK).
# Exit 77 (skip) only when a tool is missing and CI != "true".
set -u
build=$1
src=$2
if ! command -v qemu-system-arm >/dev/null 2>&1; then
    if [ "${CI:-}" = "true" ]; then
        echo "test_m4f_target: FAIL: qemu-system-arm missing (CI=true)" >&2
        exit 1
    fi
    echo "test_m4f_target: SKIP: qemu-system-arm missing" >&2
    exit 77
fi
"$src/tests/target/build.sh" "$build" "$src"
rc=$?
[ "$rc" -eq 0 ] || exit "$rc"
m4f="$build/m4f"
out=$("$src/port/cortex-m4f/qemu/run.sh" "$m4f/sfit_target_tests.elf" 2>&1)
rc=$?
printf '%s\n' "$out"
last=$(printf '%s\n' "$out" | tail -n 1)
if ! printf '%s\n' "$last" | grep -Eq '^[0-9]+ passed, 0 failed$'; then
    echo "test_m4f_target: FAIL: last line is '$last' (status $rc)" >&2
    exit 1
fi
[ "$rc" -eq 0 ] || { echo "test_m4f_target: FAIL: status $rc" >&2; exit 1; }
# The rest of the cross project's tests (the driver smoke run).
ctest --test-dir "$m4f" --output-on-failure -E '^sfit\.target$' || exit 1
