#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The long fuzz campaign (issue 19), outside CI: every harness of tests/fuzz
# for SECONDS seconds of wall time each, JOBS at a time, and the total number
# of executions.
#
#   tests/fuzz/campaign.sh SECONDS [BUILD_DIR] [JOBS]
#
#   SECONDS    wall time per harness (e.g. 1800)
#   BUILD_DIR  where the harnesses are built (default: build-fuzz-campaign)
#   JOBS       harnesses run at once (default: the number of cores)
#
# 1. Builds and checks every harness with tests/scripts/test_fuzz.sh (clang
#    -fsanitize=fuzzer,address,undefined; the committed seeds are replayed,
#    then a 1 s session each) into BUILD_DIR/fuzz.
# 2. Runs each harness for SECONDS on its own corpus, kept between runs in
#    BUILD_DIR/campaign/corpus_<name> (seeded from tests/fuzz/corpus), with
#    seed SFIT_FUZZ_SEED (default: the date, so runs differ), -max_len=4096.
# 3. Prints one line per harness (executions, edges, corpus size, result)
#    and the total. A finding (crash, sanitizer report, contract violation,
#    timeout, leak) is left in BUILD_DIR/campaign/artifacts/ and the script
#    exits 1; reproduce with BUILD_DIR/fuzz/fuzz_<name> <file>. Then turn it
#    into a regression test and a seed (tests/fuzz/README.md).
set -euo pipefail
[ $# -ge 1 ] || { sed -n '3,24p' "$0"; exit 2; }
seconds=$1
src=$(cd "$(dirname "$0")/../.." && pwd)
build=${2:-$src/build-fuzz-campaign}
jobs=${3:-$(nproc 2>/dev/null || echo 2)}
seed=${SFIT_FUZZ_SEED:-$(date +%s)}
mkdir -p "$build"
build=$(cd "$build" && pwd)
out="$build/campaign"

SFIT_FUZZ_SECONDS=1 bash "$src/tests/scripts/test_fuzz.sh" "$build" "$src" >"$build/build.log" 2>&1 \
  || { tail -n 30 "$build/build.log" >&2; echo "campaign: FAIL: build or seed replay" >&2; exit 1; }
mkdir -p "$out/artifacts"

run_one() {
  local hn=$1 name=${1#fuzz_}
  local work="$out/corpus_$name"
  mkdir -p "$work"
  cp -n "$src/tests/fuzz/corpus/$name"/* "$work"/ 2>/dev/null || true
  "$build/fuzz/$hn" -seed="$seed" -max_total_time="$seconds" -max_len=4096 -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$out/artifacts/$hn-" \
    "$work" >"$out/$hn.log" 2>&1
  echo $? >"$out/$hn.rc"
}

harnesses=()
for h in "$build"/fuzz/fuzz_*; do
  [ -x "$h" ] && [ "${h%.log}" = "$h" ] && harnesses+=("$(basename "$h")")
done
[ "${#harnesses[@]}" -gt 0 ] || { echo "campaign: FAIL: no harness built" >&2; exit 1; }
echo "campaign: ${#harnesses[@]} harnesses x ${seconds} s, $jobs at a time, seed $seed"

running=0
for hn in "${harnesses[@]}"; do
  run_one "$hn" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true

total=0
fail=0
for hn in "${harnesses[@]}"; do
  rc=$(cat "$out/$hn.rc" 2>/dev/null || echo 99)
  execs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\).*/\1/p' "$out/$hn.log" | tail -n 1)
  cov=$(grep -Eo 'cov: [0-9]+' "$out/$hn.log" | tail -n 1 || true)
  ncorp=$(find "$out/corpus_${hn#fuzz_}" -type f | wc -l)
  if [ -z "$execs" ]; then
    # a finding stops libFuzzer before the final stats: take the last status line
    execs=$(grep -Eo '^#[0-9]+' "$out/$hn.log" | tail -n 1 | tr -d '#' || true)
  fi
  total=$((total + ${execs:-0}))
  if [ "$rc" -ne 0 ]; then
    fail=1
    echo "campaign: $hn: FINDING after ${execs:-?} executions (exit $rc), log $out/$hn.log"
    grep -E 'contract violated|runtime error|ERROR: |SUMMARY|Test unit written' "$out/$hn.log" | head -n 8 || true
  else
    echo "campaign: $hn: ${execs} executions, ${cov:-cov: ?} edges, corpus $ncorp inputs, no finding"
  fi
done
echo "campaign: total $total executions in ${#harnesses[@]} harnesses (${seconds} s each, seed $seed)"
[ "$fail" -eq 0 ] || exit 1
