#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The joint from two IMUs on signals made from real motion: the C3D trials
# of tests/data/c3d (biobuddy's hip and knee at 100 Hz, CMU 135_02 at
# 120 Hz) give segment poses, virtual sensors with noise and biases
# (tests/scripts/imu_from_c3d.py); `sfit imu-joint --json` and the batch
# Gauss-Newton of tests/ref (test_imu --ref-csv) run on each trial, and
# tests/scripts/imu_c3d_trials.py --check asserts the physics of the
# signals, the accuracy and coverage of the hip with a walking pelvis, and
# that a parent which hardly turns is flagged. It prints the table of
# docs/imu.md (--markdown) and checks that the page has it (--docs).
# Usage: test_imu_c3d.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
name=test_imu_c3d
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
[ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
/usr/bin/python3 -c 'import numpy' 2>/dev/null || missing "numpy not found for /usr/bin/python3"
for f in "$build/bin/sfit" "$build/tests/test_imu"; do
    [ -x "$f" ] || missing "$f not built"
done
/usr/bin/python3 "$src/tests/scripts/imu_c3d_trials.py" "$build" --check --markdown --docs "$src/docs/imu.md"
