#!/bin/sh
# SPDX-License-Identifier: MIT
#
# tools/flopcount/cores.sh [--update-docs] [--build-dir DIR] [--no-build] [--mhz N]
#
# The cost table per core: the FLOP-count driver and the footprint of
# tests/target built for each core of port/cortex-m4f/toolchain.cmake
# (SFIT_ARM_CORE: cortex-m4f, cortex-m33, cortex-m3; tests/target/build.sh
# into DIR/m4f, DIR/m33, DIR/m3) and run on its QEMU board (count.sh):
# FLOPs (VFP arithmetic instructions; none on the M3, where float is
# emulated by libgcc), executed instructions (the library and every
# C-library / soft-float routine it calls), code size and worst-case stack.
# Prints the Markdown block; --update-docs rewrites it between
# <!-- cores:begin --> and <!-- cores:end --> in docs/cost.md.
# --mhz: the clock assumed for the soft-float 100 Hz figure (default 32).
# Exit status: 0; 1 when a build or a driver run fails; 77 when a tool is
# missing and CI is not "true".
set -u
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
build="$src/build"
update=0
mhz=32
dobuild=1
while [ $# -gt 0 ]; do
    case $1 in
    --update-docs) update=1 ;;
    --build-dir) build=$2; shift ;;
    --mhz) mhz=$2; shift ;;
    --no-build) dobuild=0 ;;
    -h | --help) sed -n '3,19p' "$0"; exit 0 ;;
    *) echo "cores.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
if ! command -v qemu-system-arm >/dev/null 2>&1; then
    [ "${CI:-}" = "true" ] && { echo "cores.sh: FAIL: qemu-system-arm missing" >&2; exit 1; }
    echo "cores.sh: SKIP: qemu-system-arm missing" >&2
    exit 77
fi
mkdir -p "$build"
build=$(cd "$build" && pwd)
# Logging every instruction of the soft-float run takes minutes: about 11 on
# an idle 2-core host since the IMU solve's row runs the whole solve (a busy
# host passed 900 s).
SFIT_QEMU_TIMEOUT=${SFIT_QEMU_TIMEOUT:-1800}
export SFIT_QEMU_TIMEOUT
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
: >"$tmp/nobudget.txt"

for core in cortex-m4f cortex-m33 cortex-m3; do
    case $core in cortex-m4f) sub=m4f ;; cortex-m33) sub=m33 ;; cortex-m3) sub=m3 ;; esac
    if [ "$dobuild" -eq 1 ]; then
        "$src/tests/target/build.sh" "$build" "$src" "$core" || exit $?
    fi
    (
        if command -v flock >/dev/null 2>&1; then flock 9; fi
        "$here/count.sh" "$build/$sub/sfit_flopdrv.elf" "$tmp/fc_$sub" || exit 1
        "$here/footprint.sh" "$build/$sub" "$tmp/nobudget.txt" >"$tmp/fp_$sub.txt"
        exit 0
    ) 9>"$build/$sub.flopcount.lock" || { echo "cores.sh: $core: driver run failed" >&2; exit 1; }
    awk -v mode=rows -f "$here/report.awk" "$tmp/fc_$sub.out" "$tmp/fc_$sub.win" "$tmp/nobudget.txt" \
        "$tmp/fp_$sub.txt" | sed "s/^/$sub /" >>"$tmp/rows.txt"
done

