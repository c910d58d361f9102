/* SPDX-License-Identifier: MIT */
/**
 * @file test_gate.c
 * @brief Outlier gate: must-show 3 (5 % gross outliers, gated centre error
 * within twice the clean error), counting, warm-up, state on bad input.
 */
#include "test_cmocka.h"

#include "sfit/sfit_gate.h"

static const double k_c[3] = {1200.0, -800.0, 300.0};
static const double k_axis[3] = {0.3, -0.5, 0.8};
#define K_R 100.0

/* Monte Carlo: each trial streams n samples of a cap (sigma = 1 mm); with
 * probability 5 % a sample is replaced by an outlier: kind 0 uniform in
 * the box c +- 3r (ghost markers), kind 1 a sample of another marker on a
 * sphere of radius 0.6 r around the same centre (label swap). The clean
 * stream (same inliers, no replacement) goes into a plain accumulator;
 * the contaminated one through the gate and, for reference, into a plain
 * accumulator too. The running fit is UGDK with the known sigma^2. */
static void gate_mc(double theta_deg, int n, int trials, int kind, uint64_t seed)
{
    const double theta = theta_deg * TU_PI / 180.0;
    sfit_fit_cfg_t fc = sfit_fit_cfg_default;
    double ec = 0.0, eg = 0.0, eu = 0.0;
    unsigned long injected = 0, flagged = 0;
    tu_rng_t g;
    int t, i, k;
    fc.mode = SFIT_MODE_SPHERE;
    fc.noise = SFIT_NOISE_ISO;
    fc.noise_var = 1.0f;
    tu_rng_seed(&g, seed);
    for (t = 0; t < trials; t++) {
        sfit_moments_t clean, dirty;
        sfit_gate_t gt;
        sfit_gate_cfg_t gc = sfit_gate_cfg_default;
        sfit_gate_stats_t gs;
        sfit_result_t a, b, d;
        gc.fit = fc;
        (void)sfit_moments_init(&clean);
        (void)sfit_moments_init(&dirty);
        assert_int_equal(sfit_gate_init(&gt, &gc), SFIT_OK);
        for (i = 0; i < n; i++) {
            double p[3];
            sfit_vec3_t v;
            tu_sample_cap(&g, k_c, K_R, k_axis, theta, 1.0, p);
            tc_to_vec3(p, &v);
            (void)sfit_moments_add(&clean, &v);
            if (tu_rng_uniform(&g) < 0.05) {
                injected++;
                if (kind == 0) {
                    for (k = 0; k < 3; k++) {
                        p[k] = k_c[k] + 3.0 * K_R * (2.0 * tu_rng_uniform(&g) - 1.0);
                    }
                } else {
                    tu_sample_cap(&g, k_c, 0.6 * K_R, k_axis, theta, 1.0, p);
                }
                tc_to_vec3(p, &v);
            }
            (void)sfit_moments_add(&dirty, &v);
            assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
        }
        assert_int_equal(sfit_fit_moments(&clean, &fc, &a), SFIT_OK);
        assert_int_equal(sfit_gate_fit(&gt, &b), SFIT_OK);
        assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
        assert_int_equal(gs.accepted + gs.outliers, (uint32_t)n);
        flagged += gs.outliers;
        ec += tc_dist(&a.center, k_c);
        eg += tc_dist(&b.center, k_c);
        eu += (sfit_fit_moments(&dirty, &fc, &d) == SFIT_OK) ? tc_dist(&d.center, k_c) : 1e3;
    }
    print_message("gate: theta %.0f N %d T %d kind %d: mean centre error clean %.3f gated %.3f "
                  "(x%.2f) ungated %.1f; outliers flagged %lu of %lu injected\n",
                  theta_deg, n, trials, kind, ec / trials, eg / trials, eg / ec, eu / trials,
                  flagged, injected);
    /* measured x0.99-x1.26 (mean over trials); the ratio of two means of
     * ~T positive errors has a relative SE of a few % plus the rare wrong
     * start (docs/beyond.md): 2 is far above both */
    assert_true(eg <= 2.0 * ec);
    /* the gate sees most injected outliers (a few land on the sphere and are
     * harmless inliers) and flags few inliers (k = 4: 6e-5 of Gaussian
     * samples; sigma^2 estimated) */
    assert_true((double)flagged >= 0.85 * (double)injected);
    assert_true((double)flagged <= 1.10 * (double)injected);
    assert_true(eu > 10.0 * ec); /* the test is not vacuous */
}

