/* SPDX-License-Identifier: MIT */
/**
 * @file test_status.c
 * @brief Every sfit_status_t value, produced through the public API of
 * every module that can return it, with the contract checked on each
 * failure: the output (filled with a sentinel) is untouched and a rejected
 * sample leaves the state byte for byte unchanged. Also the range limits of
 * the issue: sample counts at the counter's limit, coordinates whose
 * squares overflow float, and a noise covariance larger than the data's
 * spread.
 *
 * SFIT_E_NO_CONVERGENCE cannot be produced with the default Jacobi bound
 * (12 sweeps; a search over 2e7 random symmetric matrices of mixed scales,
 * subnormals included, found none that needs more; see
 * docs/reliability.md). Built with -DSFIT_JACOBI_MAX_SWEEPS=1, as
 * tests/scripts/test_clang.sh does, this file runs only the
 * no-convergence test, which then produces it through sfit_mat3_eig_sym,
 * sfit_fit_moments, sfit_multi_fit and sfit_incr_start. In the default
 * build that test is reported as skipped.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit/sfit_coverage.h"
#include "sfit/sfit_incr.h"
#include "sfit/sfit_noise.h"

#define TS_SENTINEL 0xA5
#define TS_NPTS 40

static const double ts_far[3] = {2700.0, -1200.0, 900.0};
static const double ts_axis[3] = {0.3, -0.5, 0.81};

/** Fail unless every byte of an object still holds the sentinel. */
#define assert_untouched(obj)                                                          \
    do {                                                                               \
        size_t k_;                                                                     \
        const unsigned char *b_ = (const unsigned char *)&(obj);                       \
        for (k_ = 0; k_ < sizeof(obj); k_++) {                                         \
            if (b_[k_] != (unsigned char)TS_SENTINEL) {                                \
                print_error("%s written on failure (byte %u)\n", #obj, (unsigned)k_);  \
                fail();                                                                \
            }                                                                          \
        }                                                                              \
    } while (0)

#define assert_status(expr, want)                                                      \
    do {                                                                               \
        const sfit_status_t got_ = (expr);                                             \
        if (got_ != (want)) {                                                          \
            print_error("%s: %s (%d), expected %s (%d)\n", #expr, sfit_status_str(got_), \
                        (int)got_, sfit_status_str(want), (int)(want));                \
            fail();                                                                    \
        }                                                                              \
    } while (0)

/* n noise-free points on a cap of half-angle theta (sphere r about c). */
static void ts_cap(sfit_vec3_t *pts, size_t n, const double c[3], double r, double theta,
                   uint64_t seed)
{
    tu_rng_t g;
    size_t i;
    tu_rng_seed(&g, seed);
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_cap(&g, c, r, ts_axis, theta, 0.0, p);
        tc_to_vec3(p, &pts[i]);
    }
}

static void ts_fill(sfit_moments_t *m, const sfit_vec3_t *pts, size_t n)
{
    assert_status(sfit_moments_init(m), SFIT_OK);
    assert_status(sfit_moments_add_block(m, pts, n, NULL), SFIT_OK);
}

static void ts_check_result(const sfit_result_t *r)
{
    int i;
    for (i = 0; i < 3; i++) {
        assert_true(isfinite(r->center.v[i]) && isfinite(r->eigenvalues.v[i]) && isfinite(r->axis.v[i]));
    }
    assert_true(isfinite(r->radius) && r->radius > 0.0f);
    assert_true(isfinite(r->trust_ratio) && isfinite(r->leontief_ratio));
}

/* ---------------------------------------------------------------- names */

static void test_status_names(void **state)
{
    static const sfit_status_t all[] = {SFIT_OK,         SFIT_E_ARG,        SFIT_E_TOO_FEW,
                                        SFIT_E_NOT_POSDEF, SFIT_E_NO_CONVERGENCE,
                                        SFIT_E_DEGENERATE, SFIT_E_NONFINITE, SFIT_E_RANGE};
    size_t i, j;
    (void)state;
    for (i = 0; i < sizeof all / sizeof all[0]; i++) {
        const char *a = sfit_status_str(all[i]);
        assert_non_null(a);
        assert_true(strcmp(a, "unknown") != 0);
        assert_true((all[i] == SFIT_OK) == ((int)all[i] == 0));
        assert_true((int)all[i] <= 0);
        for (j = 0; j < i; j++) {
            assert_true(strcmp(a, sfit_status_str(all[j])) != 0);
        }
    }
    assert_string_equal(sfit_status_str((sfit_status_t)-99), "unknown");
    assert_string_equal(sfit_status_str((sfit_status_t)1), "unknown");
}