awk -v mhz="$mhz" '
function f1(x) { return (x == int(x)) ? sprintf("%d", x) : sprintf("%.1f", x) }
$2 == "op" { fl[$1, $3] = $4; ins[$1, $3] = $5; if (!($3 in seen)) { seen[$3] = 1; order[++nop] = $3 } }
$2 == "code_total" { czos[$1] = $3; czo2[$1] = $4 }
$2 == "stack" { st[$1, $3] = $4 }
END {
    nk = split("moments_add moments_add_call batch_per_point solve_gdke solve_ugdk planar_solve chol_solve jacobi_eig multi_solve_per_marker incremental_update noise_calibration joint_frame joint_per_child", key, " ")
    print "Measured by `tools/flopcount/cores.sh --update-docs`: the same driver"
    print "and footprint objects as above, built with arm-none-eabi-gcc 12.2 -O2"
    print "-std=c99 for each core (`SFIT_ARM_CORE` of `port/cortex-m4f/toolchain.cmake`)"
    print "and run on its QEMU board. Instructions are exact counts of everything"
    print "executed inside the operation, C-library and soft-float routines included;"
    print "FLOPs are the VFP arithmetic instructions (the M3 has none: libgcc"
    print "emulates every float operation)."
    print ""
    print "| operation | FLOPs M4F / M33 | instructions M4F | instructions M33 | instructions M3 (soft float) | M3 / M4F |"
    print "|---|---:|---:|---:|---:|---:|"
    for (i = 1; i <= nk; i++) {
        n = key[i]
        if (!(n in seen)) continue
        printf "| `%s` | %s / %s | %s | %s | %s | %.1f |\n", n, f1(fl["m4f", n]), f1(fl["m33", n]), f1(ins["m4f", n]), \
            f1(ins["m33", n]), f1(ins["m3", n]), (ins["m4f", n] > 0 ? ins["m3", n] / ins["m4f", n] : 0)
    }
    print ""
    print "| core (QEMU board) | code -Os / -O2 (B) | stack `sfit_moments_add` | stack `sfit_fit_moments` | stack `sfit_fit_points` |"
    print "|---|---:|---:|---:|---:|"
    split("m4f m33 m3", cs, " ")
    split("Cortex-M4F, FPv4-SP (mps2-an386)|Cortex-M33, FPv5-SP (mps2-an505)|Cortex-M3, no FPU (mps2-an385)", cn, "|")
    for (c = 1; c <= 3; c++)
        printf "| %s | %s / %s | %s B | %s B | %s B |\n", cn[c], czos[cs[c]], czo2[cs[c]], st[cs[c], "sfit_moments_add"], \
            st[cs[c], "sfit_fit_moments"], st[cs[c], "sfit_fit_points"]
    print ""
    print "(stack: worst case at -O2, frame plus deepest callee chain, soft-float routines included.)"
    print ""
    a = ins["m3", "moments_add"]; a1 = ins["m3", "moments_add_call"]; s = ins["m3", "solve_gdke"]; u = ins["m3", "solve_ugdk"]
    load = (100 * a + s) / (mhz * 1e6) * 100
    printf "**A 100 Hz marker stream on a core without an FPU.** On the Cortex-M3 one\n"
    printf "sample (`sfit_moments_add`) executes %.0f instructions on average (%s for a\n", a, f1(a1)
    printf "call that does not close a block) and one GDKE solve (`sfit_fit_moments`)\n"
    printf "%s (UGDK: %s). At an assumed %s MHz (an STM32L1-class part) and one\n", f1(s), f1(u), mhz
    printf "instruction per cycle, 100 samples a second plus one solve a second take\n"
    printf "%.0f + %.0f = %.0f us of every second, %.2f %% of the CPU; the solve alone\n", \
        100 * a / mhz, s / mhz, (100 * a + s) / mhz, load
    printf "is %.2f ms. QEMU counts instructions, not cycles: on a real M3, loads,\n", s / mhz / 1000
    printf "taken branches and flash wait states cost extra cycles, so read these as\n"
    printf "lower bounds; even at three cycles per instruction the stream would take\n"
    printf "%.1f %% of the CPU.\n", 3 * load
}' "$tmp/rows.txt" >"$tmp/block.md"
cat "$tmp/block.md"

if [ "$update" -eq 1 ]; then
    "$here/update_block.sh" cores "$tmp/block.md" "$src/docs/cost.md" || exit 2
fi
exit 0
