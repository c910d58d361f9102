#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m4f_footprint.sh BUILD_DIR SOURCE_DIR
#
# Footprint of the Cortex-M4F build (tools/flopcount/footprint.sh): code
# size per module at -Os and -O2 and worst-case stack of every public
# function within tools/flopcount/footprint_budget.txt, every stack bounded
# (no recursion, no dynamic frame, no unknown callee), no heap symbol, no
# mutable static data, no double-precision helper.
# Exit 77 (skip) only when the cross compiler is missing and CI != "true".
set -u
build=$1
src=$2
"$src/tests/target/build.sh" "$build" "$src"
rc=$?
[ "$rc" -eq 0 ] || exit "$rc"
"$src/tools/flopcount/footprint.sh" "$build/m4f"