/* ------------------------------------------------------------------- OK */

static void test_ok(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    sfit_moments_t m[2];
    sfit_result_t r;
    sfit_multi_result_t mr;
    sfit_vec3_t mean, s;
    sfit_mat3_t c, l;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, 1.2, 1u);
    ts_fill(&m[0], pts, TS_NPTS / 2);
    ts_fill(&m[1], pts + TS_NPTS / 2, TS_NPTS / 2);
    assert_status(sfit_moments_stats(&m[0], &mean, &c, &s), SFIT_OK);
    assert_status(sfit_mat3_chol(&c, &l), SFIT_OK);
    assert_status(sfit_fit_moments(&m[0], NULL, &r), SFIT_OK);
    ts_check_result(&r);
    assert_status(sfit_fit_points(pts, TS_NPTS, NULL, &r), SFIT_OK);
    ts_check_result(&r);
    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = 0.01f;
    cfg.eigen = true; /* r.eigenvalues are used below */
    assert_status(sfit_fit_moments(&m[1], &cfg, &r), SFIT_OK);
    assert_status(sfit_multi_fit(m, 2u, NULL, &mr, NULL), SFIT_OK);
    assert_status(sfit_moments_merge(&m[0], &m[1]), SFIT_OK);
    assert_int_equal(sfit_moments_count(&m[0]), TS_NPTS);
    {
        sfit_incr_t inc;
        sfit_sphere_t e;
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        assert_status(sfit_incr_start(&inc, pts, 10u, &e), SFIT_OK);
        assert_status(sfit_incr_update(&inc, &pts[10], &e), SFIT_OK);
        assert_status(sfit_incr_fit(&inc, &e), SFIT_OK);
        assert_int_equal(e.n, 11);
    }
    {
        sfit_noise_est_t ne;
        sfit_vec3_t c0;
        float x;
        tc_to_vec3(ts_far, &c0);
        assert_status(sfit_noise_calibrate(&m[0], &c0, 100.0f, &ne), SFIT_OK);
        assert_status(sfit_noise_calib_std(1.0f, 100.0f, 100u, &x), SFIT_OK);
        assert_status(sfit_coverage_max_sigma(SFIT_COVERAGE_CAP, 0.5f, 100.0f, &x), SFIT_OK);
        assert_status(sfit_coverage_min_theta(SFIT_COVERAGE_ARC, 0.01f, &x), SFIT_OK);
        assert_status(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &r.eigenvalues, &x), SFIT_OK);
    }
}

/* ------------------------------------------------------------ E_ARG */

