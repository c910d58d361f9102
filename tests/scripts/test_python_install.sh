#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The README's Python install command, run as written (into a private user
# site under the build tree: PYTHONUSERBASE), then the README's one-liner
# from the repository root, which must import the installed package.
# Needs python3-pip besides the packages of test_python.sh; skip without
# them, fail in CI (CI=true).
# Usage: test_python_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
name=python_install
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd)
. "$src/tests/scripts/common.sh"
py=/usr/bin/python3
[ -x "$py" ] || missing "$py not found (python3)"
for mod in numpy setuptools pip; do
  "$py" -c "import $mod" 2>/dev/null || missing "python module $mod (python3-$mod)"
done

block() { # the shell command between the README markers $1:begin / $1:end
  sed -n "/<!-- $1:begin -->/,/<!-- $1:end -->/p" "$src/README.md" | sed '1,/^```sh$/d; /^```$/,$d'
}
install_cmd=$(block python-install)
oneliner=$(block python-oneliner)
[ -n "$install_cmd" ] && [ -n "$oneliner" ] || { echo "python_install: FAIL: README blocks" >&2; exit 1; }

export PYTHONUSERBASE="$build/python-userbase" PYTHONDONTWRITEBYTECODE=1 PIP_NO_INDEX=1
unset PYTHONPATH
rm -rf "$PYTHONUSERBASE"
cd "$src"
echo "+ $install_cmd"
bash -c "$install_cmd" > "$build/python-install.log" 2>&1 || { cat "$build/python-install.log"; exit 1; }
where=$("$py" -c 'import sfit; print(sfit.__file__)')
case "$where" in
  "$PYTHONUSERBASE"/*) ;;
  *) echo "python_install: FAIL: sfit imported from $where, not the install" >&2; exit 1 ;;
esac
echo "+ $oneliner"
bash -c "$oneliner" | tee "$build/python-oneliner.out"
grep -Eq '^\[ *[0-9.-]+ +[0-9.-]+ +[0-9.-]+ *\]$' "$build/python-oneliner.out"
