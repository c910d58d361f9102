#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_docs_figures.sh BUILD_DIR SOURCE_DIR
#
# The cost figures of the documentation are the measured ones: the table
# between <!-- flopcount:begin/end --> in docs/cost.md is what
# `tools/flopcount/run.sh --md` prints now, and every figure the prose of
# README.md and docs/*.md cites from it (tests/scripts/docs_figures.py:
# "114 FLOPs (`solve_gdke`)", "4034 B (`code -Os minimal_app`)", ...)
# equals its row; the check must fail on drifted copies of the docs.
# Exit 77 (skip) only when a tool is missing and CI != "true".
set -u
build=$1
src=$2
here=$(cd "$(dirname "$0")" && pwd)
m4f="$build/m4f"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
# The counts of sfit.script.m4f_flopcount (which runs first) when they are
# those of the current driver ELF; else count again (QEMU, about a minute).
fresh=0
if command -v qemu-system-arm >/dev/null 2>&1 && "$src/tests/target/build.sh" "$build" "$src" \
    >"$tmp/build.log" 2>&1 && [ "$m4f/fc.out" -nt "$m4f/sfit_flopdrv.elf" ] \
    && [ "$m4f/footprint.txt" -nt "$m4f/sfit_flopdrv.elf" ] \
    && [ "$m4f/fc.out" -nt "$src/tools/flopcount/budget.txt" ]; then
    fresh=1
fi
if [ "$fresh" -eq 1 ]; then
    awk -v mode=json -f "$src/tools/flopcount/report.awk" "$m4f/fc.out" "$m4f/fc.win" \
        "$src/tools/flopcount/budget.txt" "$m4f/footprint.txt" >"$tmp/fc.json"
    rc=$?
else
    "$src/tools/flopcount/run.sh" --build-dir "$build" --json >"$tmp/fc.json"
    rc=$?
fi
[ "$rc" -eq 77 ] && exit 77
[ "$rc" -le 1 ] || { echo "test_docs_figures: FAIL: counting exited $rc" >&2; exit 1; }
fail=0
# 1. the generated table is the measured one
awk -f "$src/tools/flopcount/report.awk" -v mode=md "$m4f/fc.out" "$m4f/fc.win" \
    "$src/tools/flopcount/budget.txt" "$m4f/footprint.txt" >"$tmp/table.md" 2>/dev/null
awk '/<!-- flopcount:begin -->/ { on = 1; next } /<!-- flopcount:end -->/ { on = 0 } on' \
    "$src/docs/cost.md" >"$tmp/doc.md"
if ! diff -u "$tmp/doc.md" "$tmp/table.md" >"$tmp/diff"; then
    echo "test_docs_figures: FAIL: docs/cost.md's table is not the measured one" \
        "(tools/flopcount/run.sh --update-docs):" >&2
    head -40 "$tmp/diff" >&2
    fail=1
fi
# 2. the figures the prose cites, and the check's own failure cases
python3 "$here/docs_figures.py" --selftest "$src" "$tmp/fc.json" "$m4f/footprint.txt" || fail=1
exit "$fail"