static void test_ghost_markers(void **state)
{
    (void)state;
    gate_mc(35.0, 2000, 150, 0, 61u);
    gate_mc(60.0, 500, 200, 0, 62u);
}

static void test_label_swaps(void **state)
{
    (void)state;
    gate_mc(35.0, 1000, 150, 1, 63u);
}

/* Exact samples: no rounding-level residual is gated out (variance floor);
 * an obvious outlier is; warm-up and refresh counters behave. */
static void test_counts_and_floor(void **state)
{
    sfit_gate_t gt;
    sfit_gate_cfg_t gc = sfit_gate_cfg_default;
    sfit_gate_stats_t gs;
    sfit_result_t r;
    tu_rng_t g;
    int i;
    bool acc = false;
    (void)state;
    tu_rng_seed(&g, 64u);
    gc.refresh = 16u;
    assert_int_equal(sfit_gate_init(&gt, &gc), SFIT_OK);
    for (i = 0; i < 500; i++) {
        double p[3];
        sfit_vec3_t v;
        tu_sample_cap(&g, k_c, K_R, k_axis, 1.0, 0.0, p);
        tc_to_vec3(p, &v);
        assert_int_equal(sfit_gate_add(&gt, &v, &acc), SFIT_OK);
        assert_true(acc);
        if (i == SFIT_GATE_WARMUP - 2) {
            assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
            assert_int_equal(gs.gated, 0);
            assert_int_equal(gs.accepted, SFIT_GATE_WARMUP - 1);
        }
    }
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.gated, 1);
    assert_int_equal(gs.outliers, 0);
    assert_int_equal(gs.accepted, 500);
    {
        const sfit_vec3_t far = {{1500.0f, -800.0f, 300.0f}};
        assert_int_equal(sfit_gate_add(&gt, &far, &acc), SFIT_OK);
        assert_false(acc);
    }
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.outliers, 1);
    assert_int_equal(sfit_gate_fit(&gt, &r), SFIT_OK);
    assert_true(tc_dist(&r.center, k_c) < 0.05);
    assert_int_equal(sfit_gate_reset(&gt), SFIT_OK);
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.accepted + gs.outliers, 0);
}

/* Warm-up on samples that do not yet define a sphere (collinear): the gate
 * accepts ungated and starts gating once a refresh succeeds. */
static void test_warmup_degenerate(void **state)
{
    sfit_gate_t gt;
    sfit_gate_stats_t gs;
    tu_rng_t g;
    int i;
    (void)state;
    tu_rng_seed(&g, 65u);
    assert_int_equal(sfit_gate_init(&gt, NULL), SFIT_OK);
    for (i = 0; i < SFIT_GATE_WARMUP; i++) {
        const sfit_vec3_t v = {{(float)i, 2.0f * (float)i, 5.0f}};
        assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.gated, 0);
    assert_int_equal(gs.accepted, SFIT_GATE_WARMUP);
    for (i = 0; i < 400; i++) {
        double p[3];
        sfit_vec3_t v;
        tu_sample_cap(&g, k_c, K_R, k_axis, 1.0, 0.5, p);
        tc_to_vec3(p, &v);
        assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.gated, 1);
}

/* An early refresh of the warm-up (before the buffer is full) runs the
 * robust start on what is buffered: each of its fits must have
 * SFIT_MIN_SAMPLES samples. With 24 buffered samples the 8 interleaved
 * subsets had 3 samples each, every start failed with SFIT_E_TOO_FEW and
 * the gate went ungated, keeping the outliers (as every full warm-up did
 * in a build with SFIT_MIN_SAMPLES 9..14). Samples that cannot give a fit
 * (collinear) are reported as such, not as too few. */
