#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Bounded libFuzzer session over every public API (tests/fuzz/README.md).
#
#   test_fuzz.sh BUILD_DIR SOURCE_DIR
#
# Builds each tests/fuzz/fuzz_*.c with clang -fsanitize=fuzzer,address,undefined
# (-fno-sanitize-recover=all) against the library sources in BUILD_DIR/fuzz,
# replays the committed seed corpus, then fuzzes each harness for
# SFIT_FUZZ_SECONDS seconds (default: 45 when CI=true, 10 otherwise) with a
# fixed seed (SFIT_FUZZ_SEED, default 1) on a scratch copy of the corpus.
# Any crash, sanitizer report, contract violation, timeout or leak fails
# the test; the reproducer is left in BUILD_DIR/fuzz/artifacts/.
# Prints the number of executions of each harness.
#
# Exit 77 (skipped) when clang or its libFuzzer runtime is missing, unless
# CI=true (then a missing tool is a failure).
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
out="$build/fuzz"
name=test_fuzz

# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"

CLANG=${SFIT_FUZZ_CC:-clang}
command -v "$CLANG" >/dev/null 2>&1 || missing "$CLANG not found"
rm -rf "$out"
mkdir -p "$out/obj" "$out/artifacts"

# libFuzzer's runtime ships in libclang-rt-<ver>-dev on Debian.
printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n);\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n' \
  > "$out/probe.c"
"$CLANG" -fsanitize=fuzzer "$out/probe.c" -o "$out/probe" >/dev/null 2>&1 \
  || missing "$CLANG cannot link -fsanitize=fuzzer (install libclang-rt-14-dev)"

if [ -n "${SFIT_FUZZ_SECONDS:-}" ]; then
  seconds=$SFIT_FUZZ_SECONDS
elif [ "${CI:-}" = "true" ]; then
  seconds=45
else
  seconds=10
fi
seed=${SFIT_FUZZ_SEED:-1}

san=(-fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all)
common=(-std=c99 -g -O1 -fno-omit-frame-pointer
        -I"$src/lib/include" -I"$src/lib/src" -I"$src/port" -I"$src/port/host")
# The harnesses are held to the project's warning set; the library is
# checked warning-clean by the gcc and clang builds, so it gets no -Werror here.
warn=(-Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes -Wmissing-prototypes
      -Wcast-qual -Wconversion -Wsign-conversion -Wdouble-promotion -Wundef -Wvla
      -Wswitch-enum -Wwrite-strings -Werror)

libobjs=()
for c in "$src"/lib/src/*.c; do
  o="$out/obj/lib_$(basename "${c%.c}").o"
  # -fsanitize=fuzzer-no-link: coverage instrumentation without libFuzzer's main.
  "$CLANG" "${common[@]}" -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all \
    -c "$c" -o "$o"
  libobjs+=("$o")
done

harnesses=()
for h in "$src"/tests/fuzz/fuzz_*.c; do
  hn=$(basename "${h%.c}")
  # tools/gen: headers the build generates for the host tools (the skeleton
  # page's script, tools/CMakeLists.txt) that a harness including a tool
  # source needs
  "$CLANG" "${common[@]}" "${warn[@]}" "${san[@]}" -I"$src/tests/fuzz" -I"$src/tools/formats" -I"$src/tools/lab" -I"$build/tools/gen" \
    "$h" "${libobjs[@]}" -lm -o "$out/$hn"
  harnesses+=("$hn")
done
[ "${#harnesses[@]}" -gt 0 ] || { echo "$name: FAIL: no harness in tests/fuzz" >&2; exit 1; }

fail=0
total_execs=0
for hn in "${harnesses[@]}"; do
  corpus_name=${hn#fuzz_}
  seeds="$src/tests/fuzz/corpus/$corpus_name"
  [ -d "$seeds" ] || { echo "$name: FAIL: no seed corpus $seeds" >&2; fail=1; continue; }
  work="$out/corpus_$corpus_name"
  mkdir -p "$work"
  cp "$seeds"/* "$work"/

  # 1. Every committed seed must pass (regression inputs included).
  if ! "$out/$hn" -runs=0 -artifact_prefix="$out/artifacts/$hn-seed-" "$seeds" \
       > "$out/$hn.replay.log" 2>&1; then
    echo "$name: FAIL: $hn: a seed input violates the contract:" >&2
    grep -E 'contract violated|runtime error|ERROR: AddressSanitizer|SUMMARY' "$out/$hn.replay.log" >&2 || tail -n 30 "$out/$hn.replay.log" >&2
    fail=1
    continue
  fi

  # 2. The bounded session.
  set +e
  "$out/$hn" -seed="$seed" -max_total_time="$seconds" -max_len=2048 -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$out/artifacts/$hn-" \
    "$work" > "$out/$hn.log" 2>&1
  rc=$?
  set -e
  execs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\).*/\1/p' "$out/$hn.log" | tail -n 1)
  cov=$(grep -Eo 'cov: [0-9]+' "$out/$hn.log" | tail -n 1 || true)
  ncorp=$(find "$work" -type f | wc -l)
  if [ "$rc" -ne 0 ]; then
    echo "$name: FAIL: $hn: finding after ${execs:-?} executions (exit $rc):" >&2
    grep -E 'contract violated|runtime error|ERROR: |SUMMARY|Test unit written|Base64' "$out/$hn.log" >&2 || tail -n 40 "$out/$hn.log" >&2
    fail=1
    continue
  fi
  [ -n "$execs" ] || { echo "$name: FAIL: $hn: no final stats in $out/$hn.log" >&2; fail=1; continue; }
  total_execs=$((total_execs + execs))
  echo "$name: $hn: ${seconds} s, seed $seed: $execs executions, ${cov:-cov: ?} edges, corpus $ncorp inputs, no finding"
done

[ "$fail" -eq 0 ] || exit 1
echo "$name: ok: ${#harnesses[@]} harnesses, $total_execs executions in total, no finding"
