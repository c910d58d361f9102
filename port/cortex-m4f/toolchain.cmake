# SPDX-License-Identifier: MIT
#
# CMake toolchain file: Cortex-M4F (FPv4-SP, hard-float ABI) with Debian's
# arm-none-eabi-gcc + newlib, test programs run under QEMU mps2-an386.
#
#   cmake -S . -B build-m4f \
#         -DCMAKE_TOOLCHAIN_FILE=port/cortex-m4f/toolchain.cmake
#
# Besides the compiler setup it defines, for sfit_target.cmake and for anyone
# linking a bare-metal executable by hand:
#   SFIT_M4F_ARCH_FLAGS      list: -mcpu/-mthumb/-mfpu/-mfloat-abi
#   SFIT_M4F_LINKER_SCRIPT   qemu/mps2_an386.ld
#   SFIT_M4F_STARTUP_SOURCE  qemu/startup.c (vector table, FPU enable, faults)
#   SFIT_M4F_LINK_OPTIONS    list: newlib-nano + semihosting specs, -T, gc-sections
#   SFIT_M4F_RUNNER          qemu/run.sh, also CMAKE_CROSSCOMPILING_EMULATOR
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

set(SFIT_M4F_ARCH_FLAGS -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard)
string(REPLACE ";" " " _sfit_m4f_arch "${SFIT_M4F_ARCH_FLAGS}")
# -fno-math-errno: sqrtf/__builtin_sqrtf become one vsqrt.f32 (no errno
# check + libm call). Sections per function/object for --gc-sections.
# CMAKE_<LANG>_FLAGS also reach the link line, which picks the
# thumb/v7e-m+fp/hard multilib of newlib and libgcc.
set(CMAKE_C_FLAGS_INIT "${_sfit_m4f_arch} -fno-math-errno -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_C_FLAGS_INIT}")
set(CMAKE_ASM_FLAGS_INIT "${_sfit_m4f_arch}")

# Never pick up host libraries/headers/packages (a host libm.so or cmocka
# would link or compile "fine" and break later). Libraries are searched in
# the compiler's sysroot, with this multilib's directory first, so that
# find_library(m) yields the hard-float libm.a rather than the default
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
set(SFIT_M4F_LINKER_SCRIPT "${SFIT_M4F_DIR}/qemu/mps2_an386.ld")
set(SFIT_M4F_STARTUP_SOURCE "${SFIT_M4F_DIR}/qemu/startup.c")
set(SFIT_M4F_LINK_OPTIONS
    --specs=nano.specs --specs=rdimon.specs
    "-T${SFIT_M4F_LINKER_SCRIPT}" -Wl,--gc-sections)

# ctest runs every target executable through QEMU (exit status = main's
# return value; 77 = qemu-system-arm missing, see run.sh).
set(SFIT_M4F_RUNNER "${SFIT_M4F_DIR}/qemu/run.sh")
set(CMAKE_CROSSCOMPILING_EMULATOR "${SFIT_M4F_RUNNER}")
