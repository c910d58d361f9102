#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Static analysis gate (docs/reliability.md):
#  1. cppcheck --enable=warning,portability,performance on lib/ (host and
#     cortex-m4f port headers) and the host rooms of tools/rooms.tsv
#     (formats, lab, the CLI): no finding.
#  2. clang-tidy with the repository's .clang-tidy on lib/src, with the
#     compile database of a host configure (BUILD_DIR/tidy) and again for
#     the target (BUILD_DIR/tidy-m4f, --target=arm-none-eabi, newlib
#     headers): no finding.
#  3. cppcheck's MISRA C:2012 addon on lib/src: the report is written to
#     BUILD_DIR/static/misra_report.txt (same format as the committed
#     docs/misra_report.txt; regenerate that with SFIT_MISRA_UPDATE=1), and
#     every rule it reports must have a deviation row in
#     docs/reliability.md. New rules fail the test; counts are informative.
#
#   test_static_analysis.sh BUILD_DIR SOURCE_DIR
#
# Exit 77 (skipped) when cppcheck, clang-tidy or arm-none-eabi-gcc is
# missing, unless CI=true (then a missing tool is a failure).
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
out="$build/static"
name=test_static_analysis

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
for tool in cppcheck clang-tidy cmake arm-none-eabi-gcc python3; do
  command -v "$tool" >/dev/null 2>&1 || missing "$tool not found"
done
rm -rf "$out"
mkdir -p "$out"
cd "$src"
fail=0

# ---------------------------------------------------------------- 1. cppcheck
inc=(-I lib/include -I lib/src -I port)
# the host C rooms of tools/ but the binding (it needs Python's headers)
mapfile -t host_rooms < <(awk -F'\t' '!/^#/ && NF >= 2 && $1 != "binding" { print $2 }' tools/rooms.tsv)
for port in host cortex-m4f; do
  if ! cppcheck --enable=warning,portability,performance --std=c99 --error-exitcode=1 \
       --inline-suppr -q --suppress=missingIncludeSystem \
       --template='{file}:{line}: {severity}: {id}: {message}' \
       "${inc[@]}" -I "port/$port" lib/src "${host_rooms[@]}" >"$out/cppcheck-$port.txt" 2>&1; then
    echo "$name: FAIL: cppcheck ($port port):" >&2
    cat "$out/cppcheck-$port.txt" >&2
    fail=1
  fi
done
[ "$fail" -eq 0 ] && echo "$name: cppcheck (warning, portability, performance; host and cortex-m4f ports): clean"

