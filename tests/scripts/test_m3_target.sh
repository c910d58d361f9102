#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m3_target.sh BUILD_DIR SOURCE_DIR
#
# The on-target tests on a Cortex-M3 without FPU (-mcpu=cortex-m3 -mfloat-abi=soft, float emulated) on QEMU mps2-an385
# (tests/scripts/target_core.sh).
exec "$(dirname "$0")/target_core.sh" cortex-m3 "$1" "$2"
