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
# double-precision code is in the library, that the runner's last line is
# "N passed, 0 failed" with status 0, and the footprint checks of
# tools/flopcount/footprint.sh (without the M4F byte budgets).
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
if [ "$core" = cortex-m3 ]; then
    # Control: the board really has no FPU, so an FPU build of the port's
    # smoke program must fault there (status 100 + exception number).
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT INT TERM
    q="$src/port/cortex-m4f/qemu"
    arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -std=c99 -O2 \
        -I"$src/port/cortex-m4f" "$q/startup.c" "$q/smoke.c" --specs=nano.specs --specs=rdimon.specs \
        -L"$q" -T "$q/mps2_an386.ld" -lm -o "$tmp/fpu.elf" || { echo "$name: FAIL: control build" >&2; exit 1; }
    "$q/run.sh" -M "$machine" "$tmp/fpu.elf" >"$tmp/fpu.out" 2>&1
    crc=$?
    if [ "$crc" -lt 100 ]; then
        echo "$name: FAIL: an FPU program ran on $machine (status $crc): no proof of soft float" >&2
        exit 1
    fi
    echo "$name: control: an FPU build faults on $machine (status $crc)"
fi
out=$("$src/port/cortex-m4f/qemu/run.sh" -M "$machine" "$elf" 2>&1)
rc=$?
printf '%s\n' "$out"
last=$(printf '%s\n' "$out" | tail -n 1)
if ! printf '%s\n' "$last" | grep -Eq '^[1-9][0-9]* passed, 0 failed$'; then
    echo "$name: FAIL: last line is '$last' (status $rc)" >&2
    exit 1
fi
[ "$rc" -eq 0 ] || { echo "$name: FAIL: status $rc" >&2; exit 1; }
# The footprint checks hold on this core too (no heap, no static data, no
# double, a static stack bound for every public function, soft-float and
# libm routines included); the byte budgets are the Cortex-M4F's only.
fpout=$("$src/tools/flopcount/footprint.sh" "$dir" /dev/null)
rc=$?
printf '%s\n' "$fpout" | grep '^check' | grep -v '^check budget'
if [ "$rc" -ne 0 ] || printf '%s\n' "$fpout" | grep -q '^check .* FAIL'; then
    echo "$name: FAIL: footprint checks" >&2
    exit 1
fi
# The rest of the cross project's tests (the FLOP driver smoke run), on the
# same board (CMAKE_CROSSCOMPILING_EMULATOR = run.sh -M <board>).
ctest --test-dir "$dir" --output-on-failure -E '^sfit\.target$' || exit 1
echo "$name: $last on QEMU $machine ($arch, FPU: $fp)"
