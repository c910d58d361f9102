# SPDX-License-Identifier: MIT
#
# CMake toolchain file: Cortex-M4F (FPv4-SP, hard-float ABI) with Debian's
# arm-none-eabi-gcc + newlib, test programs run under QEMU mps2-an386.
#
#   cmake -S . -B build-m4f \
#         -DCMAKE_TOOLCHAIN_FILE=port/cortex-m4f/toolchain.cmake
#
# SFIT_ARM_CORE picks another Cortex-M core for the same port (set it before
# including this file, or use the wrappers toolchain-m33.cmake and
# toolchain-m3.cmake):
#   cortex-m4f  -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard   QEMU mps2-an386
#   cortex-m33  -mcpu=cortex-m33 -mfpu=fpv5-sp-d16 -mfloat-abi=hard  QEMU mps2-an505
#   cortex-m3   -mcpu=cortex-m3 -mfloat-abi=soft (no FPU)            QEMU mps2-an385
#
# Besides the compiler setup it defines, for sfit_target.cmake and for anyone
# linking a bare-metal executable by hand:
#   SFIT_M4F_ARCH_FLAGS      list: -mcpu/-mthumb/-mfpu/-mfloat-abi
#   SFIT_M4F_QEMU_MACHINE    the QEMU board of SFIT_ARM_CORE
#   SFIT_M4F_LINKER_SCRIPT   qemu/mps2_an386.ld (mps2_an505.ld on the M33)
#   SFIT_M4F_STARTUP_SOURCE  qemu/startup.c (vector table, FPU enable, faults)
#   SFIT_M4F_LINK_OPTIONS    list: newlib-nano + semihosting specs, -T, gc-sections
#   SFIT_M4F_RUNNER          qemu/run.sh; CMAKE_CROSSCOMPILING_EMULATOR is
#                            run.sh -M <the core's board>
# The library target itself needs none of the link options.

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

# Compilers are looked up on PATH; override the prefix for another install
# (e.g. -DSFIT_M4F_TOOLCHAIN_PREFIX=/opt/gcc-arm/bin/arm-none-eabi-).
if(NOT DEFINED SFIT_M4F_TOOLCHAIN_PREFIX)
  set(SFIT_M4F_TOOLCHAIN_PREFIX arm-none-eabi-)
endif()
set(CMAKE_C_COMPILER ${SFIT_M4F_TOOLCHAIN_PREFIX}gcc)
set(CMAKE_CXX_COMPILER ${SFIT_M4F_TOOLCHAIN_PREFIX}g++)
set(CMAKE_ASM_COMPILER ${SFIT_M4F_TOOLCHAIN_PREFIX}gcc)

# Bare metal: no executable links without startup code and a linker script,
# so CMake's compiler checks build static libraries instead.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

if(NOT DEFINED SFIT_ARM_CORE)
  set(SFIT_ARM_CORE cortex-m4f)
endif()
# Compiler checks (try_compile) run this file again: pass the core on.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES SFIT_ARM_CORE)
if(SFIT_ARM_CORE STREQUAL "cortex-m4f")
  set(SFIT_M4F_ARCH_FLAGS -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard)
  set(SFIT_M4F_QEMU_MACHINE mps2-an386)
  set(_sfit_board_ld mps2_an386.ld)
elseif(SFIT_ARM_CORE STREQUAL "cortex-m33")
  set(SFIT_M4F_ARCH_FLAGS -mcpu=cortex-m33 -mthumb -mfpu=fpv5-sp-d16 -mfloat-abi=hard)
  set(SFIT_M4F_QEMU_MACHINE mps2-an505)
  set(_sfit_board_ld mps2_an505.ld)
elseif(SFIT_ARM_CORE STREQUAL "cortex-m3")
  set(SFIT_M4F_ARCH_FLAGS -mcpu=cortex-m3 -mthumb -mfloat-abi=soft)
  set(SFIT_M4F_QEMU_MACHINE mps2-an385)
  set(_sfit_board_ld mps2_an386.ld)
else()
  message(FATAL_ERROR "SFIT_ARM_CORE=${SFIT_ARM_CORE}: cortex-m4f, cortex-m33 or cortex-m3")
endif()
string(REPLACE ";" " " _sfit_m4f_arch "${SFIT_M4F_ARCH_FLAGS}")
# -fno-math-errno: sqrtf/__builtin_sqrtf become one vsqrt.f32 (no errno
# check + libm call) on an FPU core, a plain call to libm's sqrtf without. Sections per function/object for --gc-sections.
# CMAKE_<LANG>_FLAGS also reach the link line, which picks the
# thumb/v7e-m+fp/hard multilib of newlib and libgcc.
set(CMAKE_C_FLAGS_INIT "${_sfit_m4f_arch} -fno-math-errno -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_C_FLAGS_INIT}")
set(CMAKE_ASM_FLAGS_INIT "${_sfit_m4f_arch}")

# Never pick up host libraries/headers/packages (a host libm.so or cmocka
# would link or compile "fine" and break later). Libraries are searched in
# the compiler's sysroot, with this multilib's directory first, so that
# find_library(m) yields this core's libm.a rather than the default
# (Arm-state, soft-float) one.
execute_process(
  COMMAND ${CMAKE_C_COMPILER} ${SFIT_M4F_ARCH_FLAGS} -print-file-name=libm.a
  OUTPUT_VARIABLE _sfit_m4f_libm
  OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_QUIET)
if(IS_ABSOLUTE "${_sfit_m4f_libm}" AND EXISTS "${_sfit_m4f_libm}")
  get_filename_component(_sfit_m4f_libdir "${_sfit_m4f_libm}" DIRECTORY)
  get_filename_component(_sfit_m4f_libdir "${_sfit_m4f_libdir}" REALPATH)
  # <sysroot>/lib/thumb/v7e-m+fp/hard -> <sysroot>
  string(REGEX REPLACE "/(lib|newlib)/thumb/.*$" "" _sfit_m4f_sysroot "${_sfit_m4f_libdir}")
  set(CMAKE_FIND_ROOT_PATH "${_sfit_m4f_sysroot}" ${CMAKE_FIND_ROOT_PATH})
  set(CMAKE_LIBRARY_PATH "${_sfit_m4f_libdir}" ${CMAKE_LIBRARY_PATH})
endif()
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# Target programs: startup + linker script + newlib-nano with semihosting
# (printf/argv/exit through the debugger, i.e. QEMU).
set(SFIT_M4F_DIR "${CMAKE_CURRENT_LIST_DIR}")
set(SFIT_M4F_LINKER_SCRIPT "${SFIT_M4F_DIR}/qemu/${_sfit_board_ld}")
set(SFIT_M4F_STARTUP_SOURCE "${SFIT_M4F_DIR}/qemu/startup.c")
# -L: the board script INCLUDEs mps2_sections.ld from the same directory.
set(SFIT_M4F_LINK_OPTIONS
    --specs=nano.specs --specs=rdimon.specs "-L${SFIT_M4F_DIR}/qemu"
    "-T${SFIT_M4F_LINKER_SCRIPT}" -Wl,--gc-sections)

# ctest runs every target executable through QEMU on the core's board
# (exit status = main's return value; 77 = qemu-system-arm missing, run.sh).
set(SFIT_M4F_RUNNER "${SFIT_M4F_DIR}/qemu/run.sh")
set(CMAKE_CROSSCOMPILING_EMULATOR "${SFIT_M4F_RUNNER};-M;${SFIT_M4F_QEMU_MACHINE}")
