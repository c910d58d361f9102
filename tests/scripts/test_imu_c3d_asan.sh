#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The joint from two IMUs on signals made from real motion (the trials of
# test_imu_c3d.sh: biobuddy's hip and knee, CMU 135_02's arm), with
# `sfit imu-joint` and the batch reference (test_imu --ref-csv) built with
# AddressSanitizer + UndefinedBehaviorSanitizer. The same checks as
# test_imu_c3d.sh (tests/scripts/imu_c3d_trials.py --check: the physics of
# the signals, the accuracy and coverage of the hip, the flag on a parent
# that hardly turns), and no sanitizer report from any run (the script fails
# on one).
#
# Builds the CLI (sfit_cli) and test_imu in BUILD_DIR/imu-asan with
#   -fsanitize=address,undefined -fno-sanitize-recover=all
#
#   test_imu_c3d_asan.sh BUILD_DIR SOURCE_DIR
#
# SFIT_SAN_CC picks the compiler (default: gcc). Exit 77 (skipped) when the
# compiler cannot link a sanitized program, unless CI=true.
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
out="$build/imu-asan"
name=test_imu_c3d_asan

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
[ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
/usr/bin/python3 -c 'import numpy' 2>/dev/null || missing "numpy not found for /usr/bin/python3"
san_build "$out" sfit_cli test_imu
for f in "$out/bin/sfit" "$out/tests/test_imu"; do
  [ -x "$f" ] || { echo "$name: FAIL: $f not built" >&2; exit 1; }
done
/usr/bin/python3 "$src/tests/scripts/imu_c3d_trials.py" "$out" --check \
  || { echo "$name: FAIL: the IMU trials under ASan+UBSan" >&2; exit 1; }
echo "$name: ok: sfit imu-joint and the batch reference on the real-motion trials under $cc -fsanitize=address,undefined -fno-sanitize-recover=all"
