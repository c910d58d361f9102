# SPDX-License-Identifier: MIT
#
# onestep.sh: sourced by count_insns.sh and tools/flopcount/count.sh. With
# $qemu set, prints why and exits 77 when that QEMU is missing; else sets
# $onestep to the option that makes QEMU run one guest instruction per
# translation block (-singlestep; -accel tcg,one-insn-per-tb=on from QEMU 8),
# so that -d exec logs every executed instruction.
if ! command -v "$qemu" >/dev/null 2>&1; then
    echo "$(basename "$0"): SKIP: '$qemu' not found" >&2
    exit 77
fi
onestep_major=$("$qemu" --version | sed -n '1s/.*version \([0-9][0-9]*\)\..*/\1/p')
if [ "${onestep_major:-0}" -ge 8 ]; then
    onestep="-accel tcg,one-insn-per-tb=on"
else
    onestep="-singlestep"
fi
