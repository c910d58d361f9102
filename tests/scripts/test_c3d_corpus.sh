#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The C3D corpus (docs/c3d.md): every file of ../shared/data/c3d/corpus/
# (c3d.org's 50 sample files, MANIFEST.tsv: system, sha256, what a reader
# must do, the frames x points an independent reader reads) and the other
# shared recordings, read by `sfit c3d` and by the independent reader
# tests/scripts/c3d_ref.py: each `identical` file with the manifest's counts,
# the same labels and every sample bit for bit; each `refuse` file refused
# with a message naming the conflict; every file read written back with a
# point added and read again, with the same frame count, by the strict
# independent reader and by sfit (tests/scripts/c3d_corpus.py).
# The corpus is read from ../shared/data beside the source tree
# (SFIT_SHARED_DATA overrides); absent, the test fails in CI (CI=true).
# Usage: test_c3d_corpus.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 src=$2
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
cli_setup test_c3d_corpus "$build" "$src"
/usr/bin/python3 -c 'import numpy' 2>/dev/null || missing "python3-numpy not installed"
shared=${SFIT_SHARED_DATA:-$src/../shared/data}
[ -f "$shared/c3d/corpus/MANIFEST.tsv" ] || missing "C3D corpus not found at $shared/c3d/corpus"
PYTHONPATH="$src/tests/scripts" /usr/bin/python3 "$src/tests/scripts/c3d_corpus.py" "$sfit" "$shared" "$tmp" \
  || fail "C3D corpus"
echo "$name: all checks passed"
