#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m33_target.sh BUILD_DIR SOURCE_DIR
#
# The on-target tests on a Cortex-M33 with FPU (-mcpu=cortex-m33 -mfpu=fpv5-sp-d16 -mfloat-abi=hard) on QEMU mps2-an505
# (tests/scripts/target_core.sh).
exec "$(dirname "$0")/target_core.sh" cortex-m33 "$1" "$2"
