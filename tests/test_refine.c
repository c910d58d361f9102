/* SPDX-License-Identifier: MIT */
/**
 * @file test_refine.c
 * @brief Geometric refinement: agreement with the double Levenberg-Marquardt
 * oracle (far-offset centre), exact data, Monte Carlo efficiency against
 * the Cramer-Rao bound, the real hip markers against the published
 * geometric fits, bounded iterations and the contract.
 *
 * "rho" is the trust ratio sigma^2 / lambda_min(C) (C of the noisy
 * samples), as in test_selfcal.c.
 */
#include "test_cmocka.h"

#include <string.h>

#include "sfit/sfit_refine.h"
#include "sfit/sfit_selfcal.h"
#include "sfit_ref.h"

#define NMAX 1500

static double g_xt[NMAX][3], g_xn[NMAX][3];
static sfit_vec3_t g_pf[NMAX];
static const double k_axis[3] = {0.3, -0.5, 0.8};

static void gen(tu_rng_t *g, const double c[3], double r, double theta, double sigma, int n)
{
    int i, k;
    for (i = 0; i < n; i++) {
        tu_sample_cap(g, c, r, k_axis, theta, 0.0, g_xt[i]);
        for (k = 0; k < 3; k++) {
            g_xn[i][k] = g_xt[i][k] + sigma * tu_rng_gauss(g);
        }
        tc_to_vec3(g_xn[i], &g_pf[i]);
        tc_to_double3(&g_pf[i], g_xn[i]); /* oracle sees the float data */
    }
}

/* Far offset (|c| ~ 2700 mm, r = 100): float LM vs double LM on the same
 * data. The float residuals carry ~eps |x - c0| ~ 1e-5 mm; the centre
 * agrees to 1e-3 mm (1e-5 r) with the step tolerance 1e-5 r. */
static void test_matches_oracle_far(void **state)
{
    const double c[3] = {2500.0, -900.0, 450.0};
    sfit_selfcal_result_t s;
    sfit_refine_result_t r;
    double ci[3], cg[3], rg, s2 = 0.0;
    int it, i;
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 5u);
    gen(&g, c, 100.0, 40.0 * TU_PI / 180.0, 1.0, 1000);
    assert_int_equal(sfit_selfcal_points(g_pf, 1000, NULL, &s), SFIT_OK);
    assert_int_equal(sfit_refine_points(g_pf, 1000, &s.fit.center, NULL, &r), SFIT_OK);
    tc_to_double3(&s.fit.center, ci);
    assert_int_equal(ref_fit_geometric(REF_C3(g_xn), 1000, ci, (double)s.fit.radius, cg, &rg, &it), 0);
    assert_true(tc_dist(&r.center, cg) < 2e-3);
    assert_near(r.radius, rg, 2e-3, "radius vs oracle");
    for (i = 0; i < 1000; i++) {
        const double e = tu_dist3(g_xn[i], cg) - rg;
        s2 += e * e;
    }
    assert_near(r.rms, sqrt(s2 / 1000.0), 1e-4, "rms vs oracle");
    assert_true(r.converged && r.iterations >= 1u && r.iterations <= 10u);
    assert_int_equal(r.n, 1000);
}

/* The combined recipe (sfit_refine_fit): one flat result whose every field
 * equals the step that makes it, bit for bit (the geometric fit, the
 * sandwich's radius terms, the start's summary and verdict), the
 * covariance the sandwich plus b b^T, widened; the geometric centre agrees
 * with the double oracle as in test_matches_oracle_far; failures write
 * nothing. sfit_refine_points() writes the same type with the recipe's
 * fields zero. */
