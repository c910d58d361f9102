# SPDX-License-Identifier: MIT
# CMake toolchain file: Cortex-M33 with FPU (FPv5-SP, hard float), QEMU mps2-an505.
# The cortex-m4f port and toolchain.cmake with SFIT_ARM_CORE=cortex-m33.
set(SFIT_ARM_CORE cortex-m33)
include("${CMAKE_CURRENT_LIST_DIR}/toolchain.cmake")
