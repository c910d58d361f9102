#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The user documentation (README.md, docs/*.md) against the tree and the
# CLI: relative links and anchors exist, every `$ sfit ...` command shown
# prints what is shown under it, and the README's demo prints its output
# block (tests/scripts/doc_check.py). Usage: test_docs.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
name=test_docs
# shellcheck source=tests/scripts/common.sh
. "$src/tests/scripts/common.sh"
[ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
[ -x "$build/bin/sfit" ] || { echo "FAIL: $build/bin/sfit not built" >&2; exit 1; }
/usr/bin/python3 "$src/tests/scripts/doc_check.py" "$build" "$src"
