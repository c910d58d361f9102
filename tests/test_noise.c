/* SPDX-License-Identifier: MIT */
/**
 * @file test_noise.c
 * @brief Noise calibration (eq. 177, 190): Monte Carlo of the calibration
 * against the double oracle's variance, every error path. The coverage
 * aids: test_coverage.c.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit/sfit_noise.h"
#include "sfit_ref.h"
#include "test_capset.h"


static sfit_status_t calibrate_array(size_t n, const double c0[3], double r0,
                                     sfit_noise_est_t *e)
{
    sfit_moments_t m;
    sfit_vec3_t c;
    (void)sfit_moments_init(&m);
    assert_int_equal(sfit_moments_add_block(&m, g_fpts, n, NULL), SFIT_OK);
    tc_to_vec3(c0, &c);
    return sfit_noise_calibrate(&m, &c, (float)r0, e);
}

/* ------------------------------------------------------------ calibration */

/* Float result vs the double oracle on the same float samples (the oracle
 * computes mean |x - c0|^2 - r0^2 in long double). sfit's error is the
 * rounding of quantities of size r0^2 (the trace of M2 / N and
 * |mean - c0|^2, each accurate to a few ulps after the accumulator's
 * shifted block sums) plus sigma^2-sized terms: bound
 * 64 FLT_EPSILON (r0^2 + 3 sigma^2 + 1), i.e. 0.08 mm^2 for r0 = 100 mm,
 * against a statistical spread of the estimate of 4.7 mm^2 (N = 200). */
static void test_calib_matches_oracle(void **state)
{
    const double cases[][4] = {
        /* r0, theta (deg), sigma, n */
        {100.0, 180.0, 1.0, 200.0}, {100.0, 40.0, 1.0, 200.0}, {100.0, 40.0, 0.0, 5000.0},
        {2.0, 180.0, 1.0, 1000.0},  {0.0, 180.0, 0.5, 1000.0}, {100.0, 15.0, 3.0, 100000.0}};
    tu_rng_t g;
    size_t k;
    (void)state;
    tu_rng_seed(&g, 177u);
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const double r0 = cases[k][0], sigma = cases[k][2];
        const size_t n = (size_t)cases[k][3];
        sfit_noise_est_t e;
        double c0f[3], tref, tol;
        sfit_vec3_t c0v;
        make_pts(&g, 0, n, r0, cases[k][1] * DEG, sigma);
        tc_to_vec3(k_center, &c0v);
        tc_to_double3(&c0v, c0f); /* the float centre the library sees */
        assert_int_equal(calibrate_array(n, k_center, r0, &e), SFIT_OK);
        tref = ref_noise_trace(REF_C3(g_pts), n, c0f, (double)(float)r0);
        tol = 64.0 * (double)FLT_EPSILON * (r0 * r0 + 3.0 * sigma * sigma + 1.0);
        assert_int_equal(e.n, n);
        assert_near(e.noise_trace, tref, tol, "noise_trace vs oracle");
        assert_near(e.noise_var, tref / 3.0, tol / 3.0, "noise_var vs oracle");
        assert_int_equal((e.flags & SFIT_NOISE_FLAG_NEGATIVE) != 0u, e.noise_var < 0.0f);
        {
            float sd;
            const double v = ref_noise_trace_var(fabs(tref / 3.0), r0, n, 3);
            assert_int_equal(sfit_noise_calib_std((float)fabs(tref / 3.0), (float)r0,
                                                  (uint32_t)n, &sd),
                             SFIT_OK);
            assert_near(sd, sqrt(v), 1e-5 * sqrt(v) + 1e-30, "calib_std vs oracle");
            assert_near(e.noise_var_std, sqrt(v), 1e-4 * sqrt(v) + tol, "noise_var_std");
        }
    }
}

