#!/bin/sh
# SPDX-License-Identifier: MIT
#
# count_insns.sh [-v] ELF FUNCTION [ARGS...]
#
# Count the instructions executed inside FUNCTION during one run of ELF under
# QEMU mps2-an386 (via run.sh), and split out the FP work by mnemonic.
# Instruction counts, not cycles: exact and repeatable for a given binary.
# Only FUNCTION's own address range [nm value, +nm size) is counted: callees
# (libm, __aeabi_*, other sfit functions) are not, and a function that was
# inlined everywhere has no symbol (mark it noinline or count its caller).
# Conditional instructions skipped inside an IT block still count (the CPU
# issues them too).
#
# Method (TOOLCHAIN.md): one guest instruction per translation block
# (-singlestep; -accel tcg,one-insn-per-tb=on from QEMU 8), -d exec,nochain
# logs every executed block, -dfilter keeps the function's range; each
# logged PC is mapped to its objdump mnemonic.
#
# Output lines (key value ...):
#   function NAME addr 0x... size N
#   calls N        executions of the function's first instruction
#   insns N        all executed instructions in the range
#   fp_arith N     v{add,sub,mul,div,sqrt,fma,fms,fnma,fnms,mla,mls,nmla,nmls,nmul,neg,abs}.f32
#   fp_cmp / fp_cvt / fp_ldst / fp_mov / f64   compares, conversions,
#                  loads-stores-push-pop, moves (incl. vmrs/vmsr), any .f64
#   arith.<mnemonic> N   one line per FP arithmetic mnemonic
#   (-v: also mnem.<mnemonic> N for every mnemonic executed)
# Exit status: the program's (0 normally); 77 if QEMU is missing.
set -u

verbose=0
if [ "${1:-}" = "-v" ]; then
    verbose=1
    shift
fi
if [ $# -lt 2 ]; then
    echo "usage: $0 [-v] ELF FUNCTION [ARGS...]" >&2
    exit 2
fi
elf=$1
func=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
nm=${SFIT_NM:-arm-none-eabi-nm}
objdump=${SFIT_OBJDUMP:-arm-none-eabi-objdump}
qemu=${SFIT_QEMU:-qemu-system-arm}

# Address and size of FUNCTION (Thumb bit cleared if a tool reports it).
sym=$("$nm" -S "$elf" | awk -v f="$func" '$4 == f && $3 ~ /^[tTwW]$/ { print $1, $2; exit }')
if [ -z "$sym" ]; then
    echo "count_insns.sh: no sized function '$func' in $elf (inlined? static name clash?)" >&2
    exit 2
fi
start=$(( 0x${sym% *} & ~1 ))
size=$(( 0x${sym#* } ))
stop=$(( start + size ))

# One instruction per translation block: the option depends on QEMU's version.
. "$(dirname "$0")/onestep.sh"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
"$objdump" -d --no-show-raw-insn --start-address="$start" --stop-address="$stop" "$elf" \
    >"$tmp/dis.txt"
SFIT_QEMU_EXTRA="$onestep -d exec,nochain -D $tmp/exec.log -dfilter $(printf '0x%x+0x%x' "$start" "$size")" \
    "$here/run.sh" "$elf" "$@" >"$tmp/out.txt" 2>&1
rc=$?
if [ "$rc" -ne 0 ]; then
    echo "count_insns.sh: program exited with status $rc; its output:" >&2
    cat "$tmp/out.txt" >&2
    [ "$rc" -eq 77 ] && exit 77
fi
touch "$tmp/exec.log"

# Join: objdump lines "    454:\tvldr\ts15, [r0]" give pc -> mnemonic;
# log lines "Trace 0: 0x... [00000000/00000454/...] ..." give executed pcs.
awk -v name="$func" -v start="$start" -v size="$size" -v verbose="$verbose" '
function norm(h) { h = tolower(h); sub(/^0+/, "", h); return h == "" ? "0" : h }
FNR == NR {
    if (match($0, /^ *[0-9a-f]+:\t/)) {
        split($0, f, "\t")
        pc = f[1]; sub(/:.*/, "", pc); gsub(/ /, "", pc)
        mn[norm(pc)] = f[2]
    }
    next
}
/^Trace / {
    s = $0; sub(/^[^[]*\[[0-9a-fA-F]*\//, "", s); sub(/\/.*/, "", s)
    pc = norm(s)
    m = (pc in mn) ? mn[pc] : "?"
    n++; cnt[m]++
    if (pc == norm(sprintf("%x", start))) calls++
}
END {
    cond = "(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?"
    printf "function %s addr 0x%x size %d\n", name, start, size
    printf "calls %d\ninsns %d\n", calls, n
    for (m in cnt) {
        if (m ~ /\.f64$/) f64 += cnt[m]
        if (m ~ ("^v(add|sub|mul|div|sqrt|fma|fms|fnma|fnms|mla|mls|nmla|nmls|nmul|neg|abs)" cond "\\.f32$")) {
            arith += cnt[m]; am[m] = cnt[m]
        } else if (m ~ ("^vcmpe?" cond "\\.")) cmp += cnt[m]
        else if (m ~ ("^vcvt")) cvt += cnt[m]
        else if (m ~ ("^v(ldr|str|ldm|stm|push|pop)")) ldst += cnt[m]
        else if (m ~ ("^v(mov|mrs|msr)")) mov += cnt[m]
    }
    printf "fp_arith %d\nfp_cmp %d\nfp_cvt %d\nfp_ldst %d\nfp_mov %d\nf64 %d\n", arith, cmp, cvt, ldst, mov, f64
    for (m in am) printf "arith.%s %d\n", m, am[m] | "sort"
    close("sort")
    if (verbose) { for (m in cnt) printf "mnem.%s %d\n", m, cnt[m] | "sort"; close("sort") }
}' "$tmp/dis.txt" "$tmp/exec.log"
exit "$rc"
