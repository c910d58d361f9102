# SPDX-License-Identifier: MIT
# CMake toolchain file: Cortex-M3 without FPU (soft float), QEMU mps2-an385.
# The cortex-m4f port and toolchain.cmake with SFIT_ARM_CORE=cortex-m3.
set(SFIT_ARM_CORE cortex-m3)
include("${CMAKE_CURRENT_LIST_DIR}/toolchain.cmake")
