#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m4f_build.sh BUILD_DIR SOURCE_DIR
#
# The library cross-compiled for Cortex-M4F (hard float) with the STYLE.md
# warning set and -Werror (tests/target/build.sh -> BUILD_DIR/m4f):
#  - the build must succeed without a single warning;
#  - no library object, and no program built from it (the FLOP-count
#    driver links every operation), may reference a double-precision
#    helper or contain a .f64 instruction (tests/target/check_double.sh);
#  - the checker itself must catch a deliberate double (self-test).
# Exit 77 (skip) only when the cross compiler is missing and CI != "true".
set -u
build=$1
src=$2
"$src/tests/target/build.sh" "$build" "$src"
rc=$?
[ "$rc" -eq 0 ] || exit "$rc"
m4f="$build/m4f"

# Self-test: a float->double promotion must be caught.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
printf 'double sfit_selftest_dbl(float x);\ndouble sfit_selftest_dbl(float x) { return (double)x * 3.0; }\n' >"$tmp/dbl.c"
arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -O2 -c "$tmp/dbl.c" -o "$tmp/dbl.o" || exit 1
if "$src/tests/target/check_double.sh" "$tmp/dbl.o" >/dev/null; then
    echo "test_m4f_build: FAIL: check_double.sh did not catch a double in a test object" >&2
    exit 1
fi

objs=$(find "$m4f/sfit/lib" -name '*.obj' -o -name '*.o' | sort)
if [ -z "$objs" ]; then
    echo "test_m4f_build: FAIL: no library objects under $m4f/sfit/lib" >&2
    exit 1
fi
# shellcheck disable=SC2086 # word splitting of the object list is intended
"$src/tests/target/check_double.sh" $objs "$m4f/sfit/lib/libsfit.a" "$m4f/sfit_flopdrv.elf" || exit 1
echo "test_m4f_build: ok: warning-free -Werror build, no double precision in $(echo "$objs" | wc -l) objects + driver ELF"
