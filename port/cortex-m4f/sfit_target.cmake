# SPDX-License-Identifier: MIT
#
# Helpers for Cortex-M4F test programs run under QEMU. Needs the variables
# set by toolchain.cmake (configure with -DCMAKE_TOOLCHAIN_FILE=...).
#
#   include(port/cortex-m4f/sfit_target.cmake)
#   sfit_add_target_executable(test_target tests/target/main.c)
#   target_link_libraries(test_target PRIVATE sfit)
#   sfit_add_target_test(sfit.target test_target)   # or add_test(), see below
#
# sfit_add_target_executable(<name> <sources>...)
#   add_executable + startup.c (as an OBJECT library shared by all programs)
#   + linker script + newlib-nano/semihosting link options + libm.
# sfit_add_target_test(<test-name> <target> [args...])
#   add_test through run.sh with SKIP_RETURN_CODE 77 (no QEMU -> skipped,
#   not failed) and a TIMEOUT. A plain add_test(NAME x COMMAND <target>) also
#   runs under QEMU (CMAKE_CROSSCOMPILING_EMULATOR) but reports a missing
#   QEMU as a failure unless you set SKIP_RETURN_CODE 77 yourself.

if(NOT DEFINED SFIT_M4F_LINK_OPTIONS OR NOT DEFINED SFIT_M4F_STARTUP_SOURCE)
  message(FATAL_ERROR
    "sfit_target.cmake: configure with "
    "-DCMAKE_TOOLCHAIN_FILE=<sfit>/port/cortex-m4f/toolchain.cmake")
endif()

function(sfit_add_target_executable name)
  if(NOT ARGN)
    message(FATAL_ERROR "sfit_add_target_executable(${name}): no sources")
  endif()
  # Built once, with the toolchain's flags only (no project warning set).
  if(NOT TARGET sfit_m4f_startup)
    add_library(sfit_m4f_startup OBJECT "${SFIT_M4F_STARTUP_SOURCE}")
    set_target_properties(sfit_m4f_startup PROPERTIES C_STANDARD 99 C_EXTENSIONS OFF)
    # libm as a dependency of the startup objects rather than of the program:
    # CMake then emits -lm after every library the caller links later
    # (e.g. libsfit.a), so static-link order is right.
    target_link_libraries(sfit_m4f_startup INTERFACE m)
  endif()
  add_executable(${name} ${ARGN})
  # Linking an OBJECT library adds its object file itself (not an archive
  # member), so the vector table is always present.
  target_link_libraries(${name} PRIVATE sfit_m4f_startup)
  target_link_options(${name} PRIVATE ${SFIT_M4F_LINK_OPTIONS})
  set_target_properties(${name} PROPERTIES LINK_DEPENDS "${SFIT_M4F_LINKER_SCRIPT}")
endfunction()

function(sfit_add_target_test test_name target)
  add_test(NAME ${test_name} COMMAND ${target} ${ARGN})
  set_tests_properties(${test_name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 150)
endfunction()
