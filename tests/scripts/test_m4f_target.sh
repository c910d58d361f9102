#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m4f_target.sh BUILD_DIR SOURCE_DIR
#
# Runs the on-target tests (tests/target, Cortex-M4F hard float) under
# qemu-system-arm -M mps2-an386 (tests/scripts/target_core.sh): sfit.target
# (known-answer and invariant tests, ending with "N passed, 0 failed") and,
# through the cross project's ctest (BUILD_DIR/m4f), sfit.target.flopdrv
# (every operation of the FLOP-count driver returns SFIT_OK).
# Exit 77 (skip) only when a tool is missing and CI != "true".
exec "$(dirname "$0")/target_core.sh" cortex-m4f "$1" "$2"