static void test_e_arg(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    sfit_moments_t m;
    sfit_result_t r;
    sfit_multi_result_t mr;
    sfit_multi_cfg_t mc = sfit_multi_cfg_default;
    sfit_fit_cfg_t cfg;
    sfit_mat3_t a, l;
    sfit_vec3_t w;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, 1.2, 2u);
    ts_fill(&m, pts, TS_NPTS);
    memset(&r, TS_SENTINEL, sizeof r);
    memset(&mr, TS_SENTINEL, sizeof mr);

    /* NULL pointers, one per module. */
    assert_status(sfit_moments_init(NULL), SFIT_E_ARG);
    assert_status(sfit_moments_add(&m, NULL), SFIT_E_ARG);
    assert_status(sfit_moments_add_block(&m, NULL, 3u, NULL), SFIT_E_ARG);
    assert_status(sfit_moments_merge(&m, NULL), SFIT_E_ARG);
    assert_status(sfit_moments_stats(NULL, NULL, NULL, NULL), SFIT_E_ARG);
    assert_status(sfit_mat3_chol(NULL, &l), SFIT_E_ARG);
    assert_status(sfit_mat3_chol_solve(&l, NULL, &w), SFIT_E_ARG);
    assert_status(sfit_mat3_eig_sym(&a, NULL, NULL), SFIT_E_ARG);
    assert_status(sfit_fit_moments(&m, NULL, NULL), SFIT_E_ARG);
    assert_status(sfit_fit_points(NULL, 4u, NULL, &r), SFIT_E_ARG);
    assert_status(sfit_multi_fit(NULL, 1u, NULL, &mr, NULL), SFIT_E_ARG);

    /* Invalid options: bad enums, a negative / NaN variance, a planar
     * ratio outside [0, 1), a negative variance on the covariance diagonal. */
    cfg = sfit_fit_cfg_default;
    cfg.mode = (sfit_mode_t)7;
    assert_status(sfit_fit_moments(&m, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.noise = (sfit_noise_kind_t)3;
    assert_status(sfit_fit_moments(&m, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = -1.0f;
    assert_status(sfit_fit_moments(&m, &cfg, &r), SFIT_E_ARG);
    cfg.noise_var = NAN;
    assert_status(sfit_fit_points(pts, TS_NPTS, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.planar_ratio = 1.5f;
    assert_status(sfit_fit_moments(&m, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.noise = SFIT_NOISE_COV;
    cfg.noise_cov.m[4] = -1.0f;
    assert_status(sfit_fit_moments(&m, &cfg, &r), SFIT_E_ARG);
    mc.weight = (sfit_multi_weight_t)5;
    assert_status(sfit_multi_fit(&m, 1u, &mc, &mr, NULL), SFIT_E_ARG);
    assert_untouched(r);
    assert_untouched(mr);
    {
        sfit_incr_t inc, before;
        sfit_sphere_t e;
        memset(&e, TS_SENTINEL, sizeof e);
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        memcpy(&before, &inc, sizeof inc);
        sfit_incr_cfg_t icfg = sfit_incr_cfg_default;
        icfg.noise = (sfit_noise_kind_t)9;
        assert_status(sfit_incr_init(&inc, &icfg), SFIT_E_ARG);
        assert_memory_equal(&before, &inc, sizeof inc);
        assert_status(sfit_incr_add(NULL, &pts[0]), SFIT_E_ARG);
        assert_status(sfit_incr_start(&inc, NULL, 5u, &e), SFIT_E_ARG);
        assert_status(sfit_incr_fit(&inc, NULL), SFIT_E_ARG);
        assert_untouched(e);
    }
    {
        sfit_noise_est_t ne;
        sfit_vec3_t c0 = {{0.0f, 0.0f, 0.0f}};
        float x;
        memset(&ne, TS_SENTINEL, sizeof ne);
        memset(&x, TS_SENTINEL, sizeof x);
        assert_status(sfit_noise_calibrate(&m, &c0, -1.0f, &ne), SFIT_E_ARG);
        assert_status(sfit_noise_calib_std(1.0f, 1.0f, 0u, &x), SFIT_E_ARG);
        assert_status(sfit_coverage_max_sigma((sfit_coverage_kind_t)9, 1.0f, 1.0f, &x), SFIT_E_ARG);
        assert_status(sfit_coverage_max_sigma(SFIT_COVERAGE_CAP, 4.0f, 1.0f, &x), SFIT_E_ARG);
        assert_status(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, -0.1f, &x), SFIT_E_ARG);
        assert_untouched(ne);
        assert_untouched(x);
    }
}

/* --------------------------------------------------------- E_TOO_FEW */

static void test_e_too_few(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    sfit_moments_t m[2];
    sfit_result_t r;
    sfit_multi_result_t mr;
    sfit_vec3_t mean;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, 1.2, 3u);
    memset(&r, TS_SENTINEL, sizeof r);
    memset(&mr, TS_SENTINEL, sizeof mr);
    memset(&mean, TS_SENTINEL, sizeof mean);
    ts_fill(&m[0], pts, 1u);
    assert_status(sfit_moments_stats(&m[0], &mean, NULL, NULL), SFIT_E_TOO_FEW);
    ts_fill(&m[0], pts, SFIT_MIN_SAMPLES - 1u);
    ts_fill(&m[1], pts, 2u);
    assert_status(sfit_fit_moments(&m[0], NULL, &r), SFIT_E_TOO_FEW);
    assert_status(sfit_fit_points(pts, SFIT_MIN_SAMPLES - 1u, NULL, &r), SFIT_E_TOO_FEW);
    assert_status(sfit_multi_fit(m, 0u, NULL, &mr, NULL), SFIT_E_TOO_FEW);
    assert_status(sfit_multi_fit(m, 2u, NULL, &mr, NULL), SFIT_E_TOO_FEW); /* both occluded */
    assert_untouched(r);
    assert_untouched(mr);
    assert_untouched(mean);
    {
        sfit_incr_t inc;
        sfit_sphere_t e;
        memset(&e, TS_SENTINEL, sizeof e);
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        assert_status(sfit_incr_start(&inc, pts, SFIT_MIN_SAMPLES - 1u, &e), SFIT_E_TOO_FEW);
        assert_status(sfit_incr_update(&inc, &pts[0], &e), SFIT_E_TOO_FEW); /* kept, but too few */
        assert_int_equal(sfit_incr_count(&inc), 1);
        assert_status(sfit_incr_fit(&inc, &e), SFIT_E_TOO_FEW);
        assert_untouched(e);
    }
    {
        sfit_noise_est_t ne;
        sfit_vec3_t c0 = {{0.0f, 0.0f, 0.0f}};
        memset(&ne, TS_SENTINEL, sizeof ne);
        assert_status(sfit_moments_init(&m[0]), SFIT_OK);
        assert_status(sfit_noise_calibrate(&m[0], &c0, 1.0f, &ne), SFIT_E_TOO_FEW);
        assert_untouched(ne);
    }
}

/* ------------------------------------------------------- E_NOT_POSDEF */

/*
 * A noise covariance larger than the data's spread: a cap of half-angle
 * 0.3 rad on r = 100 has an axial variance of r^2 sin^4(theta/2)/3 ~ 1.7
 * (chapter eq. 210), so sigma^2 = 25 exceeds it: C - sigma^2 I is
 * indefinite and UGDK must refuse, in every module. sigma^2 = 0.5 is below
 * lambda_min and succeeds (control).
 */
static void test_e_not_posdef_noise_larger_than_spread(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    sfit_moments_t m[2];
    sfit_result_t r;
    sfit_multi_result_t mr;
    sfit_multi_cfg_t mc = sfit_multi_cfg_default;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    sfit_mat3_t a, l;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, 0.3, 4u);
    ts_fill(&m[0], pts, TS_NPTS);
    ts_fill(&m[1], pts, TS_NPTS);
    memset(&r, TS_SENTINEL, sizeof r);
    memset(&mr, TS_SENTINEL, sizeof mr);
    memset(&l, TS_SENTINEL, sizeof l);

    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = 0.5f;
    assert_status(sfit_fit_moments(&m[0], &cfg, &r), SFIT_OK);
    assert_true(r.eigenvalues.v[0] > 0.5f && r.eigenvalues.v[0] < 25.0f);
    memset(&r, TS_SENTINEL, sizeof r);
    cfg.noise_var = 25.0f;
    cfg.mode = SFIT_MODE_SPHERE;
    assert_status(sfit_fit_moments(&m[0], &cfg, &r), SFIT_E_NOT_POSDEF);
    cfg.noise = SFIT_NOISE_COV;
    memset(&cfg.noise_cov, 0, sizeof cfg.noise_cov);
    cfg.noise_cov.m[0] = 25.0f;
    cfg.noise_cov.m[4] = 25.0f;
    cfg.noise_cov.m[8] = 25.0f;
    assert_status(sfit_fit_points(pts, TS_NPTS, &cfg, &r), SFIT_E_NOT_POSDEF);
    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = 1e6f; /* larger than every eigenvalue: planar mode too */
    cfg.mode = SFIT_MODE_PLANAR;
    assert_status(sfit_fit_moments(&m[0], &cfg, &r), SFIT_E_NOT_POSDEF);
    mc.fit = cfg;
    assert_status(sfit_multi_fit(m, 2u, &mc, &mr, NULL), SFIT_E_NOT_POSDEF);
    /* The kernel itself: an indefinite matrix. */
    memset(&a, 0, sizeof a);
    a.m[0] = 1.0f;
    a.m[4] = -1.0f;
    a.m[8] = 1.0f;
    assert_status(sfit_mat3_chol(&a, &l), SFIT_E_NOT_POSDEF);
    assert_untouched(r);
    assert_untouched(mr);
    assert_untouched(l);
    {
        sfit_incr_t inc, before;
        sfit_sphere_t e;
        memset(&e, TS_SENTINEL, sizeof e);
        sfit_incr_cfg_t icfg = sfit_incr_cfg_default;
        icfg.noise = SFIT_NOISE_ISO;
        icfg.noise_var = 25.0f;
        assert_status(sfit_incr_init(&inc, &icfg), SFIT_OK);
        memcpy(&before, &inc, sizeof inc);
        assert_status(sfit_incr_start(&inc, pts, TS_NPTS, &e), SFIT_E_NOT_POSDEF);
        assert_memory_equal(&before, &inc, sizeof inc); /* failed start: unchanged */
        {
            size_t i;
            for (i = 0; i < TS_NPTS; i++) {
                assert_status(sfit_incr_add(&inc, &pts[i]), SFIT_OK);
            }
        }
        assert_status(sfit_incr_fit(&inc, &e), SFIT_E_NOT_POSDEF);
        assert_untouched(e);
    }
}

/* -------------------------------------------------- E_NO_CONVERGENCE */

static void test_e_no_convergence(void **state)
{
    (void)state;
#if SFIT_JACOBI_MAX_SWEEPS <= 1
    {
        /* One sweep of three rotations cannot diagonalise a generic matrix:
         * each rotation refills an entry the previous one zeroed. */
        static sfit_vec3_t pts[TS_NPTS];
        const sfit_mat3_t a = {{4.0f, 1.0f, 2.0f, 1.0f, 3.0f, 0.5f, 2.0f, 0.5f, 5.0f}};
        sfit_moments_t m[2];
        sfit_result_t r;
        sfit_multi_result_t mr;
        sfit_vec3_t w;
        sfit_mat3_t v;
        memset(&w, TS_SENTINEL, sizeof w);
        memset(&v, TS_SENTINEL, sizeof v);
        memset(&r, TS_SENTINEL, sizeof r);
        memset(&mr, TS_SENTINEL, sizeof mr);
        assert_status(sfit_mat3_eig_sym(&a, &w, &v), SFIT_E_NO_CONVERGENCE);
        ts_cap(pts, TS_NPTS, ts_far, 100.0, 1.2, 5u);
        ts_fill(&m[0], pts, TS_NPTS);
        ts_fill(&m[1], pts, TS_NPTS);
        assert_status(sfit_fit_moments(&m[0], NULL, &r), SFIT_E_NO_CONVERGENCE);
        assert_status(sfit_multi_fit(m, 2u, NULL, &mr, NULL), SFIT_E_NO_CONVERGENCE);
        assert_untouched(w);
        assert_untouched(v);
        assert_untouched(r);
        assert_untouched(mr);
        {
            sfit_incr_t inc, before;
            sfit_sphere_t e;
            memset(&e, TS_SENTINEL, sizeof e);
            assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
            memcpy(&before, &inc, sizeof inc);
            assert_status(sfit_incr_start(&inc, pts, TS_NPTS, &e), SFIT_E_NO_CONVERGENCE);
            assert_memory_equal(&before, &inc, sizeof inc);
            assert_untouched(e);
        }
        print_message("no_convergence: produced with SFIT_JACOBI_MAX_SWEEPS=%d\n",
                      SFIT_JACOBI_MAX_SWEEPS);
    }
#else
    print_message("no_convergence: unreachable with SFIT_JACOBI_MAX_SWEEPS=%d; "
                  "tests/scripts/test_clang.sh builds this test with a bound of 1\n",
                  SFIT_JACOBI_MAX_SWEEPS);
    skip();
#endif
}

/* ------------------------------------------------------ E_DEGENERATE */

static void test_e_degenerate(void **state)
{
    sfit_vec3_t pts[TS_NPTS];
    sfit_moments_t m;
    sfit_result_t r;
    sfit_multi_result_t mr;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    size_t i;
    (void)state;
    memset(&r, TS_SENTINEL, sizeof r);
    memset(&mr, TS_SENTINEL, sizeof mr);
    /* Coincident: one far-away point repeated (a stuck sensor). */
    for (i = 0; i < TS_NPTS; i++) {
        tc_to_vec3(ts_far, &pts[i]);
    }
    ts_fill(&m, pts, TS_NPTS);
    assert_status(sfit_fit_moments(&m, NULL, &r), SFIT_E_DEGENERATE);
    assert_status(sfit_multi_fit(&m, 1u, NULL, &mr, NULL), SFIT_E_DEGENERATE);
    /* Collinear: points on a line. */
    for (i = 0; i < TS_NPTS; i++) {
        const double t = (double)i - 20.0;
        const double p[3] = {ts_far[0] + t, ts_far[1] + 2.0 * t, ts_far[2] - 0.5 * t};
        tc_to_vec3(p, &pts[i]);
    }
    assert_status(sfit_fit_points(pts, TS_NPTS, NULL, &r), SFIT_E_DEGENERATE);
    /* Exactly planar (a circle in z = 0) forced into the GDKE sphere solution. */
    for (i = 0; i < TS_NPTS; i++) {
        const double a = 2.0 * TU_PI * (double)i / TS_NPTS;
        const double p[3] = {50.0 * cos(a), 50.0 * sin(a), 0.0};
        tc_to_vec3(p, &pts[i]);
    }
    ts_fill(&m, pts, TS_NPTS);
    cfg.mode = SFIT_MODE_SPHERE;
    assert_status(sfit_fit_moments(&m, &cfg, &r), SFIT_E_DEGENERATE);
    assert_untouched(r);
    assert_untouched(mr);
    {
        sfit_incr_t inc;
        sfit_sphere_t e;
        memset(&e, TS_SENTINEL, sizeof e);
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        assert_status(sfit_incr_start(&inc, pts, TS_NPTS, &e), SFIT_E_DEGENERATE);
        for (i = 0; i < TS_NPTS; i++) {
            assert_status(sfit_incr_add(&inc, &pts[i]), SFIT_OK);
        }
        assert_status(sfit_incr_fit(&inc, &e), SFIT_E_DEGENERATE);
        assert_untouched(e);
    }
    {
        const sfit_vec3_t eig = {{0.0f, 1.0f, 2.0f}}; /* no axial extent: no coverage */
        float th;
        memset(&th, TS_SENTINEL, sizeof th);
        assert_status(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, &th), SFIT_E_DEGENERATE);
        assert_untouched(th);
    }
}

/* ------------------------------------------------------- E_NONFINITE */

static void test_e_nonfinite(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    static const float bad[] = {NAN, INFINITY, -INFINITY};
    sfit_moments_t m, before;
    sfit_result_t r;
    sfit_mat3_t a;
    sfit_vec3_t w;
    size_t i, j, idx = 99u;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, 1.2, 6u);
    ts_fill(&m, pts, 10u);
    memset(&r, TS_SENTINEL, sizeof r);
    memset(&w, TS_SENTINEL, sizeof w);
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        for (j = 0; j < 3; j++) {
            sfit_vec3_t x = pts[11];
            x.v[j] = bad[i];
            memcpy(&before, &m, sizeof m);
            assert_status(sfit_moments_add(&m, &x), SFIT_E_NONFINITE);
            assert_memory_equal(&before, &m, sizeof m);
        }
    }
    pts[25].v[1] = NAN;
    memcpy(&before, &m, sizeof m);
    assert_status(sfit_moments_add_block(&m, pts, TS_NPTS, &idx), SFIT_E_NONFINITE);
    assert_memory_equal(&before, &m, sizeof m);
    assert_int_equal(idx, 25);
    assert_status(sfit_fit_points(pts, TS_NPTS, NULL, &r), SFIT_E_NONFINITE);
    memset(&a, 0, sizeof a);
    a.m[0] = 1.0f;
    a.m[4] = 1.0f;
    a.m[8] = 1.0f;
    a.m[7] = INFINITY;
    assert_status(sfit_mat3_eig_sym(&a, &w, NULL), SFIT_E_NONFINITE);
    assert_untouched(r);
    assert_untouched(w);
    {
        sfit_incr_t inc, ib;
        sfit_sphere_t e;
        sfit_vec3_t x = pts[0];
        memset(&e, TS_SENTINEL, sizeof e);
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        assert_status(sfit_incr_start(&inc, pts, 10u, NULL), SFIT_OK);
        x.v[2] = -INFINITY;
        memcpy(&ib, &inc, sizeof inc);
        assert_status(sfit_incr_add(&inc, &x), SFIT_E_NONFINITE);
        assert_status(sfit_incr_update(&inc, &x, &e), SFIT_E_NONFINITE);
        assert_memory_equal(&ib, &inc, sizeof inc);
        assert_status(sfit_incr_start(&inc, pts, TS_NPTS, &e), SFIT_E_NONFINITE);
        assert_memory_equal(&ib, &inc, sizeof inc);
        assert_untouched(e);
    }
    {
        sfit_noise_est_t ne;
        sfit_vec3_t c0 = {{0.0f, NAN, 0.0f}};
        float x;
        memset(&ne, TS_SENTINEL, sizeof ne);
        memset(&x, TS_SENTINEL, sizeof x);
        assert_status(sfit_noise_calibrate(&m, &c0, 1.0f, &ne), SFIT_E_NONFINITE);
        assert_status(sfit_noise_calib_std(INFINITY, 1.0f, 10u, &x), SFIT_E_NONFINITE);
        assert_status(sfit_coverage_max_sigma(SFIT_COVERAGE_ARC, NAN, 1.0f, &x), SFIT_E_NONFINITE);
        assert_untouched(ne);
        assert_untouched(x);
    }
}

/* ----------------------------------------------------------- E_RANGE */

/* Coordinates whose squares (or cubes summed over 2^32 samples) would
 * overflow float are rejected; the largest accepted coordinate still
 * gives a finite fit. */
static void test_e_range_coordinates(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    const float lim = ldexpf(1.0f, SFIT_COORD_MAX_EXP);  /* first rejected */
    const float ok = nextafterf(lim, 0.0f);              /* largest accepted */
    const float huge[] = {lim, -lim, 1.8446744e19f /* square > FLT_MAX */, 1e30f, FLT_MAX};
    sfit_moments_t m, before;
    sfit_result_t r;
    size_t i, j, idx = 99u;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, 1.2, 7u);
    ts_fill(&m, pts, 10u);
    memset(&r, TS_SENTINEL, sizeof r);
    for (i = 0; i < sizeof huge / sizeof huge[0]; i++) {
        for (j = 0; j < 3; j++) {
            sfit_vec3_t x = pts[12];
            x.v[j] = huge[i];
            memcpy(&before, &m, sizeof m);
            assert_status(sfit_moments_add(&m, &x), SFIT_E_RANGE);
            assert_memory_equal(&before, &m, sizeof m);
        }
    }
    pts[30].v[0] = -lim;
    assert_status(sfit_moments_add_block(&m, pts, TS_NPTS, &idx), SFIT_E_RANGE);
    assert_int_equal(idx, 30);
    assert_memory_equal(&before, &m, sizeof m);
    assert_status(sfit_fit_points(pts, TS_NPTS, NULL, &r), SFIT_E_RANGE);
    assert_untouched(r);

    /* A sphere of radius 2^25 centred at the largest accepted coordinate
     * minus the radius: every sample in range, the fit finite. */
    {
        const double c[3] = {(double)ok - 4.0e7, -(double)ok + 4.0e7, 1.0e8};
        ts_cap(pts, TS_NPTS, c, 3.3e7, TU_PI, 8u);
        for (i = 0; i < TS_NPTS; i++) {
            for (j = 0; j < 3; j++) {
                assert_true(fabsf(pts[i].v[j]) < lim);
            }
        }
        assert_status(sfit_fit_points(pts, TS_NPTS, NULL, &r), SFIT_OK);
        ts_check_result(&r);
        assert_near(r.radius, 3.3e7, 3.3e7 * 1e-3, "radius at the coordinate limit");
    }
    {
        sfit_incr_t inc, ib;
        sfit_vec3_t x = pts[0];
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        x.v[1] = 1e30f;
        memcpy(&ib, &inc, sizeof inc);
        assert_status(sfit_incr_add(&inc, &x), SFIT_E_RANGE);
        assert_memory_equal(&ib, &inc, sizeof inc);
    }
    {
        float x;
        memset(&x, TS_SENTINEL, sizeof x);
        /* sigma/r >= 1/sqrt(3): no cap coverage is enough. */
        assert_status(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, 0.6f, &x), SFIT_E_RANGE);
        /* r^2 overflows float. */
        assert_status(sfit_coverage_eigs(SFIT_COVERAGE_CAP, 1.0f, 1e20f, &x, NULL), SFIT_E_RANGE);
        assert_untouched(x);
    }
}

