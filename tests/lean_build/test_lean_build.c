/* SPDX-License-Identifier: MIT */
/**
 * @file test_lean_build.c
 * @brief The firmware build without the full solver's fallback
 * (SFIT_FULL_SOLVER 0, lib/include/sfit/sfit_config.h): linked against a
 * copy of the library compiled with that knob (tests/CMakeLists.txt, ctest
 * sfit.lean_build). Where the screen passes, the fit is the screened one
 * (exact 0) and within the README's promise (1e-4 r) of the double
 * reference; below SFIT_COV_MIN_SAMPLES it is still fitted, flagged by the
 * count. Where the screen trips (near-planar, collinear, coincident, an
 * untrusted bound) and for the options only the full solver serves
 * (cfg.eigen = true, planar mode, a full covariance), the status is
 * SFIT_E_UNSUPPORTED and the output is untouched; invalid options and too
 * few samples keep their own statuses.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit_ref.h"
#include "sfit_solve.h" /* sfit_i_lmin_lower (internal) */

#if SFIT_FULL_SOLVER != 0
#error "test_lean_build.c is built with -DSFIT_FULL_SOLVER=0 (tests/CMakeLists.txt)"
#endif

#define NMAX 1000
#define SENTINEL 0xA5
static double g_pts[NMAX][3];
static sfit_vec3_t g_fpts[NMAX];

static const double k_center[3] = {2100.0, -1500.0, 900.0};
static const double k_axis[3] = {0.267261241912424, 0.534522483824849, 0.801783725737273};
static const double k_dir[3] = {1.0, 0.0, 0.0};

