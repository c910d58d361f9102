#!/bin/sh
# SPDX-License-Identifier: MIT
#
# test_m4f_lower_limb.sh BUILD_DIR SOURCE_DIR
#
# The lower-limb firmware example (port/cortex-m4f/examples/lower_limb,
# issue 30), built and run like the on-target tests:
#  1. ll_gen (host) converts the shared session's four trials
#     (tests/data/c3d/lower_limb_session) to a C array;
#  2. ll_main is built for the host (the library sources, cc -std=c99) and
#     for the Cortex-M4F (the tests/target build's libsfit.a), run on the
#     host and under QEMU (mps2-an386);
#  3. every joint centre printed by the target equals the host's within
#     float rounding (at most 4 ulp per coordinate; the largest difference
#     is printed), and so do the pair results;
#  4. tools/flopcount/count.sh counts the instructions of every frame
#     (each between fc_begin and fc_end) and the cycle model's estimate:
#     mean and max per frame for the calibration of each joint and for
#     tracking; the tracking frames after the first (which runs the full
#     solves) must stay within 21000 instructions and 32000 estimated cycles.
# Prints the summary (docs/lower_limb_firmware.md quotes it). Exit 77 (skip) when a
# tool is missing and CI != "true".
set -eu
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
name=test_m4f_lower_limb
. "$src/tests/scripts/common.sh"
ex="$src/port/cortex-m4f/examples/lower_limb"
out="$build/lower_limb"
mkdir -p "$out"
CC=${CC:-cc}
command -v "$CC" >/dev/null 2>&1 || missing "$CC not found"
command -v arm-none-eabi-gcc >/dev/null 2>&1 || missing "arm-none-eabi-gcc not found"
command -v qemu-system-arm >/dev/null 2>&1 || missing "qemu-system-arm not found"

# 1. the data
"$CC" -std=c99 -O1 -I"$src/tools/formats" -I"$ex" "$ex/ll_gen.c" "$src/tools/formats/c3d.c" "$src/tools/formats/c3d_param.c" -lm \
    -o "$out/ll_gen"
"$out/ll_gen" "$src/tests/data/c3d/lower_limb_session" "$out/ll_data.c"

# 2. host and target builds, runs
"$CC" -std=c99 -O2 -I"$src/lib/include" -I"$src/lib/src" -I"$src/port" -I"$src/port/host" -I"$ex" \
    "$ex/ll_main.c" "$out/ll_data.c" "$src"/lib/src/*.c -lm -o "$out/ll_host"
"$out/ll_host" >"$out/host.txt"
rc=0
"$src/tests/target/build.sh" "$build" "$src" || rc=$?
[ "$rc" -eq 0 ] || exit "$rc"
m4f="$build/m4f"
FL="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -fno-math-errno -ffunction-sections -fdata-sections -O2 -std=c99"
INC="-I$src/lib/include -I$src/port -I$src/port/cortex-m4f -I$ex"
arm-none-eabi-gcc $FL $INC -Wall -Wextra -Werror -c "$ex/ll_main.c" -o "$out/ll_main.o"
arm-none-eabi-gcc $FL $INC -c "$out/ll_data.c" -o "$out/ll_data.o"
startup=$(find "$m4f/CMakeFiles" -name 'startup.c.obj' | head -n 1)
arm-none-eabi-gcc $FL --specs=nano.specs --specs=rdimon.specs -L"$src/port/cortex-m4f/qemu" \
    -T"$src/port/cortex-m4f/qemu/mps2_an386.ld" -Wl,--gc-sections "$out/ll_main.o" "$out/ll_data.o" \
    "$startup" "$m4f/sfit/lib/libsfit.a" -lm -o "$out/ll.elf"
rc=0
timeout 300 "$src/port/cortex-m4f/qemu/run.sh" "$out/ll.elf" >"$out/target.txt" || rc=$?
if [ "$rc" -ne 0 ]; then
    cat "$out/target.txt"
    echo "FAIL: the firmware example exited $rc under QEMU" >&2
    exit 1
fi

# 3. centres: target vs host, in ulp of each coordinate
/usr/bin/python3 - "$out/host.txt" "$out/target.txt" <<'PY' || exit 1
import struct, sys
def load(p):
    c, pairs = {}, {}
    for l in open(p):
        w = l.split()
        if w and w[0] == "centre" and w[3] != "none":
            c[(int(w[1]), int(w[2]))] = [int(x, 16) for x in w[3:6]]
        elif w and w[0] == "centre":
            c[(int(w[1]), int(w[2]))] = None
        elif w and w[0] == "pair":
            pairs[w[1]] = w[2:]
    return c, pairs
def ulp(a, b):
    def key(u):
        return u if u < 0x80000000 else 0x80000000 - u
    return abs(key(a) - key(b))
h, hp = load(sys.argv[1]); t, tp = load(sys.argv[2])
bad = 0
worst = 0; worst_mm = 0.0
if set(h) != set(t) or len(h) != 122 * 3:
    print("FAIL: the centres printed differ in number or frames"); sys.exit(1)
for k in h:
    if (h[k] is None) != (t[k] is None):
        print("FAIL: centre", k, "valid on one side only"); bad += 1; continue
    if h[k] is None:
        continue
    for a, b in zip(h[k], t[k]):
        u = ulp(a, b)
        fa = struct.unpack("<f", struct.pack("<I", a))[0]
        fb = struct.unpack("<f", struct.pack("<I", b))[0]
        worst = max(worst, u); worst_mm = max(worst_mm, abs(fa - fb))
        if u > 4:
            print("FAIL: centre", k, fa, fb, u, "ulp"); bad += 1
if hp != tp:
    print("FAIL: pair results differ:", hp, tp); bad += 1
valid = sum(1 for k in h if h[k] is not None)
print("centres: %d of %d valid; target vs host: largest difference %d ulp (%.3g mm)" % (valid, len(h), worst, worst_mm))
sys.exit(1 if bad else 0)
PY
grep -E '^(pair|ram|stack)' "$out/target.txt"

# 4. instructions per frame
# every instruction logged: about 10x slower than a plain run (100 s alone)
SFIT_QEMU_TIMEOUT=${SFIT_QEMU_TIMEOUT:-1200} "$src/tools/flopcount/count.sh" "$out/ll.elf" "$out/count" >/dev/null || exit 1
awk '
{ k = $2; n = $3; c = $4
  g = (k < 525) ? "calibrate hip (pelvis, right thigh)" : (k < 742) ? "calibrate knee (right thigh, shank)" : (k < 1228) ? "calibrate ankle (right shank, foot)" : "track 7 segments, 6 centres"
  if (!(g in cnt)) order[++ng] = g
  cnt[g]++; s[g] += n; sc[g] += c; if (n > mx[g]) mx[g] = n; if (c > mc[g]) mc[g] = c
  if (k > 1228) { ts += n; tc += c; tn++; if (n > tmx) tmx = n; if (c > tmc) tmc = c } }
END {
  for (i = 1; i <= ng; i++) { g = order[i]
    printf "%-38s frames %4d  instructions mean %8.1f max %6d  est. cycles mean %8.1f max %6d\n", g, cnt[g], s[g] / cnt[g], mx[g], sc[g] / cnt[g], mc[g] }
  printf "tracking after the first frame: instructions mean %.1f max %d, est. cycles mean %.1f max %d (budget 21000 / 32000)\n", ts / tn, tmx, tc / tn, tmc
  if (tmx > 21000 || tmc > 32000) { print "FAIL: tracking frame over budget"; exit 1 }
}' "$out/count.win"
