#!/bin/sh
# SPDX-License-Identifier: MIT
#
# run.sh [-M MACHINE] ELF [ARGS...]
#
# Run a Cortex-M4F test program (linked with startup.c + mps2_an386.ld) under
# QEMU's mps2-an386 with semihosting: the program's stdout/stderr go to ours,
# its argv is "basename(ELF) ARGS...", and main's return value (or exit())
# becomes our exit status. A CPU fault exits with 100 + exception number
# (startup.c), a hang is killed after SFIT_QEMU_TIMEOUT seconds (status 124).
# Exits 77 (CTest SKIP_RETURN_CODE) when qemu-system-arm is not installed.
#
# -M MACHINE: the board (mps2-an386 Cortex-M4F, mps2-an505 Cortex-M33,
# mps2-an385 Cortex-M3, mps2-an500 Cortex-M7); overrides SFIT_QEMU_MACHINE.
#
# Environment:
#   SFIT_QEMU           emulator binary        (default qemu-system-arm)
#   SFIT_QEMU_MACHINE   -M value               (default mps2-an386)
#   SFIT_QEMU_TIMEOUT   seconds                (default 120)
#   SFIT_QEMU_EXTRA     extra QEMU options, word-split (e.g. "-d exec -D log")
set -u

machine=${SFIT_QEMU_MACHINE:-mps2-an386}
if [ $# -ge 2 ] && [ "$1" = "-M" ]; then
    machine=$2
    shift 2
fi
if [ $# -lt 1 ]; then
    echo "usage: $0 [-M MACHINE] ELF [ARGS...]" >&2
    exit 2
fi
qemu=${SFIT_QEMU:-qemu-system-arm}
if ! command -v "$qemu" >/dev/null 2>&1; then
    echo "run.sh: SKIP: '$qemu' not found (Debian: apt-get install qemu-system-arm)" >&2
    exit 77
fi
if ! command -v timeout >/dev/null 2>&1; then
    echo "run.sh: 'timeout' (coreutils) not found" >&2
    exit 2
fi
elf=$1
shift
if [ ! -f "$elf" ]; then
    echo "run.sh: no such file: $elf" >&2
    exit 2
fi

# Semihosting command line = one arg= per word; QEMU wants ',' doubled inside
# an option value. argv[0] is the basename: newlib's crt0 reads the command
# line into a small fixed buffer, so long build paths would not fit.
# Arguments must not contain whitespace (crt0 splits the joined line on it),
# and the joined line must fit in 254 characters, else crt0 silently gets
# argc == 0.
esc() { printf '%s' "$1" | sed 's/,/,,/g'; }
name=$(basename "$elf")
cfg="enable=on,target=native,arg=$(esc "$name")"
len=${#name}
for a in "$@"; do
    cfg="$cfg,arg=$(esc "$a")"
    len=$((len + 1 + ${#a}))
done
if [ "$len" -gt 254 ]; then
    echo "run.sh: command line is $len characters; semihosting crt0 takes at most 254" >&2
    exit 2
fi

tmo=${SFIT_QEMU_TIMEOUT:-120}
# shellcheck disable=SC2086 # SFIT_QEMU_EXTRA is meant to be word-split
timeout -k 5 "$tmo" "$qemu" -M "$machine" \
    -nographic -monitor none -serial none \
    -semihosting-config "$cfg" ${SFIT_QEMU_EXTRA:-} -kernel "$elf"
rc=$?
if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
    echo "run.sh: TIMEOUT: $elf still running after ${tmo}s, killed" >&2
fi
exit "$rc"
