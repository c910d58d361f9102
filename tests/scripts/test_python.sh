#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The Python package (tools/python): build the extension from lib/src into
# the build tree and run its pytest suite with Debian's /usr/bin/python3,
# against the CLI of this build (bin/sfit). Missing python3-dev, -numpy,
# -pytest or -setuptools: skip, or fail in CI (CI=true).
# Usage: test_python.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
name=python
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd)
. "$src/tests/scripts/common.sh"
py=/usr/bin/python3
[ -x "$py" ] || missing "$py not found (python3)"
for mod in numpy pytest setuptools; do
  "$py" -c "import $mod" 2>/dev/null || missing "python module $mod (python3-$mod)"
done
inc=$("$py" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')
[ -f "$inc/Python.h" ] || missing "Python.h (python3-dev)"

out="$build/python"
rm -rf "$out"
(cd "$src/tools/python" && "$py" setup.py -q build --build-lib "$out/lib" --build-temp "$out/temp" \
  --force) > "$out.build.log" 2>&1 || { cat "$out.build.log"; echo "python: FAIL: build" >&2; exit 1; }
# the extension must compile without a warning
if grep -E ": warning:" "$out.build.log"; then
  echo "python: FAIL: compiler warnings" >&2
  exit 1
fi

export PYTHONPATH="$out/lib" PYTHONDONTWRITEBYTECODE=1 SFIT_CLI="$build/bin/sfit" SFIT_SOURCE_DIR="$src"
cd "$out"
"$py" -c 'import sfit, sys; assert sfit.__file__.startswith(sys.argv[1]), sfit.__file__' "$out/lib"
exec "$py" -m pytest -q -p no:cacheprovider "$src/tools/python/tests"