/*
 * Monte Carlo: T trials of N samples on a sphere (or cap) far from the
 * origin. Checks, against the oracle's eq. 190 variance V:
 *  - unbiased: |mean - sigma^2| <= 3 SE, SE = sample sd / sqrt(T);
 *  - spread: |sample variance / V - 1| <= 10 %.
 * Why 10 %: the estimate is a mean of N independent terms, close to
 * Gaussian, so the sample variance of T trials has a relative standard
 * error sqrt(2 / (T - 1)) (times sqrt(1 + kurt/2), kurt the excess
 * kurtosis, < 0.05 here). With T = 4000 that is 2.2 %: 10 % is 4.5 standard
 * errors (asserted below), so a correct formula fails with probability
 * ~1e-5, while a factor-of-D mistake (or the chapter's 1/(N D^2) read as
 * 1/(N D)) is off by 200 % or more. T = 1000 would give 4.5 % and 10 % =
 * 2.2 SE only, hence 4000.
 */
#define MC_TRIALS 4000
static void mc_calibration(uint64_t seed, double r0, double theta, double sigma, size_t n)
{
    tu_rng_t g;
    double sum = 0.0, sum2 = 0.0, mean, var, v_pred, se;
    size_t t, negatives = 0;
    tu_rng_seed(&g, seed);
    for (t = 0; t < MC_TRIALS; t++) {
        sfit_noise_est_t e;
        make_pts(&g, 0, n, r0, theta, sigma);
        assert_int_equal(calibrate_array(n, k_center, r0, &e), SFIT_OK);
        sum += (double)e.noise_var;
        sum2 += (double)e.noise_var * (double)e.noise_var;
        if (e.flags & SFIT_NOISE_FLAG_NEGATIVE) {
            negatives++;
        }
    }
    mean = sum / MC_TRIALS;
    var = (sum2 - MC_TRIALS * mean * mean) / (MC_TRIALS - 1);
    se = sqrt(var / MC_TRIALS);
    v_pred = ref_noise_trace_var(sigma * sigma, r0, n, 3);
    assert_true(3.0 * sqrt(2.0 / (MC_TRIALS - 1)) < 0.10); /* 10 % > 3 SE of a variance */
    print_message("  r0 %g theta %g deg N %zu: mean %.4f (truth %.4f, SE %.4f), "
                  "var %.4f (eq. 190: %.4f, ratio %.4f), %zu negative\n",
                  r0, theta / DEG, n, mean, sigma * sigma, se, var, v_pred, var / v_pred,
                  negatives);
    assert_near(mean, sigma * sigma, 3.0 * se, "calibration mean vs sigma^2");
    assert_near(var / v_pred, 1.0, 0.10, "calibration variance / eq. 190");
}

static void test_calib_mc_sphere(void **state)
{
    (void)state;
    mc_calibration(1001u, 100.0, TU_PI, 1.0, 200u);
}

static void test_calib_mc_cap(void **state)
{
    (void)state;
    mc_calibration(1002u, 100.0, 40.0 * DEG, 1.0, 200u);
}

/* r0 = 2 sigma: the D sigma^4 term is 27 % of eq. 190, so this case also
 * checks that term (with r0 = 100 it is 0.015 %). */
static void test_calib_mc_small_radius(void **state)
{
    (void)state;
    mc_calibration(1003u, 2.0, TU_PI, 1.0, 200u);
}

/* r0 = 0: a fixed point measured repeatedly; eq. 190 reduces to
 * 2 sigma^4 / (D N). */
static void test_calib_mc_fixed_point(void **state)
{
    (void)state;
    mc_calibration(1004u, 0.0, TU_PI, 0.7, 50u);
}

