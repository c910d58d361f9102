/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_garbage.c
 * @brief libFuzzer harness: garbage bytes and out-of-range counters in every
 * public state struct, through every public function that takes it
 * (program format and checks: garbage_driver.h; tests/fuzz/README.md).
 */
#include "garbage_driver.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_garbage_run(data, size);
    return 0;
}
