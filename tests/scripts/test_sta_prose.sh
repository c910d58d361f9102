#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The soft-tissue benchmark's summary table in docs/joint_benchmark.md is
# the one docs/figures/sta_bench.csv measured (tests/scripts/sta_prose.py),
# and the check fails on copies of the docs with a drifted figure.
# Usage: test_sta_prose.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
name=test_sta_prose
: "$build"
# shellcheck source=tests/scripts/common.sh
. "$src/tests/scripts/common.sh"
rule_setup "$src/tests/scripts/sta_prose.py"
fresh() {
  rm -rf "$tmp/t"; mkdir -p "$tmp/t/docs/figures"
  cp "$src/docs/joint_benchmark.md" "$tmp/t/docs/"
  cp "$src/docs/figures/sta_bench.csv" "$tmp/t/docs/figures/"
}
fresh
/usr/bin/python3 "$rule_check" "$tmp/t" > /dev/null || { echo "FAIL: the copy itself does not pass" >&2; exit 1; }
row() { grep -n "^| $1, " "$tmp/t/docs/joint_benchmark.md" | cut -d: -f1; }
fresh; sed -i "$(row 'rigid cluster motion')s/(all: \([0-9.]*\) %)/(all: 99.9 %)/" "$tmp/t/docs/joint_benchmark.md"
must_fail "a drifted overall coverage"
fresh; sed -i "$(row 'per-marker motion + drift')s/| \([0-9.]*\)-\([0-9.]*\) | \([0-9.]*\)-/| 0.5-\2 | \3-/" "$tmp/t/docs/joint_benchmark.md"
must_fail "a drifted median d'C^-1 d"
fresh; sed -i "$(row 'marker noise only')s/| \([0-9]*\) of \([0-9]*\) |/| \1 of 200 |/" "$tmp/t/docs/joint_benchmark.md"
must_fail "a drifted trial count"
fresh; sed -i '0,/^ball rigid,/s/^\(ball rigid,rigid,20,0.5,2,[0-9]*,[0-9]*,[0-9]*,[0-9]*,\)[0-9.]*/\10.5000/' "$tmp/t/docs/figures/sta_bench.csv"
must_fail "a re-run benchmark the prose was not updated for"
echo "test_sta_prose: ok"
