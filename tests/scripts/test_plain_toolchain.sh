#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# sfit in a firmware project that brings its own toolchain file
# (tests/consumer/toolchain-plain.cmake: -mcpu=cortex-m4 -mthumb
# -mfpu=fpv4-sp-d16 -mfloat-abi=hard and nothing else, no sfit flags):
#  0. the README's `cmake --preset cortex-m4f` + build exits 0 and the cross
#     build installs (headers, libsfit.a, CMake package, sfit.pc);
#  1. sfit built with the plain toolchain at -Os and installed: libsfit.a
#     calls no sqrtf (one vsqrt.f32 per square root instead);
#  2. find_package(sfit) of that install: the whole library linked into an
#     ELF, a known-answer fit run under QEMU mps2-an386;
#  3. add_subdirectory(sfit) at -O2: the same, and again no sqrtf;
#  4. pkg-config of the install: arm-none-eabi-gcc links and runs the same;
#  5. the sqrtf check can fail: a library source compiled with the plain
#     flags but without -fno-math-errno does call sqrtf;
#  6. a parent's set(SFIT_PORT ...) before add_subdirectory is honoured on
#     the first configure.
# Usage: test_plain_toolchain.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd)
name=test_plain_toolchain
# shellcheck source=tests/scripts/common.sh
. "$(dirname "$0")/common.sh"
for t in arm-none-eabi-gcc arm-none-eabi-nm arm-none-eabi-objdump qemu-system-arm pkg-config; do
  command -v "$t" >/dev/null 2>&1 || missing "$t not found"
done
work="$build/plain_toolchain"
rm -rf "$work"
mkdir -p "$work"
fail() { echo "$name: FAIL: $*" >&2; exit 1; }
tc="$src/tests/consumer/toolchain-plain.cmake"
board="$src/port/cortex-m4f/qemu"
run() { "$board/run.sh" "$@"; }
q() { # q LOG CMD...: run quietly, show the log on failure
  local log=$1; shift
  "$@" >"$log" 2>&1 || { cat "$log" >&2; fail "'$*' (log $log)"; }
}
no_sqrtf() { # no_sqrtf LIB WHAT: no reference to sqrtf, at least one vsqrt.f32
  local n_call n_vsqrt
  n_call=$(arm-none-eabi-nm -A "$1" | grep -cE ' U sqrtf$' || true)
  n_vsqrt=$(arm-none-eabi-objdump -d "$1" | grep -cE '\svsqrt\.f32\s' || true)
  echo "$2: objects referencing sqrtf: $n_call, vsqrt.f32 instructions: $n_vsqrt"
  [ "$n_call" -eq 0 ] || fail "$2: $n_call objects of $1 call sqrtf"
  [ "$n_vsqrt" -gt 0 ] || fail "$2: no vsqrt.f32 in $1"
}
kat() { # kat ELF WHAT: the known-answer fit passes under QEMU
  local out
  out=$(run "$1" 2>&1) || { printf '%s\n' "$out" >&2; fail "$2: the ELF exited non-zero"; }
  printf '%s\n' "$out"
  printf '%s\n' "$out" | grep -q '^plain consumer: PASS$' || fail "$2: no PASS line"
  if arm-none-eabi-nm "$1" | grep -qE ' [Tt] sqrtf$'; then fail "$2: libm sqrtf linked into $1"; fi
}

# 0. The README's preset (binary dir moved into the build tree), and install.
(cd "$src" && q "$work/preset.log" cmake --preset cortex-m4f -B "$work/preset")
q "$work/preset-build.log" cmake --build "$work/preset" -j2
q "$work/preset-install.log" cmake --install "$work/preset" --prefix "$work/preset-prefix"
for f in include/sfit/sfit.h lib/libsfit.a lib/cmake/sfit/sfitConfig.cmake lib/pkgconfig/sfit.pc; do
  [ -f "$work/preset-prefix/$f" ] || fail "cortex-m4f preset: $f not installed"
done
if find "$work/preset" -name 'test_*' -type f -perm -u+x | grep -q .; then
  fail "cortex-m4f preset built host test executables"
fi
echo "preset cortex-m4f: configure, build and install ok (library only)"

# 1. sfit with the plain toolchain at -Os, installed.
q "$work/lib.log" cmake -S "$src" -B "$work/lib" -DCMAKE_TOOLCHAIN_FILE="$tc" -DCMAKE_BUILD_TYPE=MinSizeRel
q "$work/lib-build.log" cmake --build "$work/lib" -j2
q "$work/lib-install.log" cmake --install "$work/lib" --prefix "$work/prefix"
no_sqrtf "$work/prefix/lib/libsfit.a" "plain toolchain -Os (installed)"

