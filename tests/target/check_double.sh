#!/bin/sh
# SPDX-License-Identifier: MIT
#
# check_double.sh FILE...   (objects, archives or ELF files for Cortex-M4F)
#
# Fails (exit 1) when any FILE references or contains a double-precision
# helper (__aeabi_d*, __aeabi_f2d, __aeabi_d2f, __aeabi_*2d, __*df3, __*df2,
# __extendsfdf2, __truncdfsf2, __fix*df*, __float*df) or executes a .f64
# instruction: on an FPv4-SP core each of these is software emulation.
# Prints what it found; "ok" otherwise.
set -u
nm=${SFIT_NM:-arm-none-eabi-nm}
objdump=${SFIT_OBJDUMP:-arm-none-eabi-objdump}
pat='^(__aeabi_d[a-z0-9]*|__aeabi_[a-z0-9]*2d|__aeabi_f2d|__aeabi_d2f|__[a-z]*df[23]|__(extend|trunc)[a-z]*df[a-z0-9]*|__fix(uns)?df[a-z0-9]*|__float[a-z]*df)$'
bad=0
for f in "$@"; do
    syms=$("$nm" "$f" 2>/dev/null | awk '{ print $NF }' | grep -E "$pat" | sort -u | tr '\n' ' ')
    if [ -n "$syms" ]; then
        echo "check_double: $f: double-precision helper(s): $syms"
        bad=1
    fi
    n=$("$objdump" -d "$f" 2>/dev/null | grep -c '\.f64')
    if [ "$n" -ne 0 ]; then
        echo "check_double: $f: $n .f64 instruction(s):"
        "$objdump" -d "$f" | grep '\.f64' | head -5
        bad=1
    fi
done
[ "$bad" -eq 0 ] && echo "check_double: ok ($# file(s))"
exit "$bad"
