#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every cmocka test under AddressSanitizer + UndefinedBehaviorSanitizer (gcc).
#
#   test_sanitizers.sh BUILD_DIR SOURCE_DIR
#
# Configures a nested build of the project in BUILD_DIR/asan with
#   -fsanitize=address,undefined -fno-sanitize-recover=all
# (without the last flag UBSan only prints and the test still passes) and
# -DSFIT_WERROR=ON, builds it and runs its ctest without the script tests
# (no recursion), the CLI scripts (tests/scripts/test_cli*.sh) and the IMU
# trials from real motion (tests/scripts/imu_c3d_trials.py --check) with its
# sanitized sfit. Then replays the committed fuzz seed corpus through the
# harnesses built with gcc and the same sanitizers (tests/fuzz/replay_main.c),
# so the harnesses also compile and hold under gcc.
#
# SFIT_SAN_CC picks the compiler (default: gcc). Exit 77 (skipped) when the
# compiler cannot link a sanitized program, unless CI=true.
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
out="$build/asan"
name=test_sanitizers

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
# LeakSanitizer on (the library allocates nothing; a leak would be in a test).
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
san_build "$out"
if ! ctest --test-dir "$out" -E '^sfit\.script\.' --output-on-failure -j2 >"$out/ctest.log" 2>&1; then
  cat "$out/ctest.log" >&2
  echo "$name: FAIL: a test failed under ASan+UBSan" >&2
  exit 1
fi
ntests=$(sed -n 's/.*tests passed, 0 tests failed out of \([0-9]*\).*/\1/p' "$out/ctest.log")
grep -q "tests passed" "$out/ctest.log" || { cat "$out/ctest.log" >&2; exit 1; }

# The CLI scripts (readers on real, written and corrupt files) with the
# sanitized sfit binary.
ncli=0
for t in "$src"/tests/scripts/test_cli*.sh; do
  if ! bash "$t" "$out" "$src" >"$out/$(basename "$t" .sh).log" 2>&1; then
    cat "$out/$(basename "$t" .sh).log" >&2
    echo "$name: FAIL: $(basename "$t") with the sanitized sfit" >&2
    exit 1
  fi
  ncli=$((ncli + 1))
done

# The joint from two IMUs on signals made from real motion (the checks of
# test_imu_c3d.sh) with the sanitized sfit and test_imu; imu_c3d_trials.py
# fails on a sanitizer report.
nimu=0
if [ -x "$out/tests/test_imu" ] && /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
  if ! /usr/bin/python3 "$src/tests/scripts/imu_c3d_trials.py" "$out" --check >"$out/imu_c3d.log" 2>&1; then
    cat "$out/imu_c3d.log" >&2
    echo "$name: FAIL: the IMU trials from real motion with the sanitized sfit" >&2
    exit 1
  fi
  nimu=1
elif [ "${CI:-}" = "true" ]; then
  echo "$name: FAIL: test_imu or numpy missing for the IMU trials (required in CI)" >&2
  exit 1
fi

# Fuzz seed corpus through gcc-built harnesses (no libFuzzer needed).
nrep=0
if [ -d "$src/tests/fuzz" ]; then
  mkdir -p "$out/fuzz-replay"
  for h in "$src"/tests/fuzz/fuzz_*.c; do
    hn=$(basename "${h%.c}")
    corpus="$src/tests/fuzz/corpus/${hn#fuzz_}"
    [ -d "$corpus" ] || continue
    # shellcheck disable=SC2086
    "$cc" -std=c99 -D_POSIX_C_SOURCE=200809L -g -O1 $san -Wall -Wextra -Werror \
      -I"$src/lib/include" -I"$src/lib/src" -I"$src/port" -I"$src/port/host" -I"$src/tests/fuzz" -I"$src/tools/formats" -I"$src/tools/lab" \
      -I"$build/tools/gen" -I"$out/tools/gen" \
      "$h" "$src/tests/fuzz/replay_main.c" "$src"/lib/src/*.c -lm -o "$out/fuzz-replay/$hn"
    if ! "$out/fuzz-replay/$hn" "$corpus" >"$out/fuzz-replay/$hn.log" 2>&1; then
      cat "$out/fuzz-replay/$hn.log" >&2
      echo "$name: FAIL: $hn seed corpus under $cc sanitizers" >&2
      exit 1
    fi
    nrep=$((nrep + $(find "$corpus" -type f | wc -l)))
  done
fi
echo "$name: ok: ${ntests:-all} tests pass under $cc -fsanitize=address,undefined -fno-sanitize-recover=all; $ncli CLI scripts and $nimu set of IMU trials from real motion with the sanitized sfit; $nrep fuzz seeds replayed"
