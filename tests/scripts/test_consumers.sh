#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# sfit as a dependency, the three ways a project consumes it, each building
# and running the README's C example:
#   1. add_subdirectory() (tests and tools must not be built then),
#   2. find_package(sfit) after `cmake --install`,
#   3. pkg-config after the same install.
# Usage: test_consumers.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd)
work="$build/consumers"
rm -rf "$work"
mkdir -p "$work/app"
fail() { echo "FAIL: $*" >&2; exit 1; }

# The README example, between its markers.
sed -n '/<!-- example:begin -->/,/<!-- example:end -->/p' "$src/README.md" \
  | sed '1,/^```c$/d; /^```$/,$d' > "$work/app/main.c"
[ -s "$work/app/main.c" ] || fail "README example not found"

# 1. add_subdirectory
cat > "$work/app/CMakeLists.txt" <<CMK
cmake_minimum_required(VERSION 3.16)
project(sfit_consumer_sub C)
add_subdirectory("$src" sfit)
add_executable(app main.c)
target_link_libraries(app PRIVATE sfit::sfit)
CMK
cmake -S "$work/app" -B "$work/sub" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/sub" >/dev/null
"$work/sub/app" | tee "$work/sub.out"
grep -q "centre" "$work/sub.out" || fail "example output"
if cmake --build "$work/sub" --target help | grep -Eq 'test_fit|sfit_cli'; then
  fail "tests or tools are built when sfit is a subdirectory"
fi

# 2. install + find_package
cmake --install "$build" --prefix "$work/prefix" >/dev/null
[ -f "$work/prefix/lib/pkgconfig/sfit.pc" ] || [ -f "$work/prefix/lib/x86_64-linux-gnu/pkgconfig/sfit.pc" ] \
  || fail "no pkg-config file installed"
mkdir -p "$work/app2"
cp "$work/app/main.c" "$work/app2/"
cat > "$work/app2/CMakeLists.txt" <<'CMK'
cmake_minimum_required(VERSION 3.16)
project(sfit_consumer_pkg C)
find_package(sfit 0.3 REQUIRED CONFIG)
add_executable(app main.c)
target_link_libraries(app PRIVATE sfit::sfit)
CMK
cmake -S "$work/app2" -B "$work/pkg" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/pkg" >/dev/null
"$work/pkg/app" >/dev/null || fail "find_package consumer"

# 3. pkg-config
pcdir=$(dirname "$(find "$work/prefix" -name sfit.pc | head -n 1)")
flags=$(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags --libs --static sfit)
# shellcheck disable=SC2086
cc -std=c99 -Wall -Wextra -Werror "$work/app/main.c" $flags -o "$work/app_pc" -lm
"$work/app_pc" >/dev/null || fail "pkg-config consumer"
echo "consumers: add_subdirectory, find_package and pkg-config all build and run the README example"