static void test_recipe(void **state)
{
    const double c[3] = {2500.0, -900.0, 450.0};
    sfit_selfcal_result_t s;
    sfit_refine_result_t r;
    sfit_uncert_t u;
    sfit_refine_result_t f, sentinel;
    double ci[3], cg[3], rg;
    int it;
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 5u);
    gen(&g, c, 100.0, 40.0 * TU_PI / 180.0, 1.0, 1000);
    assert_int_equal(sfit_refine_fit(g_pf, 1000, NULL, &f), SFIT_OK);
    assert_int_equal(sfit_selfcal_points(g_pf, 1000, NULL, &s), SFIT_OK);
    assert_int_equal(sfit_refine_points(g_pf, 1000, &s.fit.center, NULL, &r), SFIT_OK);
    assert_int_equal(sfit_uncert_geometric(g_pf, 1000, &r.center, &u), SFIT_OK);
    /* the geometric fit */
    assert_memory_equal(&f.center, &r.center, sizeof r.center);
    assert_true(f.radius == r.radius && f.rms == r.rms && f.noise_var == r.noise_var);
    assert_true(f.n == r.n && f.iterations == r.iterations && f.converged == r.converged);
    /* the start's summary and verdict */
    assert_memory_equal(&f.eigenvalues, &s.fit.eigenvalues, sizeof s.fit.eigenvalues);
    assert_memory_equal(&f.axis, &s.fit.axis, sizeof s.fit.axis);
    assert_true(f.trust_ratio == s.fit.trust_ratio && f.leontief_ratio == s.fit.leontief_ratio);
    assert_int_equal(f.flags, s.fit.flags);
    /* sfit_refine_points leaves the recipe's fields zero */
    {
        sfit_refine_result_t z;
        memset(&z, 0, sizeof z);
        assert_memory_equal(&r.center_cov, &z.center_cov, sizeof z.center_cov);
        assert_true(r.radius_var == 0.0f && r.cov_noise_var == 0.0f && r.flags == 0u);
        assert_memory_equal(r.center_radius_cov, z.center_radius_cov, sizeof z.center_radius_cov);
        assert_memory_equal(&r.eigenvalues, &z.eigenvalues, sizeof z.eigenvalues);
        assert_memory_equal(&r.axis, &z.axis, sizeof z.axis);
        assert_true(r.trust_ratio == 0.0f && r.leontief_ratio == 0.0f);
    }
    /* the recipe's covariance is the sandwich plus b b^T, b = geometric -
     * self-calibrated centre (its bias estimate), times the widening of
     * docs/coverage.md rule 7, 1 + K (v / r^2) sqrt(96 / (N - 4)) with the
     * self-calibrated v and r; the rest is the sandwich */
    {
        const double wf = 1.0 + REF_COV_WIDEN_K * ((double)s.noise_var
                                       / ((double)s.fit.radius * (double)s.fit.radius))
                                    * sqrt(96.0 / 996.0);
        int k;
        for (k = 0; k < 9; k++) {
            const double b0 = (double)r.center.v[k / 3] - (double)s.fit.center.v[k / 3];
            const double b1 = (double)r.center.v[k % 3] - (double)s.fit.center.v[k % 3];
            assert_near(f.center_cov.m[k], ((double)u.center_cov.m[k] + b0 * b1) * wf,
                        1e-5 * ((double)u.center_cov.m[0] + (double)u.center_cov.m[4]
                                + (double)u.center_cov.m[8]),
                        "recipe cov = sandwich + b b^T");
            /* symmetric, as every covariance of the API */
            assert_true(f.center_cov.m[k] == f.center_cov.m[3 * (k % 3) + k / 3]);
        }
        assert_true(f.radius_var == u.radius_var);
        assert_memory_equal(f.center_radius_cov, u.center_radius_cov,
                            sizeof u.center_radius_cov);
        assert_true(f.cov_noise_var == u.noise_var);
    }
    tc_to_double3(&s.fit.center, ci);
    assert_int_equal(ref_fit_geometric(REF_C3(g_xn), 1000, ci, (double)s.fit.radius, cg, &rg, &it), 0);
    assert_true(tc_dist(&f.center, cg) < 2e-3);
    assert_near(f.radius, rg, 2e-3, "recipe radius vs oracle");
    assert_true(f.converged);
    /* contract */
    memset(&sentinel, 0x6B, sizeof sentinel);
    f = sentinel;
    assert_int_equal(sfit_refine_fit(g_pf, 1000, NULL, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_refine_fit(NULL, 1000, NULL, &f), SFIT_E_ARG);
    assert_int_equal(sfit_refine_fit(g_pf, 4, NULL, &f), SFIT_E_TOO_FEW);
    g_pf[17].v[1] = NAN;
    assert_int_equal(sfit_refine_fit(g_pf, 1000, NULL, &f), SFIT_E_NONFINITE);
    assert_memory_equal(&f, &sentinel, sizeof f);
}