/* Noise-free samples: the estimate is 0 up to float rounding of r0^2. */
static void test_calib_noise_free(void **state)
{
    tu_rng_t g;
    sfit_noise_est_t e;
    (void)state;
    tu_rng_seed(&g, 5u);
    make_pts(&g, 0, 1000u, 100.0, 30.0 * DEG, 0.0);
    assert_int_equal(calibrate_array(1000u, k_center, 100.0, &e), SFIT_OK);
    /* float rounding of the samples near |c| = 3061 mm: half an ulp,
     * 1.2e-4 mm per coordinate, gives E|dx|^2 ~ 3 (1.2e-4)^2 / 3 plus a
     * first-order term 2 u.dx averaging out: |T| << 64 eps r0^2 = 0.08. */
    assert_near(e.noise_trace, 0.0, 64.0 * (double)FLT_EPSILON * 1e4, "noise-free trace");
    assert_true(e.noise_var_std >= 0.0f);
}

static void test_errors(void **state)
{
    const float nan = (float)NAN, inf = (float)INFINITY;
    sfit_moments_t m;
    sfit_noise_est_t e, e0;
    sfit_vec3_t c0 = {{0.0f, 0.0f, 0.0f}}, x = {{1.0f, 0.0f, 0.0f}};
    float out = 123.0f;
    (void)state;

    /* calibration */
    memset(&e0, 0xA5, sizeof e0);
    e = e0;
    (void)sfit_moments_init(&m);
    assert_int_equal(sfit_noise_calibrate(NULL, &c0, 1.0f, &e), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calibrate(&m, NULL, 1.0f, &e), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calibrate(&m, &c0, 1.0f, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calibrate(&m, &c0, 1.0f, &e), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_moments_add(&m, &x), SFIT_OK);
    assert_int_equal(sfit_noise_calibrate(&m, &c0, -1.0f, &e), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calibrate(&m, &c0, nan, &e), SFIT_E_NONFINITE);
    assert_int_equal(sfit_noise_calibrate(&m, &c0, inf, &e), SFIT_E_NONFINITE);
    c0.v[1] = nan;
    assert_int_equal(sfit_noise_calibrate(&m, &c0, 1.0f, &e), SFIT_E_NONFINITE);
    c0.v[1] = 0.0f;
    assert_memory_equal(&e, &e0, sizeof e);
    /* one sample exactly on the sphere: estimate 0, defined for N = 1 */
    assert_int_equal(sfit_noise_calibrate(&m, &c0, 1.0f, &e), SFIT_OK);
    assert_int_equal(e.n, 1);
    assert_true(e.noise_trace == 0.0f && e.noise_var == 0.0f);
    /* r0 = 0 with a far sample: trace = |x - c0|^2 */
    assert_int_equal(sfit_noise_calibrate(&m, &c0, 0.0f, &e), SFIT_OK);
    assert_near(e.noise_trace, 1.0, 1e-6, "fixed-point trace");
    /* overflow: |x - c0|^2 beyond float */
    c0.v[0] = -3.0e20f;
    assert_int_equal(sfit_noise_calibrate(&m, &c0, 0.0f, &e), SFIT_E_RANGE);
    c0.v[0] = 0.0f;

    assert_int_equal(sfit_noise_calib_std(1.0f, 1.0f, 0u, &out), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calib_std(-1.0f, 1.0f, 10u, &out), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calib_std(1.0f, -1.0f, 10u, &out), SFIT_E_ARG);
    assert_int_equal(sfit_noise_calib_std(nan, 1.0f, 10u, &out), SFIT_E_NONFINITE);
    assert_int_equal(sfit_noise_calib_std(1.0f, inf, 10u, &out), SFIT_E_NONFINITE);
    assert_int_equal(sfit_noise_calib_std(1.0f, 1e30f, 10u, &out), SFIT_E_RANGE);
    assert_int_equal(sfit_noise_calib_std(1.0f, 1.0f, 10u, NULL), SFIT_E_ARG);
    assert_true(out == 123.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_calib_matches_oracle),
        cmocka_unit_test(test_calib_mc_sphere),
        cmocka_unit_test(test_calib_mc_cap),
        cmocka_unit_test(test_calib_mc_small_radius),
        cmocka_unit_test(test_calib_mc_fixed_point),
        cmocka_unit_test(test_calib_noise_free),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests_name("noise", tests, NULL, NULL);
}