static void make_cap(uint64_t seed, size_t n, double r, double theta_deg, double sigma)
{
    tu_rng_t g;
    size_t i;
    tu_rng_seed(&g, seed);
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_cap(&g, k_center, r, k_axis, theta_deg * TU_PI / 180.0, sigma, p);
        tc_to_vec3(p, &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
}

/* A noise-free full circle: exactly planar. */
static void make_circle(size_t n, double r)
{
    tu_rng_t g;
    size_t i;
    tu_rng_seed(&g, 77);
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_arc(&g, k_center, r, k_axis, k_dir, TU_PI, 0.0, p);
        tc_to_vec3(p, &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
}

/* Fit the first n samples both ways (array and accumulator): the same
 * status and bytes; returns the status, the result in *r. */
static sfit_status_t fit_both(size_t n, const sfit_fit_cfg_t *cfg, sfit_result_t *r)
{
    sfit_moments_t m;
    sfit_result_t rm;
    sfit_status_t sp, sm;
    memset(r, SENTINEL, sizeof *r);
    memset(&rm, SENTINEL, sizeof rm);
    sp = sfit_fit_points(g_fpts, n, cfg, r);
    assert_int_equal(sfit_moments_init(&m), SFIT_OK);
    assert_int_equal(sfit_moments_add_block(&m, g_fpts, n, NULL), SFIT_OK);
    sm = sfit_fit_moments(&m, cfg, &rm);
    assert_int_equal(sp, sm);
    assert_memory_equal(r, &rm, sizeof rm);
    return sp;
}

static void assert_untouched(const sfit_result_t *r)
{
    const unsigned char *b = (const unsigned char *)r;
    size_t k;
    for (k = 0; k < sizeof *r; k++) {
        assert_int_equal(b[k], SENTINEL);
    }
}

/* A screened result within 1e-4 r of the double reference (GDKE, or UGDK
 * with sigma^2 I when var > 0). */
static void assert_like_ref(size_t n, const sfit_result_t *r, double var)
{
    ref_fit_t ref;
    const double cov[6] = {var, var, var, 0.0, 0.0, 0.0}; /* packed XX, YY, ZZ, XY, XZ, YZ */
    assert_int_equal(ref_fit_sphere(REF_C3(g_pts), n, (var > 0.0) ? cov : NULL, &ref), 0);
    assert_int_equal(r->exact, 0);
    assert_int_equal(r->mode, SFIT_MODE_SPHERE);
    assert_int_equal(r->method, (var > 0.0) ? SFIT_METHOD_UGDK : SFIT_METHOD_GDKE);
    assert_true(r->n == (uint32_t)n);
    assert_true(tc_dist(&r->center, ref.center) <= 1e-4 * ref.radius);
    assert_near(r->radius, ref.radius, 1e-4 * ref.radius, "radius");
    assert_true(r->eigenvalues.v[0] == 0.0f && r->axis.v[0] == 0.0f);
    /* The screened ratio bounds the exact one (the reference's rho(C'^-1 Sigma)). */
    assert_true((double)r->leontief_ratio >= ref.trust_ratio * (1.0 - 1e-3));
}

/* The screen passes: a fit, as the default build's screened path gives it. */
static void test_screened_fits(void **state)
{
    sfit_result_t r;
    sfit_fit_cfg_t c = sfit_fit_cfg_default;
    (void)state;
    make_cap(1601, 500, 100.0, 60.0, 0.5);
    assert_int_equal(fit_both(500, NULL, &r), SFIT_OK);
    assert_like_ref(500, &r, 0.0);
    assert_int_equal(r.flags, 0u);
    c.noise = SFIT_NOISE_ISO;
    c.noise_var = 0.25f;
    assert_int_equal(fit_both(500, &c, &r), SFIT_OK);
    assert_like_ref(500, &r, 0.25);
    assert_int_equal(r.flags, 0u);
}

/* Below SFIT_COV_MIN_SAMPLES the flags are the count's: still a fit. */
static void test_few_samples_fit(void **state)
{
    sfit_result_t r;
    const size_t n_cov = (size_t)SFIT_COV_MIN_SAMPLES - 1u;
    const size_t n_few = (size_t)SFIT_FEW_SAMPLES - 1u;
    (void)state;
    make_cap(1602, n_cov, 100.0, 90.0, 0.0);
    assert_int_equal(fit_both(n_cov, NULL, &r), SFIT_OK);
    assert_like_ref(n_cov, &r, 0.0);
    assert_int_equal(r.flags, (uint32_t)(SFIT_FLAG_UNTRUSTED | SFIT_FLAG_COV_LIMIT)
                                  | ((n_cov < (size_t)SFIT_FEW_SAMPLES)
                                         ? (uint32_t)SFIT_FLAG_FEW_SAMPLES
                                         : 0u));
    make_cap(1603, n_few, 100.0, 90.0, 0.0);
    assert_int_equal(fit_both(n_few, NULL, &r), SFIT_OK);
    assert_like_ref(n_few, &r, 0.0);
    assert_int_equal(r.flags, (uint32_t)(SFIT_FLAG_UNTRUSTED | SFIT_FLAG_COV_LIMIT
                                         | SFIT_FLAG_FEW_SAMPLES));
}

/* The screen trips: SFIT_E_UNSUPPORTED, output untouched. */
static void test_tripped(void **state)
{
    sfit_result_t r;
    sfit_fit_cfg_t c = sfit_fit_cfg_default;
    size_t i;
    (void)state;
    make_circle(200, 80.0); /* near-planar (exactly planar) */
    assert_int_equal(fit_both(200, NULL, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    make_cap(1604, 300, 100.0, 60.0, 2.0); /* an untrusted trust bound */
    c.noise = SFIT_NOISE_ISO;
    c.noise_var = 400.0f;
    assert_int_equal(fit_both(300, &c, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    for (i = 0; i < 60; i++) { /* collinear */
        g_fpts[i].v[0] = 2100.0f + (float)i;
        g_fpts[i].v[1] = -1500.0f + 2.0f * (float)i;
        g_fpts[i].v[2] = 900.0f - 0.5f * (float)i;
    }
    assert_int_equal(fit_both(60, NULL, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    for (i = 0; i < 60; i++) { /* coincident */
        g_fpts[i].v[0] = 2100.0f;
        g_fpts[i].v[1] = -1500.0f;
        g_fpts[i].v[2] = 900.0f;
    }
    assert_int_equal(fit_both(60, NULL, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    assert_string_equal(sfit_status_str(SFIT_E_UNSUPPORTED), "unsupported");
}

/* What only the full solver serves: SFIT_E_UNSUPPORTED even on data the
 * screen passes; invalid options and too few samples keep their statuses. */
static void test_options(void **state)
{
    sfit_result_t r;
    sfit_fit_cfg_t c;
    (void)state;
    make_cap(1605, 500, 100.0, 60.0, 0.5);
    c = sfit_fit_cfg_default;
    c.eigen = true;
    assert_int_equal(fit_both(500, &c, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    c = sfit_fit_cfg_default;
    c.mode = SFIT_MODE_PLANAR;
    assert_int_equal(fit_both(500, &c, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    c = sfit_fit_cfg_default;
    c.noise = SFIT_NOISE_COV;
    memset(&c.noise_cov, 0, sizeof c.noise_cov);
    c.noise_cov.m[0] = c.noise_cov.m[4] = c.noise_cov.m[8] = 0.25f;
    assert_int_equal(fit_both(500, &c, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    c.noise_cov.m[4] = -1.0f; /* not positive semi-definite: the option is invalid */
    assert_int_equal(fit_both(500, &c, &r), SFIT_E_ARG);
    assert_untouched(&r);
    c = sfit_fit_cfg_default;
    tu_set_byte(&c.eigen, 2u); /* a bool holding byte 2 (garbage): refused */
    assert_int_equal(fit_both(500, &c, &r), SFIT_E_ARG);
    assert_untouched(&r);
    assert_int_equal(fit_both(3, NULL, &r), SFIT_E_TOO_FEW);
    assert_untouched(&r);
}

/* The modules built on sfit_fit_moments() inherit the status (their
 * headers' @retval lists): self-calibration, the gate (fit and refresh)
 * and the incremental start, each with its output untouched; on a cap the
 * screen passes, they fit. */
static void test_inherited(void **state)
{
    static sfit_gate_t g;
    sfit_selfcal_result_t sc;
    sfit_result_t r;
    sfit_incr_t inc;
    sfit_sphere_t sp, sentinel;
    size_t i;
    bool acc;
    (void)state;
    memset(&sentinel, SENTINEL, sizeof sentinel);
    make_circle(200, 80.0);
    memset(&sc, SENTINEL, sizeof sc);
    assert_int_equal(sfit_selfcal_points(g_fpts, 200, NULL, &sc), SFIT_E_UNSUPPORTED);
    assert_untouched(&sc.fit);
    assert_int_equal(sfit_gate_init(&g, NULL), SFIT_OK);
    for (i = 0; i < 200; i++) {
        assert_int_equal(sfit_gate_add(&g, &g_fpts[i], &acc), SFIT_OK);
    }
    memset(&r, SENTINEL, sizeof r);
    assert_int_equal(sfit_gate_fit(&g, &r), SFIT_E_UNSUPPORTED);
    assert_untouched(&r);
    assert_int_equal(sfit_gate_refresh(&g), SFIT_E_UNSUPPORTED);
    assert_int_equal(sfit_incr_init(&inc, NULL), SFIT_OK);
    memset(&sp, SENTINEL, sizeof sp);
    assert_int_equal(sfit_incr_start(&inc, g_fpts, 200, &sp), SFIT_E_UNSUPPORTED);
    assert_memory_equal(&sp, &sentinel, sizeof sp);

    make_cap(1606, 500, 100.0, 90.0, 0.5);
    assert_int_equal(sfit_incr_start(&inc, g_fpts, 500, &sp), SFIT_OK);
    assert_true(tc_dist(&sp.center, k_center) <= 0.5);
    /* a full noise covariance: the incremental estimator solves it itself
     * (the batch check used to ask sfit_fit_moments() for it and so always
     * returned SFIT_E_UNSUPPORTED); one too large for the data is refused */
    {
        sfit_incr_cfg_t ic = sfit_incr_cfg_default;
        sfit_sphere_t si;
        ic.noise = SFIT_NOISE_COV;
        ic.noise_cov.m[0] = 0.25f;
        ic.noise_cov.m[4] = 0.25f;
        ic.noise_cov.m[8] = 0.25f;
        ic.noise_cov.m[3] = 0.05f;
        ic.noise_cov.m[1] = 0.05f;
        assert_int_equal(sfit_incr_init(&inc, &ic), SFIT_OK);
        assert_int_equal(sfit_incr_start(&inc, g_fpts, 500, &sp), SFIT_OK);
        assert_true(tc_dist(&sp.center, k_center) <= 0.5);
        assert_int_equal(sfit_incr_fit(&inc, &si), SFIT_OK);
        assert_memory_equal(&si, &sp, sizeof si);
        ic.noise_cov.m[0] = ic.noise_cov.m[4] = ic.noise_cov.m[8] = 1e6f;
        ic.noise_cov.m[3] = ic.noise_cov.m[1] = 0.0f;
        assert_int_equal(sfit_incr_init(&inc, &ic), SFIT_OK);
        memset(&sp, SENTINEL, sizeof sp);
        assert_int_equal(sfit_incr_start(&inc, g_fpts, 500, &sp), SFIT_E_NOT_POSDEF);
        assert_memory_equal(&sp, &sentinel, sizeof sp);
        assert_int_equal(sfit_incr_count(&inc), 0u);
    }
}

/* Self-calibration without the full solver: its cap on sigma^2 comes from
 * the screen's lower bound of lambda_min(C). Where the noise stays below
 * that cap the fit is the default build's: UGDK at the estimated sigma^2
 * (compared with the double oracle at that sigma^2, as test_selfcal.c
 * does); where it reaches the cap (the issue-14 case: 30-degree cap,
 * sigma 5, N 1000, capped and flagged in the default build) the status is
 * SFIT_E_UNSUPPORTED, output untouched. */
static void test_selfcal(void **state)
{
    sfit_selfcal_result_t sc;
    ref_fit_t rf;
    double cov[6];
    (void)state;
    make_cap(1607, 800, 100.0, 35.0, 1.5);
    assert_int_equal(sfit_selfcal_points(g_fpts, 800, NULL, &sc), SFIT_OK);
    assert_int_equal(sc.flags, 0);
    assert_int_equal(sc.fit.exact, 0);
    assert_int_equal(sc.fit.method, SFIT_METHOD_UGDK);
    assert_true(sc.noise_var > 0.5f * 2.25f && sc.noise_var < 1.5f * 2.25f);
    cov[0] = cov[1] = cov[2] = (double)sc.noise_var;
    cov[3] = cov[4] = cov[5] = 0.0;
    assert_int_equal(ref_fit_sphere(REF_C3(g_pts), 800, cov, &rf), 0);
    assert_true(tc_dist(&sc.fit.center, rf.center) < 1e-2); /* 1e-4 r, as test_selfcal.c */
    assert_near(sc.fit.radius, rf.radius, 1e-2, "radius vs oracle");
    assert_true((double)sc.fit.leontief_ratio >= rf.trust_ratio * (1.0 - 1e-3));

    make_cap(1608, 1000, 100.0, 30.0, 5.0);
    memset(&sc, SENTINEL, sizeof sc);
    assert_int_equal(sfit_selfcal_points(g_fpts, 1000, NULL, &sc), SFIT_E_UNSUPPORTED);
    assert_untouched(&sc.fit);
}

/* The bound behind self-calibration's cap: for symmetric positive definite
 * C of every conditioning, 0 < lower <= lambda_min(C) (the double Jacobi
 * reference of the float matrix) and lower >= lambda_min / 3 less the
 * margins (e2 <= 3 l2 l3); 0 for a singular, indefinite or non-finite C. */
static void test_lmin_lower(void **state)
{
    tu_rng_t g;
    int t, i, j, k;
    (void)state;
    tu_rng_seed(&g, 1609);
    for (t = 0; t < 2000; t++) {
        double q[3][3], a[3][3], w[3], v[3][3], lam[3], norm, tr = 0.0, lo;
        sfit_mat3_t c;
        /* C = Q diag(lam) Q^T, Q from Gram-Schmidt of a random matrix,
         * lambda_min / lambda_max from 1 down to 1e-6 */
        for (i = 0; i < 3; i++) {
            for (k = 0; k < 3; k++) {
                q[i][k] = tu_rng_gauss(&g);
            }
            for (j = 0; j < i; j++) {
                const double d = q[i][0] * q[j][0] + q[i][1] * q[j][1] + q[i][2] * q[j][2];
                for (k = 0; k < 3; k++) {
                    q[i][k] -= d * q[j][k];
                }
            }
            norm = sqrt(q[i][0] * q[i][0] + q[i][1] * q[i][1] + q[i][2] * q[i][2]);
            for (k = 0; k < 3; k++) {
                q[i][k] /= norm;
            }
        }
        lam[2] = 1000.0;
        lam[1] = lam[2] * pow(10.0, -3.0 * tu_rng_uniform(&g));
        lam[0] = lam[1] * pow(10.0, -3.0 * tu_rng_uniform(&g));
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                double s = 0.0;
                for (k = 0; k < 3; k++) {
                    s += q[k][i] * lam[k] * q[k][j];
                }
                c.m[3 * i + j] = (float)s;
            }
        }
        for (i = 0; i < 3; i++) { /* the float matrix, symmetric, in double */
            for (j = 0; j < 3; j++) {
                a[i][j] = (double)c.m[3 * (i > j ? i : j) + (i > j ? j : i)];
            }
            tr += a[i][i];
        }
        ref_sym3_eig((const double (*)[3])a, w, v);
        lo = (double)sfit_i_lmin_lower(&c);
        assert_true(lo <= w[0]);
        assert_true(lo >= (w[0] / 3.0) * (1.0 - 0.015625) - 2.44140625e-4 * tr - 1e-5 * w[0]);
    }
    {
        sfit_mat3_t c;
        memset(&c, 0, sizeof c);
        c.m[0] = 1.0f;
        c.m[4] = 1.0f; /* singular */
        assert_true(sfit_i_lmin_lower(&c) == 0.0f);
        c.m[8] = -1.0f; /* indefinite */
        assert_true(sfit_i_lmin_lower(&c) == 0.0f);
        c.m[8] = 1.0f;
        c.m[3] = NAN;
        assert_true(sfit_i_lmin_lower(&c) == 0.0f);
        c.m[3] = 0.0f;
        assert_true(sfit_i_lmin_lower(&c) > 0.3f); /* I: 1/3 less the margins */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_screened_fits),
        cmocka_unit_test(test_few_samples_fit),
        cmocka_unit_test(test_tripped),
        cmocka_unit_test(test_options),
        cmocka_unit_test(test_inherited),
        cmocka_unit_test(test_selfcal),
        cmocka_unit_test(test_lmin_lower),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
