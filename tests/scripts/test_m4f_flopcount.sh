#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m4f_flopcount.sh BUILD_DIR SOURCE_DIR
#
# tools/flopcount/run.sh --json on the emulated Cortex-M4F: every operation
# the issue names is listed, and no FLOP count exceeds its budget
# (tools/flopcount/budget.txt; moments_add <= 30, incremental_update <= 123),
# the batch accumulator (moments_add_batch) takes at most 64 M4F
# instructions per sample and the screened solve at N = 500
# (solve_gdke_500) at most 800.
# Also checks that a budget violation is detected (a budget file with a
# limit below the measured count must fail).
# Exit 77 (skip) only when a tool is missing and CI != "true".
set -u
build=$1
src=$2
tool="$src/tools/flopcount/run.sh"
json=$("$tool" --build-dir "$build" --json)
rc=$?
printf '%s\n' "$json"
[ "$rc" -eq 77 ] && exit 77
fail=0
[ "$rc" -eq 0 ] || { echo "test_m4f_flopcount: FAIL: run.sh exited $rc (budget or footprint)" >&2; fail=1; }
for op in moments_add moments_add_batch batch_per_point solve_gdke solve_gdke_500 solve_ugdk chol_solve jacobi_eig planar_solve \
    multi_solve_per_marker incremental_update noise_calibration; do
    if ! printf '%s\n' "$json" | grep -q "{\"name\": \"$op\", "; then
        echo "test_m4f_flopcount: FAIL: operation $op missing from --json" >&2
        fail=1
    fi
done
# Instruction limits (M4F instructions, not FLOPs): the batch accumulator
# at most 64 per sample amortised; the screened solve at N = 500 (an open
# block) at most 800; the joint between two IMUs at most 2000 per sample,
# in the steady state and for the sample that fills its buffer (docs/imu.md).
insns() {
    printf '%s\n' "$json" | sed -n "s/.*{\"name\": \"$1\", .*\"insns\": \([0-9.]*\),.*/\1/p"
}
for lim in moments_add_batch:64 solve_gdke_500:800 imu_add:2000 imu_add_compact:2000; do
    op=${lim%%:*}
    max=${lim#*:}
    got=$(insns "$op")
    if [ -z "$got" ] || ! awk -v g="$got" -v m="$max" 'BEGIN { exit !(g <= m) }'; then
        echo "test_m4f_flopcount: FAIL: $op: ${got:-no figure} M4F instructions > $max" >&2
        fail=1
    else
        echo "test_m4f_flopcount: $op: $got M4F instructions <= $max"
    fi
done
# The budget check must be able to fail: halve every budget.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
awk '/^[a-z]/ { $2 = $2 / 2 } { print }' "$src/tools/flopcount/budget.txt" >"$tmp/budget.txt"
out="$build/m4f"
if awk -v mode=text -f "$src/tools/flopcount/report.awk" "$out/fc.out" "$out/fc.win" "$tmp/budget.txt" \
    "$out/footprint.txt" >/dev/null 2>&1; then
    echo "test_m4f_flopcount: FAIL: halved budgets were not reported as exceeded" >&2
    fail=1
fi
exit "$fail"
