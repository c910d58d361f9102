#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Every module has every step: the table of docs/modules.md against the
# tree (tests/scripts/modules_check.py), and the check fails on a module
# that misses a step (copies of the tree, each with one step removed).
# Usage: test_modules.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
src=$2
name=test_modules
# shellcheck source=tests/scripts/common.sh
. "$src/tests/scripts/common.sh"
rule_setup "$src/tests/scripts/modules_check.py"
rooms() { awk -F'\t' '!/^#/ && NF >= 2 { print $2 }' "$src/tools/rooms.tsv"; }
fresh() {
  rm -rf "$tmp/t"; mkdir -p "$tmp/t"
  (cd "$src" && tar cf - --exclude=tests/data --exclude='tests/fuzz/corpus' docs lib tests \
     tools/flopcount/footprint_budget.txt tools/rooms.tsv $(rooms)) | tar xf - -C "$tmp/t"
}
fresh; sed -i '/^code_os sfit_gate /d' "$tmp/t/tools/flopcount/footprint_budget.txt"
must_fail "no code-size budget for gate"
fresh; rm "$tmp/t/tests/test_refine.c"
must_fail "no tests/test_refine.c"
fresh; printf 'int sfit_extra_x(void);\nint sfit_extra_x(void) { return 0; }\n' > "$tmp/t/lib/src/sfit_extra.c"
must_fail "a library source in no table"
fresh; sed -i 's/^| incr | \(.*\) | garbage_driver.h | /| incr | \1 | n\/a: no state | /' "$tmp/t/docs/modules.md"
must_fail "a state without a garbage-state entry (incr)"
fresh; sed -i 's/sfit_joint_/sfit_xjoint_/g' "$tmp/t/tests/fuzz/fuzz_joint.c"
must_fail "a fuzz harness that does not call the module (joint)"
fresh; sed -i 's/ref_fit_geometric(/ref_fit_geometric_gone(/' "$tmp/t/tests/test_refine.c"
must_fail "a reference the test does not call (refine)"
fresh; sed -i '/^| cluster /d' "$tmp/t/docs/modules.md"
must_fail "a public header without a row (cluster)"