# 2. find_package of the cross install (the toolchain searches packages
#    only under CMAKE_FIND_ROOT_PATH, as firmware toolchain files do).
q "$work/pkg.log" cmake -S "$src/tests/consumer" -B "$work/pkg" -DCMAKE_TOOLCHAIN_FILE="$tc" \
  -DCMAKE_BUILD_TYPE=MinSizeRel -DSFIT_VIA=package -DCMAKE_FIND_ROOT_PATH="$work/prefix" \
  -DCMAKE_PREFIX_PATH=/ -DBOARD_DIR="$board"
q "$work/pkg-build.log" cmake --build "$work/pkg"
kat "$work/pkg/fw.elf" "find_package"
# The whole library is in the ELF: every function libsfit.a defines.
arm-none-eabi-nm "$work/prefix/lib/libsfit.a" | awk '$2 == "T" { print $3 }' | sort -u >"$work/lib.syms"
arm-none-eabi-nm "$work/pkg/fw.elf" | awk '$2 == "T" { print $3 }' | sort -u >"$work/elf.syms"
nmiss=$(comm -23 "$work/lib.syms" "$work/elf.syms" | wc -l)
[ "$nmiss" -eq 0 ] || fail "$nmiss functions of libsfit.a not in the ELF: $(comm -23 "$work/lib.syms" "$work/elf.syms" | head -3)"
echo "find_package: all $(wc -l <"$work/lib.syms") functions of libsfit.a linked into fw.elf"

# 3. add_subdirectory at -O2.
q "$work/sub.log" cmake -S "$src/tests/consumer" -B "$work/sub" -DCMAKE_TOOLCHAIN_FILE="$tc" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSFIT_VIA=subdirectory -DSFIT_SRC="$src" -DBOARD_DIR="$board"
q "$work/sub-build.log" cmake --build "$work/sub" -j2
no_sqrtf "$work/sub/sfit/lib/libsfit.a" "plain toolchain -O2 (add_subdirectory)"
kat "$work/sub/fw.elf" "add_subdirectory"
if find "$work/sub" -name 'test_*' -type f | grep -q . || [ -e "$work/sub/bin/sfit" ]; then
  fail "add_subdirectory built tests or tools"
fi

# 4. pkg-config of the same install, by hand.
arch=(-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard)
pc=$(PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" pkg-config --cflags --libs sfit)
case " $pc " in *" -lm "*) ;; *) fail "pkg-config --libs sfit has no -lm: $pc" ;; esac
# shellcheck disable=SC2086 # pkg-config output is a word list
arm-none-eabi-gcc "${arch[@]}" -std=c99 -Os "$src/tests/consumer/main.c" "$board/startup.c" \
  -Wl,--whole-archive "$work/prefix/lib/libsfit.a" -Wl,--no-whole-archive $pc \
  --specs=nano.specs --specs=rdimon.specs -L"$board" -T "$board/mps2_an386.ld" \
  -o "$work/pc.elf" || fail "pkg-config link"
kat "$work/pc.elf" "pkg-config"

# 5. The check above can fail: without -fno-math-errno, -Os calls sqrtf.
arm-none-eabi-gcc "${arch[@]}" -std=c99 -Os -I"$src/lib/include" -I"$src/lib/src" -I"$src/port" \
  -I"$src/port/cortex-m4f" -c "$src/lib/src/sfit_mat3.c" -o "$work/errno.o"
if arm-none-eabi-nm "$work/errno.o" | grep -qE ' U sqrtf$'; then
  echo "control: without -fno-math-errno sfit_mat3.o calls sqrtf (the check sees it)"
else
  fail "control: sfit_mat3.c without -fno-math-errno does not call sqrtf; the check proves nothing"
fi

# 6. A parent's SFIT_PORT wins on the first configure (host compiler, whose
#    default port would be host).
mkdir -p "$work/parent"
cat >"$work/parent/CMakeLists.txt" <<CMK
cmake_minimum_required(VERSION 3.16)
project(parent C)
set(SFIT_PORT cortex-m4f)
set(SFIT_BUILD_TOOLS ON)
add_subdirectory("$src" sfit)
get_target_property(_inc sfit INCLUDE_DIRECTORIES)
message(STATUS "parent: sfit include dirs: \${_inc}")
if(NOT TARGET sfit_cli)
  message(FATAL_ERROR "parent: SFIT_BUILD_TOOLS ON was not honoured")
endif()
CMK
q "$work/parent.log" cmake -S "$work/parent" -B "$work/parent-build"
grep -q 'sfit [0-9.]*: port cortex-m4f' "$work/parent.log" || fail "parent SFIT_PORT not honoured: $(grep 'port' "$work/parent.log")"
grep -q 'include dirs: .*port/cortex-m4f' "$work/parent.log" || fail "sfit not compiled with port/cortex-m4f"
echo "parent: set(SFIT_PORT cortex-m4f) and set(SFIT_BUILD_TOOLS ON) honoured on the first configure"
echo "$name: ok"
