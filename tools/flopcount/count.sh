#!/bin/sh
# SPDX-License-Identifier: MIT
#
# count.sh DRIVER_ELF OUT_PREFIX
#
# Run the FLOP-count driver (driver.c) once under QEMU mps2-an386 (or the
# board named in core.txt beside the ELF: mps2-an505, mps2-an385) with one
# instruction per translation block and every executed instruction logged
# (TOOLCHAIN.md: -singlestep -d exec,nochain), and count, for every window
# fc_begin() .. fc_end(), the instructions executed outside the driver's
# own functions (fc_*, main): the library and the C-library routines it
# calls. The log is streamed through a FIFO (never stored).
#
# Writes OUT_PREFIX.out (the driver's stdout: fcop/fcinfo lines) and
# OUT_PREFIX.win, one line per window:
#   win K insns CYC add sub mul div sqrt fma mla absneg cmp cvt fpmov fpldst f64
# CYC is the cycle estimate of docs/cost.md ("Cycle model"); mnemonics are
# classified from arm-none-eabi-objdump of the same ELF.
# Exit status: 0, or the driver's (failed operations), 77 without QEMU.
set -u
if [ $# -lt 2 ]; then
    echo "usage: $0 DRIVER_ELF OUT_PREFIX" >&2
    exit 2
fi
elf=$1
outp=$2
here=$(cd "$(dirname "$0")" && pwd)
src=$(cd "$here/../.." && pwd)
objdump=${SFIT_OBJDUMP:-arm-none-eabi-objdump}
qemu=${SFIT_QEMU:-qemu-system-arm}
. "$src/port/cortex-m4f/qemu/onestep.sh" # $onestep, or exit 77 without QEMU

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
"$objdump" -d --no-show-raw-insn "$elf" >"$tmp/dis.txt" || exit 2
mkfifo "$tmp/exec.fifo"

awk -v outfile="$outp.win" '
function norm(h) { h = tolower(h); sub(/^0+/, "", h); return h == "" ? "0" : h }
# number of registers in a {...} list: r4-r7 / s16-s23 ranges, d regs = 2 singles
function nregs(ops,    l, a, n, i, k, r, lo, hi, w) {
    if (!match(ops, /\{[^}]*\}/)) return 1
    l = substr(ops, RSTART + 1, RLENGTH - 2)
    k = split(l, a, /, */)
    n = 0
    for (i = 1; i <= k; i++) {
        w = (a[i] ~ /^d/) ? 2 : 1
        if (split(a[i], r, "-") == 2) {
            lo = r[1]; hi = r[2]; gsub(/[^0-9]/, "", lo); gsub(/[^0-9]/, "", hi)
            n += (hi - lo + 1) * w
        } else n += w
    }
    return n
}
BEGIN {
    cc = "(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?"
    fl = "add sub mul div sqrt fma mla absneg cmp cvt fpmov fpldst f64"
    nf = split(fl, fname, " ")
}
# ---- pass 1: the disassembly ----------------------------------------------
FNR == NR {
    if ($0 ~ /^[0-9a-f]+ <.*>:$/) {
        fn = $0; sub(/^[0-9a-f]+ </, "", fn); sub(/>:$/, "", fn)
        isdrv = (fn ~ /^fc_/ || fn == "main") ? 1 : 0
        a = $1
        if (fn == "fc_begin") begin_pc = norm(a)
        if (fn == "fc_end") end_pc = norm(a)
        next
    }
    if (match($0, /^ *[0-9a-f]+:\t/)) {
        n = split($0, f, "\t")
        pc = f[1]; sub(/:.*/, "", pc); gsub(/ /, "", pc); pc = norm(pc)
        mn = f[2]; ops = (n >= 3) ? f[3] : ""
        drv[pc] = isdrv
        if (prevpc != "") nxt[prevpc] = pc
        prevpc = pc
        # class and cycles of this instruction
        base = mn; sub(/\..*$/, "", base)
        c = ""; cyc = 1; ls1 = 0
        if (mn ~ /\.f64/) c = "f64"
        else if (base ~ ("^vadd" cc "$")) c = "add"
        else if (base ~ ("^vsub" cc "$")) c = "sub"
        else if (base ~ ("^vn?mul" cc "$")) c = "mul"
        else if (base ~ ("^vdiv" cc "$")) { c = "div"; cyc = 14 }
        else if (base ~ ("^vsqrt" cc "$")) { c = "sqrt"; cyc = 14 }
        else if (base ~ ("^vf(n)?m[as]" cc "$")) { c = "fma"; cyc = 3 }
        else if (base ~ ("^vn?ml[as]" cc "$")) { c = "mla"; cyc = 3 }
        else if (base ~ ("^v(abs|neg)" cc "$")) c = "absneg"
        else if (base ~ ("^vcmpe?" cc "$")) c = "cmp"
        else if (base ~ /^vcvt/) c = "cvt"
        else if (base ~ ("^v(ldr|str)" cc "$")) { c = "fpldst"; cyc = 2; ls1 = 1 }
        else if (base ~ /^v(ldm|stm|push|pop)/) { c = "fpldst"; cyc = 1 + nregs(ops) }
        else if (base ~ /^v(mov|mrs|msr)/) { c = "fpmov"; cyc = (split(ops, q, ",") >= 3) ? 2 : 1 }
        else if (base ~ ("^(ldr|str)(b|h|sb|sh|ex|t|bt|ht)?" cc "$")) { cyc = 2; ls1 = 1 }
        else if (base ~ ("^(ldr|str)d" cc "$")) cyc = 3
        else if (base ~ /^(push|pop|ldm|stm)/) cyc = 1 + nregs(ops)
        else if (base ~ ("^[su]div" cc "$")) cyc = 12
        cls[pc] = c; cyc0[pc] = cyc; ldst1[pc] = ls1
    }
    next
}
# ---- pass 2: the execution log ---------------------------------------------
/^Trace / {
    s = $0; sub(/^[^[]*\[[0-9a-fA-F]*\//, "", s); sub(/\/.*/, "", s)
    pc = norm(s)
    # taken branch / any PC write: +P (2) on the previous counted instruction
    if (lastc != "" && pc != nxt[lastc]) cyc_tot += 2
    lastc = ""
    if (pc == begin_pc) {
        on = 1; insns = 0; cyc_tot = 0; prevls = 0
        for (i = 1; i <= nf; i++) cnt[fname[i]] = 0
        next
    }
    if (pc == end_pc && on) {
        on = 0
        line = "win " (k + 0) " " insns " " cyc_tot
        for (i = 1; i <= nf; i++) line = line " " cnt[fname[i]]
        print line > outfile
        k++
        next
    }
    if (!on || drv[pc] != 0) { prevls = 0; next }
    if (!(pc in cls)) { unknown++; insns++; cyc_tot++; next }
    insns++
    c = cls[pc]
    if (c != "") cnt[c]++
    cy = cyc0[pc]
    if (ldst1[pc]) { if (prevls) cy = 1; prevls = 1 } else prevls = 0
    cyc_tot += cy
    lastc = pc
}
END {
    if (begin_pc == "" || end_pc == "") { print "count.sh: no fc_begin/fc_end in the ELF" > "/dev/stderr"; exit 2 }
    if (unknown > 0) printf "count.sh: %d executed instructions had no disassembly\n", unknown > "/dev/stderr"
    close(outfile)
}' "$tmp/dis.txt" "$tmp/exec.fifo" &
awkpid=$!

# The board of the core the ELF was built for (tests/target writes core.txt).
machine=mps2-an386
if [ -f "$(dirname "$elf")/core.txt" ]; then
    machine=$(awk '$1 == "machine" { print $2 }' "$(dirname "$elf")/core.txt")
fi
SFIT_QEMU_EXTRA="$onestep -d exec,nochain -D $tmp/exec.fifo" \
    "$src/port/cortex-m4f/qemu/run.sh" -M "$machine" "$elf" >"$outp.out" 2>"$outp.err"
rc=$?
wait "$awkpid"
arc=$?
if [ "$arc" -ne 0 ]; then
    echo "count.sh: trace analysis failed ($arc)" >&2
    exit 2
fi
if [ "$rc" -ne 0 ]; then
    echo "count.sh: driver exited with status $rc:" >&2
    cat "$outp.out" "$outp.err" >&2
fi
exit "$rc"
