#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One name, one file: every public function's prefix names the header that
# declares it and the source that defines it (tests/scripts/api_names.py),
# and the check fails on a violation (a copy of the tree with one function
# moved, one declared twice and one stray prefix must each fail).
# Usage: test_api_names.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
src=$2
name=test_api_names
# shellcheck source=tests/scripts/common.sh
. "$src/tests/scripts/common.sh"
rule_setup "$src/tests/scripts/api_names.py"
fresh() { rm -rf "$tmp/t"; mkdir -p "$tmp/t/lib"; cp -r "$src/lib/include" "$src/lib/src" "$tmp/t/lib/"; }

# 1. a function declared under another family's header
fresh
printf 'sfit_status_t sfit_moments_extra(const sfit_moments_t *m);\n' >> "$tmp/t/lib/include/sfit/sfit_fit.h"
printf 'sfit_status_t sfit_moments_extra(const sfit_moments_t *m) { (void)m; return SFIT_OK; }\n' >> "$tmp/t/lib/src/sfit_moments.c"
must_fail "sfit_moments_extra declared in sfit_fit.h"
# 2. a function defined in another family's source
fresh
printf 'sfit_status_t sfit_moments_extra(const sfit_moments_t *m);\n' >> "$tmp/t/lib/include/sfit/sfit_moments.h"
printf 'sfit_status_t sfit_moments_extra(const sfit_moments_t *m) { (void)m; return SFIT_OK; }\n' >> "$tmp/t/lib/src/sfit_fit.c"
must_fail "sfit_moments_extra defined in sfit_fit.c"
# 3. a prefix that names no header
fresh
printf 'int sfit_points_count(void);\n' >> "$tmp/t/lib/include/sfit/sfit_fit.h"
must_fail "sfit_points_count (no sfit_points.h)"
# 4. a header left with no function of its own
fresh
sed -i 's/sfit_status_str/prv_status_str/' "$tmp/t/lib/include/sfit/sfit_status.h" "$tmp/t/lib/src/sfit_status.c"
must_fail "sfit_status.h without an sfit_status_* function"