static void test_exact_data(void **state)
{
    const double c[3] = {-300.0, 150.0, 1000.0};
    const sfit_vec3_t start = {{-290.0f, 160.0f, 990.0f}}; /* 17 mm off */
    sfit_refine_result_t r;
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 6u);
    gen(&g, c, 80.0, 70.0 * TU_PI / 180.0, 0.0, 300);
    assert_int_equal(sfit_refine_points(g_pf, 300, &start, NULL, &r), SFIT_OK);
    assert_true(tc_dist(&r.center, c) < 5e-3);
    assert_near(r.radius, 80.0, 5e-3, "radius");
    assert_true(r.rms < 1e-3f);
}

/* Must-show 1 for the refined fit (started from the self-calibrated
 * UGDK). Ratio RMSE / sqrt(mean tr CRLB); relative SE ~ 1/sqrt(2T). */
static double efficiency(double theta_deg, double rho, int n, int trials, uint64_t seed)
{
    const double c[3] = {1200.0, -800.0, 300.0}, r0 = 100.0;
    const double theta = theta_deg * TU_PI / 180.0;
    double lmin, lmax, s2, mse = 0.0, crlb = 0.0, ratio;
    tu_rng_t g;
    int t;
    ref_cap_eigs_numeric(theta, r0, &lmin, &lmax);
    s2 = rho / (1.0 - rho) * lmin;
    tu_rng_seed(&g, seed);
    for (t = 0; t < trials; t++) {
        sfit_selfcal_result_t s;
        sfit_refine_result_t r;
        double cr[4][4], e;
        gen(&g, c, r0, theta, sqrt(s2), n);
        assert_int_equal(sfit_selfcal_points(g_pf, (size_t)n, NULL, &s), SFIT_OK);
        assert_int_equal(sfit_refine_points(g_pf, (size_t)n, &s.fit.center, NULL, &r), SFIT_OK);
        e = tc_dist(&r.center, c);
        mse += e * e;
        ref_crlb_sphere(REF_C3(g_xt), (size_t)n, c, r0, s2, cr);
        crlb += cr[0][0] + cr[1][1] + cr[2][2];
    }
    ratio = sqrt(mse / crlb);
    print_message("refined: theta %.0f rho %.2f N %d T %d: RMSE/sqrt(tr CRLB) = %.4f\n",
                  theta_deg, rho, n, trials, ratio);
    return ratio;
}

static void test_efficiency(void **state)
{
    (void)state;
    /* measured over several seeds: 0.97-1.01, 0.99-1.03 and 1.00-1.07
     * (T = 1000 each; seed-to-seed spread +-3 %, a little above the
     * chi^2_1 estimate 1/sqrt(2T) = 2.2 %): the bounds 1.10 / 1.15 are
     * >= 3 spreads above the expected values */
    assert_true(efficiency(35.0, 0.1, 100, 1000, 31u) <= 1.10);
    assert_true(efficiency(90.0, 0.1, 100, 1000, 32u) <= 1.10);
    assert_true(efficiency(35.0, 0.3, 1000, 1000, 33u) <= 1.15);
}

static void test_efficiency_wide(void **state)
{
    double lmin, lmax, rho;
    (void)state;
    /* Wide coverage up to sigma / r = 0.1. Measured (seed 77, T = 4000 /
     * 3000): whole sphere 1.010, 60-degree cap at rho = 0.3 1.073; SE 1.6 %
     * and 2.2 % here. */
    ref_cap_eigs_numeric(TU_PI, 100.0, &lmin, &lmax);
    rho = 100.0 / (lmin + 100.0); /* sigma = 10 */
    assert_true(efficiency(180.0, rho, 100, 2000, 34u) <= 1.10);
    assert_true(efficiency(60.0, 0.3, 1000, 1000, 35u) <= 1.15);
}

/* The documented limit: the maximum-likelihood fit itself misses the
 * first-order bound at large sigma / r. Whole sphere at rho = 0.3 is
 * sigma / r = 0.38: measured 1.26-1.30 (SE 2.2 % at T = 1000), 5 SE above 1.15. No
 * estimator here meets must-show 1 there; docs/beyond.md says so. */
