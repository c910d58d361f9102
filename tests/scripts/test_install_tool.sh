#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `cmake --install BUILD --prefix P` puts bin/sfit beside the library, and
# `P/bin/sfit --version` prints the version of project() in CMakeLists.txt
# (passed to the CLI by the build, not written in its source).
# Usage: test_install_tool.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd)
name=test_install_tool
fail() { echo "$name: FAIL: $*" >&2; exit 1; }
P="$build/install_tool"
rm -rf "$P"
cmake --install "$build" --prefix "$P" >"$build/install_tool.log" 2>&1 || { cat "$build/install_tool.log" >&2; fail "install"; }
[ -x "$P/bin/sfit" ] || fail "no $P/bin/sfit"
ls "$P"/lib*/libsfit.a >/dev/null 2>&1 || ls "$P"/lib/*/libsfit.a >/dev/null 2>&1 || fail "no libsfit.a"
want=$(sed -n 's/^project(sfit VERSION \([0-9][0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
[ -n "$want" ] || fail "no version in CMakeLists.txt"
got=$("$P/bin/sfit" --version)
[ "$got" = "sfit $want" ] || fail "'sfit --version' printed '$got', CMakeLists.txt says $want"
"$P/bin/sfit" --help | head -n 1 | grep -q "^sfit $want:" || fail "--help shows another version"
echo "installed bin/sfit --version: $got (CMakeLists.txt: $want)"
