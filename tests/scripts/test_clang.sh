#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every cmocka test built by clang (the gcc build is the main one).
#
#   test_clang.sh BUILD_DIR SOURCE_DIR
#
# Configures a nested build in BUILD_DIR/clang with CC=clang, RelWithDebInfo
# (-O2 -g, the build type of the CI preset, so gcc and clang differ only by
# compiler; SFIT_CLANG_BUILD_TYPE overrides it), the
# project's warning set as errors (-DSFIT_WERROR=ON) and clang's
# AddressSanitizer + UndefinedBehaviorSanitizer (-fno-sanitize-recover=all;
# clang's UBSan also checks float-to-integer overflow and more pointer
# arithmetic than gcc's), builds it and runs its ctest without the script
# tests. Then builds tests/test_status.c against a copy of the library
# compiled with -DSFIT_JACOBI_MAX_SWEEPS=1, the only way to make the
# eigen-solver hit its bound on real data (SFIT_E_NO_CONVERGENCE cannot be
# produced with the default bound of 12: see docs/reliability.md).
#
# Exit 77 (skipped) when clang is missing, unless CI=true.
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
out="$build/clang"
name=test_clang
cc=${SFIT_CLANG:-clang}

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
command -v "$cc" >/dev/null 2>&1 || missing "$cc not found"
command -v cmake >/dev/null 2>&1 || missing "cmake not found"
command -v pkg-config >/dev/null 2>&1 || missing "pkg-config not found"

san="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
mkdir -p "$out"
printf 'int main(void) { return 0; }\n' > "$out/probe.c"
# shellcheck disable=SC2086
"$cc" $san "$out/probe.c" -o "$out/probe" >/dev/null 2>&1 || missing "$cc cannot link $san (libclang-rt-14-dev?)"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

CC="$cc" cmake -S "$src" -B "$out" -DCMAKE_BUILD_TYPE="${SFIT_CLANG_BUILD_TYPE:-RelWithDebInfo}" -DSFIT_WERROR=ON \
  -DCMAKE_C_FLAGS="$san" -DCMAKE_EXE_LINKER_FLAGS="$san" >"$out/configure.log" 2>&1 \
  || { cat "$out/configure.log" >&2; echo "$name: FAIL: configure" >&2; exit 1; }
cmake --build "$out" -j2 >"$out/build.log" 2>&1 \
  || { tail -n 60 "$out/build.log" >&2; echo "$name: FAIL: build (clang -Werror)" >&2; exit 1; }
if ! ctest --test-dir "$out" -E '^sfit\.script\.' --output-on-failure -j2 >"$out/ctest.log" 2>&1; then
  cat "$out/ctest.log" >&2
  echo "$name: FAIL: a test failed with clang" >&2
  exit 1
fi
ntests=$(sed -n 's/.*tests passed, 0 tests failed out of \([0-9]*\).*/\1/p' "$out/ctest.log")

# SFIT_E_NO_CONVERGENCE: test_status.c against a library with a 1-sweep Jacobi.
if [ -f "$src/tests/test_status.c" ]; then
  nc="$out/no_convergence"
  mkdir -p "$nc"
  # -Wno-unused-function: in this build main() registers only the no-convergence test.
  # shellcheck disable=SC2046,SC2086
  "$cc" -std=c99 -O1 -g $san -Wall -Wextra -Werror -Wno-unused-function -DSFIT_JACOBI_MAX_SWEEPS=1 \
    -I"$src/lib/include" -I"$src/lib/src" -I"$src/port" -I"$src/port/host" -I"$src/tests" -I"$src/tests/ref" \
    "$src/tests/test_status.c" "$src"/lib/src/*.c "$src"/tests/ref/sfit_ref*.c \
    $(pkg-config --cflags --libs cmocka) -lm -o "$nc/test_status_1sweep" \
    || { echo "$name: FAIL: building test_status with SFIT_JACOBI_MAX_SWEEPS=1" >&2; exit 1; }
  if ! "$nc/test_status_1sweep" >"$nc/run.log" 2>&1; then
    cat "$nc/run.log" >&2
    echo "$name: FAIL: test_status with SFIT_JACOBI_MAX_SWEEPS=1" >&2
    exit 1
  fi
  grep -q "no_convergence: produced with SFIT_JACOBI_MAX_SWEEPS=1" "$nc/run.log" || { cat "$nc/run.log" >&2; echo "$name: FAIL: the no-convergence test did not run" >&2; exit 1; }
  echo "$name: test_status with SFIT_JACOBI_MAX_SWEEPS=1: SFIT_E_NO_CONVERGENCE produced by sfit_mat3_eig_sym, sfit_fit_moments, sfit_multi_fit, sfit_incr_start"
fi
echo "$name: ok: ${ntests:-all} tests pass built by $cc -O2 -Werror with ASan+UBSan"