static void test_efficiency_limit(void **state)
{
    (void)state;
    assert_true(efficiency(180.0, 0.3, 1000, 1000, 36u) > 1.15);
}

/* Must-show 4: the real hip markers. Published double geometric fits
 * (tests/data/README.md); their standard error per axis is
 * sqrt(diag CRLB) with sigma^2 = RMS^2 (independent-error model). Both
 * the self-calibrated UGDK and the refined fit must lie within 2 SE per
 * axis; the refined one reproduces the published centre to 0.005 mm. */
static void check_hip(const char *marker, const double geo[3], double geo_r, double rms)
{
    static double x[1400][3];
    static sfit_vec3_t p[1400];
    char path[512];
    size_t n, i;
    double cr[4][4], se[3];
    sfit_selfcal_result_t s;
    sfit_refine_result_t r;
    int k;

    snprintf(path, sizeof path, "%s/mocap/hip_right/%s.csv", SFIT_TEST_DATA_DIR, marker);
    assert_int_equal(tu_load_csv(path, x, 1400, &n), 0);
    for (i = 0; i < n; i++) {
        tc_to_vec3(x[i], &p[i]);
    }
    ref_crlb_sphere(REF_C3(x), n, geo, geo_r, rms * rms, cr);
    for (k = 0; k < 3; k++) {
        se[k] = sqrt(cr[k][k]);
    }
    assert_int_equal(sfit_selfcal_points(p, n, NULL, &s), SFIT_OK);
    assert_int_equal(sfit_refine_points(p, n, &s.fit.center, NULL, &r), SFIT_OK);
    print_message("%s: SE (%.3f %.3f %.3f); selfcal (%.3f %.3f %.3f) sigma %.3f trust %.3f; "
                  "refined (%.3f %.3f %.3f) r %.3f rms %.3f it %u\n",
                  marker, se[0], se[1], se[2], (double)s.fit.center.v[0],
                  (double)s.fit.center.v[1], (double)s.fit.center.v[2],
                  sqrt((double)s.noise_var), (double)s.fit.trust_ratio, (double)r.center.v[0],
                  (double)r.center.v[1], (double)r.center.v[2], (double)r.radius,
                  (double)r.rms, (unsigned)r.iterations);
    for (k = 0; k < 3; k++) {
        assert_near(s.fit.center.v[k], geo[k], 2.0 * se[k], "selfcal vs published geo");
        assert_near(r.center.v[k], geo[k], 0.005, "refined vs published geo");
    }
    assert_near(r.radius, geo_r, 0.005, "refined radius");
    assert_near(r.rms, rms, 0.005, "refined rms");
}

static void test_hip_real(void **state)
{
    static const double rthi1[3] = {-67.033, -88.814, 72.238};
    static const double rlfe[3] = {-70.844, -78.911, 78.887};
    static const double rgt[3] = {-87.155, -76.349, 126.351};
    (void)state;
    check_hip("RTHI1", rthi1, 260.495, 1.75);
    check_hip("RLFE", rlfe, 422.521, 2.27);
    check_hip("RGT", rgt, 65.952, 1.74);
}