# -------------------------------------------------------------- 2. clang-tidy
lib_sources=(lib/src/*.c)
cmake -S "$src" -B "$build/tidy" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON -DSFIT_BUILD_TESTS=OFF \
  -DSFIT_BUILD_TOOLS=OFF -DSFIT_INSTALL=OFF >"$out/tidy-configure.log" 2>&1 \
  || { cat "$out/tidy-configure.log" >&2; echo "$name: FAIL: configure for clang-tidy" >&2; exit 1; }
if ! clang-tidy -p "$build/tidy" --quiet "${lib_sources[@]}" >"$out/clang-tidy-host.txt" 2>&1; then
  echo "$name: FAIL: clang-tidy (host):" >&2
  grep -E 'warning:|error:' "$out/clang-tidy-host.txt" >&2 || cat "$out/clang-tidy-host.txt" >&2
  fail=1
else
  echo "$name: clang-tidy (host, ${#lib_sources[@]} files, .clang-tidy checks): clean"
fi

# The same on the target: the cortex-m4f port, 32-bit ARM, newlib headers.
cmake -S "$src" -B "$build/tidy-m4f" -DCMAKE_TOOLCHAIN_FILE="$src/port/cortex-m4f/toolchain.cmake" \
  -DCMAKE_EXPORT_COMPILE_COMMANDS=ON -DSFIT_BUILD_TESTS=OFF -DSFIT_BUILD_TOOLS=OFF \
  >"$out/tidy-m4f-configure.log" 2>&1 \
  || { cat "$out/tidy-m4f-configure.log" >&2; echo "$name: FAIL: configure (cortex-m4f) for clang-tidy" >&2; exit 1; }
arm_inc=()
while IFS= read -r d; do
  arm_inc+=("--extra-arg=-isystem$d")
done < <(echo | arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -xc -E -v - 2>&1 \
           | sed -n '/#include <...> search starts here:/,/End of search list./p' | sed -n 's/^ \(\/.*\)$/\1/p' \
           | grep -v '/include-fixed$\|/gcc/arm-none-eabi/[^/]*/include$' || true)
if ! clang-tidy -p "$build/tidy-m4f" --quiet --extra-arg=--target=arm-none-eabi "${arm_inc[@]}" \
     "${lib_sources[@]}" >"$out/clang-tidy-m4f.txt" 2>&1; then
  echo "$name: FAIL: clang-tidy (--target=arm-none-eabi):" >&2
  grep -E 'warning:|error:' "$out/clang-tidy-m4f.txt" >&2 || cat "$out/clang-tidy-m4f.txt" >&2
  fail=1
else
  echo "$name: clang-tidy (--target=arm-none-eabi, cortex-m4f port): clean"
fi

# ------------------------------------------------------------------ 3. MISRA
# Rule texts are not shipped with cppcheck (they are licensed): the report
# names rules by number; docs/reliability.md gives the deviation per rule.
cppcheck --addon=misra --std=c99 -q --inline-suppr --template='{file}:{line}: {id}' \
  -I lib/include -I lib/src -I port -I port/cortex-m4f lib/src/*.c 2>"$out/misra_raw.txt" || true
if grep -v -E '^[^:]+:[0-9]+: misra-c2012-[0-9]+\.[0-9]+$' "$out/misra_raw.txt" | grep -q .; then
  echo "$name: FAIL: cppcheck misra addon did not run cleanly:" >&2
  grep -v -E '^[^:]+:[0-9]+: misra-c2012-' "$out/misra_raw.txt" | head -n 20 >&2
  fail=1
fi
python3 - "$out/misra_raw.txt" "$out/misra_report.txt" "$src/docs/reliability.md" "$(cppcheck --version)" <<'PY' || fail=1
import re, sys, collections
raw, report, doc, version = sys.argv[1:5]
rows = []
for line in open(raw):
    m = re.match(r'^([^:]+):(\d+): misra-c2012-(\d+\.\d+)$', line.strip())
    if m:
        rows.append((m.group(1), int(m.group(2)), m.group(3)))
key = lambda r: tuple(int(x) for x in r.split('.'))
count = collections.Counter(r for _, _, r in rows)
files = collections.defaultdict(collections.Counter)
for f, _, r in rows:
    files[r][f] += 1
with open(report, 'w') as out:
    out.write('# MISRA C:2012 report of lib/src (cppcheck misra addon)\n')
    out.write('# Generated by tests/scripts/test_static_analysis.sh; %s.\n' % version)
    out.write('# cppcheck --addon=misra --std=c99 --inline-suppr -I lib/include -I lib/src -I port '
              '-I port/cortex-m4f lib/src/*.c\n')
    out.write('# Rule texts are not shipped with cppcheck: see docs/reliability.md for the\n')
    out.write('# topic of each rule and the deviation rationale.\n#\n')
    out.write('# rule      count  files\n')
    for r in sorted(count, key=key):
        fl = ', '.join('%s (%d)' % (f.split('/')[-1], n) for f, n in sorted(files[r].items()))
        out.write('# %-8s %6d  %s\n' % (r, count[r], fl))
    out.write('# total    %6d\n#\n' % len(rows))
    for f, n, r in sorted(rows, key=lambda x: (x[0], x[1], key(x[2]))):
        out.write('%s:%d: %s\n' % (f, n, r))
documented = set(re.findall(r'^\|\s*(\d+\.\d+)\s*\|', open(doc).read(), re.M))
undocumented = sorted(set(count) - documented, key=key)
print('test_static_analysis: MISRA C:2012 (cppcheck addon): %d findings of %d rules, all with a '
      'documented deviation' % (len(rows), len(count)) if not undocumented else '')
for r in undocumented:
    sites = ', '.join('%s:%d' % (f, n) for f, n, rr in rows if rr == r)
    print('test_static_analysis: FAIL: MISRA rule %s (%d findings: %s) has no deviation row in '
          'docs/reliability.md' % (r, count[r], sites), file=sys.stderr)
sys.exit(1 if undocumented else 0)
PY
if [ "${SFIT_MISRA_UPDATE:-0}" = "1" ]; then
  cp "$out/misra_report.txt" "$src/docs/misra_report.txt"
  echo "$name: docs/misra_report.txt updated"
elif [ -f "$src/docs/misra_report.txt" ] \
     && ! diff -q <(grep '^# [0-9]' "$src/docs/misra_report.txt") <(grep '^# [0-9]' "$out/misra_report.txt") >/dev/null; then
  echo "$name: note: MISRA counts differ from docs/misra_report.txt (regenerate with SFIT_MISRA_UPDATE=1):"
  diff <(grep '^# [0-9]' "$src/docs/misra_report.txt") <(grep '^# [0-9]' "$out/misra_report.txt") || true
fi

[ "$fail" -eq 0 ] || exit 1
echo "$name: ok"
