/* SPDX-License-Identifier: MIT */
/**
 * @file test_knob_build.c
 * @brief The library built with a non-default SFIT_MIN_SAMPLES (10, inside
 * its documented range: tests/CMakeLists.txt, ctest sfit.knob_build): the
 * modules whose internal sample counts depend on it still work. The gate's
 * robust start fitted subsets of 8 buffered samples whatever
 * SFIT_MIN_SAMPLES was: with 9..14 every start failed with SFIT_E_TOO_FEW
 * and the gate went ungated, keeping the warm-up's outliers. The sfit.config
 * tests only compile a header or source with every knob set; this one runs.
 */
#include "test_cmocka.h"

#include "sfit/sfit_gate.h"
#include "sfit/sfit_incr.h"
#include "sfit/sfit_selfcal.h"

#if SFIT_MIN_SAMPLES != 10u
#error "test_knob_build.c is built with -DSFIT_MIN_SAMPLES=10u (tests/CMakeLists.txt)"
#endif

static const double k_c[3] = {1200.0, -800.0, 300.0};
static const double k_axis[3] = {0.3, -0.5, 0.8};
#define K_R 100.0

/* A full warm-up with 4 gross outliers (every 16th sample 3 r off): the
 * robust start drops them and the gate gates. */
static void test_gate_warmup(void **state)
{
    static sfit_gate_t gt;
    sfit_gate_stats_t gs;
    sfit_result_t r;
    tu_rng_t g;
    int i;
    (void)state;
    tu_rng_seed(&g, 91u);
    assert_int_equal(sfit_gate_init(&gt, NULL), SFIT_OK);
    for (i = 0; i < SFIT_GATE_WARMUP; i++) {
        double p[3];
        sfit_vec3_t v;
        tu_sample_cap(&g, k_c, K_R, k_axis, 1.0, 0.5, p);
        if (i % 16 == 3) {
            p[0] += 3.0 * K_R;
        }
        tc_to_vec3(p, &v);
        assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.gated, 1);
    assert_true(gs.outliers >= (uint32_t)(SFIT_GATE_WARMUP / 16)
                && gs.outliers <= (uint32_t)(SFIT_GATE_WARMUP / 16) + 2u);
    assert_int_equal(sfit_gate_fit(&gt, &r), SFIT_OK);
    assert_true(tc_dist(&r.center, k_c) < 2.0); /* one outlier kept: tens of mm */
}

/* Self-calibration and the incremental start keep working; fewer samples
 * than the knob are refused as such. */
static void test_selfcal_incr(void **state)
{
    static sfit_vec3_t v[300];
    sfit_selfcal_result_t sc;
    sfit_incr_t inc;
    sfit_sphere_t sp;
    tu_rng_t g;
    int i;
    (void)state;
    tu_rng_seed(&g, 92u);
    for (i = 0; i < 300; i++) {
        double p[3];
        tu_sample_cap(&g, k_c, K_R, k_axis, 1.0, 0.5, p);
        tc_to_vec3(p, &v[i]);
    }
    assert_int_equal(sfit_selfcal_points(v, 300, NULL, &sc), SFIT_OK);
    assert_true(tc_dist(&sc.fit.center, k_c) < 2.0);
    assert_int_equal(sfit_selfcal_points(v, 9, NULL, &sc), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_incr_init(&inc, NULL), SFIT_OK);
    assert_int_equal(sfit_incr_start(&inc, v, 9, &sp), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_incr_start(&inc, v, 300, &sp), SFIT_OK);
    assert_true(tc_dist(&sp.center, k_c) < 2.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gate_warmup),
        cmocka_unit_test(test_selfcal_incr),
    };
    return cmocka_run_group_tests_name("knob_build", tests, NULL, NULL);
}