static void test_bounds_and_contract(void **state)
{
    const double c[3] = {10.0, 20.0, 30.0};
    const sfit_vec3_t far_start = {{60.0f, 20.0f, 30.0f}}, bad = {{NAN, 0.0f, 0.0f}};
    sfit_refine_cfg_t cfg = sfit_refine_cfg_default;
    sfit_refine_result_t r, sentinel;
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 7u);
    gen(&g, c, 50.0, 50.0 * TU_PI / 180.0, 0.3, 200);
    memset(&sentinel, 0x5A, sizeof sentinel);
    r = sentinel;
    /* one iteration from 50 mm off cannot converge: no output */
    cfg.max_iters = 1u;
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, &cfg, &r), SFIT_E_NO_CONVERGENCE);
    assert_memory_equal(&r, &sentinel, sizeof r);
    /* the same with accept_unconverged: the last accepted centre, converged 0 */
    cfg.accept_unconverged = true;
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, &cfg, &r), SFIT_OK);
    assert_true(!r.converged && r.iterations == 1u);
    assert_true(tc_dist(&r.center, c) < 50.0 && isfinite(r.radius) && isfinite(r.noise_var));
    cfg.accept_unconverged = false;
    r = sentinel;
    cfg.max_iters = 0u;
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, &cfg, &r), SFIT_OK);
    assert_true(tc_dist(&r.center, c) < 0.5);
    assert_true(r.iterations > 1u && r.iterations <= SFIT_REFINE_MAX_ITERS);
    r = sentinel;
    cfg.tol = 0.5f;
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, &cfg, &r), SFIT_E_ARG);
    /* accept_unconverged is a bool: a byte other than 0/1 in it (garbage RAM)
     * is refused, read as a byte (sfit_types.h, "Yes/no"); 2 was taken for 1 */
    cfg.tol = 0.0f;
    tu_set_byte(&cfg.accept_unconverged, 2u);
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, &cfg, &r), SFIT_E_ARG);
    tu_set_byte(&cfg.accept_unconverged, 0xFFu);
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, &cfg, &r), SFIT_E_ARG);
    cfg.accept_unconverged = false;
    assert_int_equal(sfit_refine_points(NULL, 200, &far_start, NULL, &r), SFIT_E_ARG);
    assert_int_equal(sfit_refine_points(g_pf, 200, NULL, NULL, &r), SFIT_E_ARG);
    assert_int_equal(sfit_refine_points(g_pf, 200, &bad, NULL, &r), SFIT_E_NONFINITE);
    assert_int_equal(sfit_refine_points(g_pf, 4, &far_start, NULL, &r), SFIT_E_TOO_FEW);
    g_pf[3].v[2] = INFINITY;
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, NULL, &r), SFIT_E_NONFINITE);
    g_pf[3].v[2] = 0.0f;
    /* a sample exactly at the start centre */
    g_pf[5] = far_start;
    assert_int_equal(sfit_refine_points(g_pf, 200, &far_start, NULL, &r), SFIT_E_DEGENERATE);
    assert_memory_equal(&r, &sentinel, sizeof r);
    /* planar data: the centre is free along the normal */
    {
        sfit_vec3_t ring[40];
        const sfit_vec3_t s0 = {{0.5f, 0.2f, 0.0f}};
        int i;
        for (i = 0; i < 40; i++) {
            ring[i].v[0] = 10.0f * (float)cos(0.15 * i);
            ring[i].v[1] = 10.0f * (float)sin(0.15 * i);
            ring[i].v[2] = 0.0f;
        }
        assert_int_equal(sfit_refine_points(ring, 40, &s0, NULL, &r), SFIT_E_DEGENERATE);
    }
    assert_memory_equal(&r, &sentinel, sizeof r);
}

/* Fuzz finding: with 10 or more coincident samples the damped system looked
 * regular and the refinement "converged" at the start centre. */
static void test_coincident_is_degenerate(void **state)
{
    sfit_vec3_t p[12], c0 = {{0.0f, 0.0f, 0.0f}};
    sfit_refine_result_t r, sentinel;
    size_t i;
    (void)state;
    for (i = 0; i < 12; i++) {
        p[i].v[0] = 5.0f;
        p[i].v[1] = 5.0f;
        p[i].v[2] = 5.0f;
    }
    memset(&sentinel, 0x3C, sizeof sentinel);
    r = sentinel;
    for (i = 5; i <= 12; i++) {
        assert_int_equal(sfit_refine_points(p, i, &c0, NULL, &r), SFIT_E_DEGENERATE);
    }
    assert_memory_equal(&r, &sentinel, sizeof r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_matches_oracle_far),
        cmocka_unit_test(test_recipe),
        cmocka_unit_test(test_exact_data),
        cmocka_unit_test(test_efficiency),
        cmocka_unit_test(test_efficiency_wide),
        cmocka_unit_test(test_efficiency_limit),
        cmocka_unit_test(test_hip_real),
        cmocka_unit_test(test_bounds_and_contract),
        cmocka_unit_test(test_coincident_is_degenerate),
    };
    return cmocka_run_group_tests_name("refine", tests, NULL, NULL);
}