static void test_warmup_refresh_early(void **state)
{
    sfit_gate_t gt;
    sfit_gate_stats_t gs;
    sfit_result_t r;
    tu_rng_t g;
    int n, i;
    (void)state;
    for (n = 24; n <= 32; n += 4) {
        tu_rng_seed(&g, 67u + (uint64_t)n);
        assert_int_equal(sfit_gate_init(&gt, NULL), SFIT_OK);
        for (i = 0; i < n; i++) {
            double p[3];
            sfit_vec3_t v;
            tu_sample_cap(&g, k_c, K_R, k_axis, 1.0, 0.5, p);
            if (i == 5 || i == 18) {
                p[0] += 3.0 * K_R; /* two gross outliers */
            }
            tc_to_vec3(p, &v);
            assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
        }
        assert_int_equal(sfit_gate_refresh(&gt), SFIT_OK);
        assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
        printf("  early refresh with %d samples: %u outliers\n", n, (unsigned)gs.outliers);
        assert_int_equal(gs.gated, 1);
        /* both gross outliers out (a clean sample may fall outside the cut
         * of a MAD scale from ~20 residuals), the centre clean: one of
         * them kept would move it by tens of mm, sigma = 0.5 mm by < 1 */
        assert_true(gs.outliers >= 2u && gs.outliers <= 4u);
        assert_int_equal(gs.accepted + gs.outliers, (uint32_t)n);
        assert_int_equal(sfit_gate_fit(&gt, &r), SFIT_OK);
        assert_true(tc_dist(&r.center, k_c) < 2.0);
    }
    assert_int_equal(sfit_gate_init(&gt, NULL), SFIT_OK);
    for (i = 0; i < 24; i++) {
        const sfit_vec3_t v = {{(float)i, 2.0f * (float)i, 5.0f}};
        assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_gate_refresh(&gt), SFIT_E_DEGENERATE);
    assert_int_equal(sfit_gate_stats(&gt, &gs), SFIT_OK);
    assert_int_equal(gs.gated, 0);
    assert_int_equal(gs.accepted, 24);
}

static void test_contract(void **state)
{
    sfit_gate_t gt, copy;
    sfit_gate_cfg_t gc = sfit_gate_cfg_default;
    const sfit_vec3_t bad = {{0.0f, INFINITY, 0.0f}}, huge = {{1e30f, 0.0f, 0.0f}};
    bool acc;
    tu_rng_t g;
    int i;
    (void)state;
    tu_set_byte(&acc, 7u); /* a sentinel: written only on SFIT_OK */
    assert_int_equal(sfit_gate_init(NULL, NULL), SFIT_E_ARG);
    gc.k = 0.5f;
    assert_int_equal(sfit_gate_init(&gt, &gc), SFIT_E_ARG);
    gc.k = 0.0f;
    gc.noise_var = -1.0f;
    assert_int_equal(sfit_gate_init(&gt, &gc), SFIT_E_ARG);
    gc.noise_var = 0.0f;
    gc.fit.mode = (sfit_mode_t)9;
    assert_int_equal(sfit_gate_init(&gt, &gc), SFIT_E_ARG);
    assert_int_equal(sfit_gate_init(&gt, NULL), SFIT_OK);
    tu_rng_seed(&g, 66u);
    for (i = 0; i < 200; i++) {
        double p[3];
        sfit_vec3_t v;
        tu_sample_cap(&g, k_c, K_R, k_axis, 1.0, 0.5, p);
        tc_to_vec3(p, &v);
        assert_int_equal(sfit_gate_add(&gt, &v, NULL), SFIT_OK);
        if (i == 10 || i == 150) {
            copy = gt;
            assert_int_equal(sfit_gate_add(&gt, &bad, &acc), SFIT_E_NONFINITE);
            assert_int_equal(sfit_gate_add(&gt, &huge, &acc), SFIT_E_RANGE);
            assert_memory_equal(&gt, &copy, sizeof gt);
            assert_int_equal(tu_byte(&acc), 7);
        }
    }
    assert_int_equal(sfit_gate_add(&gt, NULL, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_gate_refresh(NULL), SFIT_E_ARG);
    assert_int_equal(sfit_gate_fit(&gt, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_gate_stats(NULL, NULL), SFIT_E_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ghost_markers),
        cmocka_unit_test(test_label_swaps),
        cmocka_unit_test(test_counts_and_floor),
        cmocka_unit_test(test_warmup_degenerate),
        cmocka_unit_test(test_warmup_refresh_early),
        cmocka_unit_test(test_contract),
    };
    return cmocka_run_group_tests_name("gate", tests, NULL, NULL);
}
