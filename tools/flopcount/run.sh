#!/bin/sh
# SPDX-License-Identifier: MIT
#
# tools/flopcount/run.sh [--json | --md] [--update-docs] [--build-dir DIR] [--no-build]
#
# The FLOP-count verification tool, in one command:
#  1. builds the Cortex-M4F project tests/target (library + driver.c +
#     footprint objects) into DIR/m4f (tests/target/build.sh; DIR defaults
#     to <source>/build);
#  2. runs the driver under QEMU and counts, per public operation, the
#     executed FLOPs by kind, the FP compares/conversions, all instructions
#     and an estimated cycle count (count.sh);
#  3. measures the footprint (footprint.sh: code size per module at -Os and
#     -O2, struct sizes, worst-case stack, no heap / static data / double);
#  4. prints a table (default), JSON (--json) or the Markdown of
#     docs/cost.md (--md); --update-docs rewrites the block between
#     <!-- flopcount:begin --> and <!-- flopcount:end --> in docs/cost.md.
# Exit status: 0; 1 when a FLOP budget (budget.txt) or a footprint check
# fails; 77 when a tool is missing and CI is not "true".
set -u
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
mode=text
update=0
build="$src/build"
dobuild=1
while [ $# -gt 0 ]; do
    case $1 in
    --json) mode=json ;;
    --md) mode=md ;;
    --update-docs) update=1 ;;
    --build-dir) build=$2; shift ;;
    --no-build) dobuild=0 ;;
    -h | --help) sed -n '3,19p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
mkdir -p "$build"
build=$(cd "$build" && pwd)
m4f="$build/m4f"

if ! command -v qemu-system-arm >/dev/null 2>&1; then
    if [ "${CI:-}" = "true" ]; then
        echo "flopcount: FAIL: qemu-system-arm missing (CI=true)" >&2
        exit 1
    fi
    echo "flopcount: SKIP: qemu-system-arm missing (Debian: qemu-system-arm)" >&2
    exit 77
fi
if [ "$dobuild" -eq 1 ]; then
    "$src/tests/target/build.sh" "$build" "$src" || exit $?
fi

# One run at a time per build directory (ctest -j runs several scripts).
lock="$build/m4f.flopcount.lock"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
(
    if command -v flock >/dev/null 2>&1; then flock 9; fi
    "$here/count.sh" "$m4f/sfit_flopdrv.elf" "$tmp/fc" || exit $?
    "$here/footprint.sh" "$m4f" >"$tmp/footprint.txt"
    echo $? >"$tmp/footprint.rc"
    cp "$tmp/fc.out" "$tmp/fc.win" "$tmp/footprint.txt" "$m4f/" 2>/dev/null
    exit 0
) 9>"$lock" || exit $?
fprc=$(cat "$tmp/footprint.rc")

awk -v mode="$mode" -f "$here/report.awk" "$tmp/fc.out" "$tmp/fc.win" "$here/budget.txt" \
    "$tmp/footprint.txt" >"$tmp/report.txt"
rc=$?
[ "$rc" -le 1 ] || exit "$rc"
cat "$tmp/report.txt"

if [ "$update" -eq 1 ]; then
    awk -f "$here/report.awk" -v mode=md "$tmp/fc.out" "$tmp/fc.win" "$here/budget.txt" \
        "$tmp/footprint.txt" >"$tmp/table.md" 2>/dev/null
    # The generated block lives in docs/cost.md only (the README links to it).
    "$here/update_block.sh" flopcount "$tmp/table.md" "$src/docs/cost.md" || exit 2
fi
if [ "$fprc" -ne 0 ]; then
    echo "flopcount: FAIL: footprint check(s) failed:" >&2
    grep 'FAIL' "$tmp/footprint.txt" >&2
    rc=1
fi
exit "$rc"
