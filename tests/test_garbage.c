/* SPDX-License-Identifier: MIT */
/**
 * @file test_garbage.c
 * @brief Issue 19: the garbage-state programs of tests/fuzz/garbage_driver.h
 * (random bytes and out-of-range counters in every public state struct,
 * through every public function) from a fixed-seed generator, so that they
 * run in ctest, and under ASan + UBSan in tests/scripts/test_sanitizers.sh.
 * A contract violation aborts (the test fails); a sanitizer report too.
 */
#include "test_cmocka.h"

#include "fuzz/garbage_driver.h"

static uint8_t g_prog[4096];

static void run_programs(uint64_t seed, int count, uint8_t target, size_t maxlen)
{
    tu_rng_t rng;
    int t;
    tu_rng_seed(&rng, seed);
    for (t = 0; t < count; t++) {
        const size_t len = 2u + (size_t)(tu_rng_u64(&rng) % (uint64_t)(maxlen - 2u));
        size_t i;
        for (i = 0; i < len; i++) {
            g_prog[i] = (uint8_t)(tu_rng_u64(&rng) >> 56);
        }
        g_prog[0] = target;
        fz_garbage_run(g_prog, len);
    }
}

static void test_moments(void **state)
{
    (void)state;
    run_programs(101u, 3000, 0u, 1024u);
}

static void test_incr(void **state)
{
    (void)state;
    run_programs(102u, 3000, 1u, 1024u);
}

static void test_gate(void **state)
{
    (void)state;
    run_programs(103u, 1500, 2u, 4096u);
}

static void test_cluster(void **state)
{
    (void)state;
    run_programs(104u, 3000, 3u, 1024u);
}

static void test_joint(void **state)
{
    (void)state;
    run_programs(105u, 1500, 4u, 4096u);
}

static void test_multi(void **state)
{
    (void)state;
    run_programs(106u, 3000, 5u, 1024u);
}

static void test_pair(void **state)
{
    (void)state;
    run_programs(107u, 1500, 6u, 2048u);
}

static void test_imu(void **state)
{
    (void)state;
    run_programs(108u, 300, 7u, 4096u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_moments), cmocka_unit_test(test_incr),
        cmocka_unit_test(test_gate),    cmocka_unit_test(test_cluster),
        cmocka_unit_test(test_joint),   cmocka_unit_test(test_multi),
        cmocka_unit_test(test_pair),    cmocka_unit_test(test_imu),
    };
    return cmocka_run_group_tests_name("garbage", tests, NULL, NULL);
}
