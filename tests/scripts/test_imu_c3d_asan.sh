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
cc=${SFIT_SAN_CC:-gcc}

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
command -v "$cc" >/dev/null 2>&1 || missing "$cc not found"
command -v cmake >/dev/null 2>&1 || missing "cmake not found"
[ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
/usr/bin/python3 -c 'import numpy' 2>/dev/null || missing "numpy not found for /usr/bin/python3"

san="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
mkdir -p "$out"
printf 'int main(void) { return 0; }\n' > "$out/probe.c"
# shellcheck disable=SC2086
"$cc" $san "$out/probe.c" -o "$out/probe" >/dev/null 2>&1 || missing "$cc cannot link $san"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

CC="$cc" cmake -S "$src" -B "$out" -DCMAKE_BUILD_TYPE=Debug -DSFIT_WERROR=ON \
  -DSFIT_TESTS_REQUIRE_CMOCKA=ON \
  -DCMAKE_C_FLAGS="$san -O1" -DCMAKE_EXE_LINKER_FLAGS="$san" >"$out/configure.log" 2>&1 \
  || { cat "$out/configure.log" >&2; echo "$name: FAIL: configure" >&2; exit 1; }
cmake --build "$out" -j2 --target sfit_cli test_imu >"$out/build.log" 2>&1 \
  || { tail -n 60 "$out/build.log" >&2; echo "$name: FAIL: build" >&2; exit 1; }
for f in "$out/bin/sfit" "$out/tests/test_imu"; do
  [ -x "$f" ] || { echo "$name: FAIL: $f not built" >&2; exit 1; }
done
/usr/bin/python3 "$src/tests/scripts/imu_c3d_trials.py" "$out" --check \
  || { echo "$name: FAIL: the IMU trials under ASan+UBSan" >&2; exit 1; }
echo "$name: ok: sfit imu-joint and the batch reference on the real-motion trials under $cc -fsanitize=address,undefined -fno-sanitize-recover=all"
