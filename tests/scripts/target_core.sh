#!/bin/sh
# SPDX-License-Identifier: MIT
#
# target_core.sh CORE BUILD_DIR SOURCE_DIR
#
# The on-target tests (tests/target: the known-answer and invariant suites,
# and the FLOP-count driver as a smoke run) built for a Cortex-M core with
# port/cortex-m4f/toolchain.cmake (SFIT_ARM_CORE=CORE: cortex-m4f,
# cortex-m33, cortex-m3; tests/target/build.sh -> BUILD_DIR/<m4f|m33|m3>)
# and run under that core's QEMU board (core.txt). Checks that the ELF is built for
# that core (readelf build attributes: architecture, FPU or none), that no
# double-precision code is in the library, and that the runner's last line
# is "N passed, 0 failed" with status 0.
# Called by test_m4f_target.sh, test_m33_target.sh and test_m3_target.sh (ctest).
# Exit 77 (skip) only when a tool is missing and CI != "true".
set -u
core=$1
build=$2
src=$3
name="target_core($core)"
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
for t in qemu-system-arm arm-none-eabi-readelf; do
    command -v "$t" >/dev/null 2>&1 || missing "$t not found"
done
"$src/tests/target/build.sh" "$build" "$src" "$core"
rc=$?
[ "$rc" -eq 0 ] || exit "$rc"
case $core in
cortex-m4f) dir="$build/m4f"; want_arch="v7E-M"; want_fp=yes ;;
cortex-m33) dir="$build/m33"; want_arch="v8-M.mainline"; want_fp=yes ;;
cortex-m3) dir="$build/m3"; want_arch="v7"; want_fp=no ;;
*) echo "$name: FAIL: unknown core" >&2; exit 2 ;;
esac
elf="$dir/sfit_target_tests.elf"
machine=$(awk '$1 == "machine" { print $2 }' "$dir/core.txt")
attrs=$(arm-none-eabi-readelf -A "$elf")
arch=$(printf '%s\n' "$attrs" | sed -n 's/^ *Tag_CPU_arch: //p')
[ "$arch" = "$want_arch" ] || { echo "$name: FAIL: $elf is built for '$arch', not $want_arch" >&2; exit 1; }
if printf '%s\n' "$attrs" | grep -q 'Tag_FP_arch'; then fp=yes; else fp=no; fi
[ "$fp" = "$want_fp" ] || { echo "$name: FAIL: FPU attribute '$fp', expected $want_fp" >&2; exit 1; }
"$src/tests/target/check_double.sh" "$dir/sfit/lib/libsfit.a" || exit 1
out=$("$src/port/cortex-m4f/qemu/run.sh" -M "$machine" "$elf" 2>&1)
rc=$?
printf '%s\n' "$out"
last=$(printf '%s\n' "$out" | tail -n 1)
if ! printf '%s\n' "$last" | grep -Eq '^[1-9][0-9]* passed, 0 failed$'; then
    echo "$name: FAIL: last line is '$last' (status $rc)" >&2
    exit 1
fi
[ "$rc" -eq 0 ] || { echo "$name: FAIL: status $rc" >&2; exit 1; }
# The rest of the cross project's tests (the FLOP driver smoke run), on the
# same board (CMAKE_CROSSCOMPILING_EMULATOR = run.sh -M <board>).
ctest --test-dir "$dir" --output-on-failure -E '^sfit\.target$' || exit 1
echo "$name: $last on QEMU $machine ($arch, FPU: $fp)"