/*
 * The sample counter at its limit. UINT32_MAX samples cannot be added one
 * by one in a unit test, but merging doubles counts: acc holds 7 samples
 * of a sphere, `eight` holds 8 others and is doubled by self-merges;
 * merged into acc after each of its 29 sizes 8 * 2^k (k = 0..28), it
 * brings acc to 7 + 8 (2^29 - 1) = 2^32 - 1 = UINT32_MAX samples. Then
 * every way to add one more is refused with SFIT_E_RANGE and changes
 * nothing, and the fit of these 4.3e9 samples (15 distinct points of one
 * sphere, heavily weighted) is finite and still finds the sphere.
 */
static void test_e_range_counter_limit(void **state)
{
    static sfit_vec3_t pts[TS_NPTS];
    sfit_moments_t acc, one, before, two;
    sfit_result_t r;
    sfit_vec3_t mean;
    sfit_mat3_t c;
    int k;
    (void)state;
    ts_cap(pts, TS_NPTS, ts_far, 100.0, TU_PI, 9u);
    ts_fill(&acc, pts, 7u);
    ts_fill(&one, &pts[7], 8u);
    for (k = 0; k <= 28; k++) {
        assert_status(sfit_moments_merge(&acc, &one), SFIT_OK);
        if (k < 28) {
            assert_status(sfit_moments_merge(&one, &one), SFIT_OK); /* self-merge doubles */
        }
    }
    assert_int_equal(sfit_moments_count(&acc), UINT32_MAX);
    assert_int_equal(sfit_moments_count(&one), 1u << 31);
    memcpy(&before, &acc, sizeof acc);
    assert_status(sfit_moments_add(&acc, &pts[20]), SFIT_E_RANGE);
    assert_status(sfit_moments_add_block(&acc, &pts[20], 1u, NULL), SFIT_E_RANGE);
    assert_status(sfit_moments_merge(&acc, &one), SFIT_E_RANGE);
    assert_status(sfit_moments_merge(&one, &one), SFIT_E_RANGE); /* 2^32 */
    assert_memory_equal(&before, &acc, sizeof acc);
    ts_fill(&two, pts, 2u);
    assert_status(sfit_moments_merge(&acc, &two), SFIT_E_RANGE);
    assert_memory_equal(&before, &acc, sizeof acc);
    assert_status(sfit_moments_merge(&acc, &acc), SFIT_E_RANGE);
    assert_memory_equal(&before, &acc, sizeof acc);
    /* Still usable: statistics and fit are finite. */
    assert_status(sfit_moments_stats(&acc, &mean, &c, NULL), SFIT_OK);
    for (k = 0; k < 9; k++) {
        assert_true(isfinite(c.m[k]));
    }
    assert_status(sfit_fit_moments(&acc, NULL, &r), SFIT_OK);
    ts_check_result(&r);
    assert_int_equal(r.n, UINT32_MAX);
    print_message("counter limit: centre error %.3g, radius error %.3g (r = 100)\n",
                  tc_dist(&r.center, ts_far), fabs((double)r.radius - 100.0));
    assert_true(tc_dist(&r.center, ts_far) < 0.1 && fabs((double)r.radius - 100.0) < 0.1);
    {
        sfit_multi_result_t mr;
        sfit_moments_t mk[2];
        memcpy(&mk[0], &acc, sizeof acc);
        ts_fill(&mk[1], pts, 10u);
        memset(&mr, TS_SENTINEL, sizeof mr);
        /* The total sample count of the markers exceeds the counter. */
        assert_status(sfit_multi_fit(mk, 2u, NULL, &mr, NULL), SFIT_E_RANGE);
        assert_untouched(mr);
    }
    {
        /* White-box: 4.3e9 calls are out of reach, so the (documented,
         * caller-visible) counter of a valid state is set to the limit. */
        sfit_incr_t inc, ib;
        assert_status(sfit_incr_init(&inc, NULL), SFIT_OK);
        assert_status(sfit_incr_start(&inc, pts, 10u, NULL), SFIT_OK);
        inc.n = UINT32_MAX;
        memcpy(&ib, &inc, sizeof inc);
        assert_status(sfit_incr_add(&inc, &pts[11]), SFIT_E_RANGE);
        assert_memory_equal(&ib, &inc, sizeof inc);
    }
}

int main(void)
{
#if SFIT_JACOBI_MAX_SWEEPS <= 1
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_e_no_convergence),
    };
#else
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_names),
        cmocka_unit_test(test_ok),
        cmocka_unit_test(test_e_arg),
        cmocka_unit_test(test_e_too_few),
        cmocka_unit_test(test_e_not_posdef_noise_larger_than_spread),
        cmocka_unit_test(test_e_no_convergence),
        cmocka_unit_test(test_e_degenerate),
        cmocka_unit_test(test_e_nonfinite),
        cmocka_unit_test(test_e_range_coordinates),
        cmocka_unit_test(test_e_range_counter_limit),
    };
#endif
    return cmocka_run_group_tests_name("status", tests, NULL, NULL);
}
