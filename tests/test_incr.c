/* SPDX-License-Identifier: MIT */
/**
 * @file test_incr.c
 * @brief Incremental estimator (chapter 5.4): recursion vs batch, float
 * stability up to 10^6 samples, UGDK, error handling.
 *
 * Oracles: ref_fit_sphere() (batch, double, tests/ref/sfit_ref.c) and the
 * double recursions of tests/ref/sfit_ref_incr.c. Nothing here is computed
 * by the code under test.
 *
 * Tolerances
 *  - 1e-9 r for a double recursion against the double batch fit: double
 *    rounding gives ~eps sqrt(N) cond(C) |c - m| ~ 1e-16 * 300 * 20 * r
 *    ~ 1e-12 r at N = 2e4, so 1e-9 r is 1000x above rounding, while any
 *    wrong factor or sign in a recursion is off by >= 1e-3 r (the printed
 *    eq. 229 is, see test_ref_chapter_printed_229_is_wrong).
 *  - 1e-4 r for the float library against the double batch fit, at every
 *    checkpoint up to 10^6 samples (the requirement). Float
 *    rounding alone (eps = 1.2e-7, samples rounded to float) bounds what
 *    is achievable at ~1e-6 r; the chapter's recursion in float reaches
 *    2.8e-3 r at 10^6 (docs/incremental.md), so the bound separates a
 *    stable formulation from a drifting one by a factor > 25.
 * Samples: uniform on a cap (tu_sample_cap) plus isotropic Gaussian noise
 * sigma = 0.5 mm, centre (1500, -2000, 1000) (|c| = 2693 mm), r = 100 mm,
 * rounded to float; the double references see the same rounded values.
 */
#include <stdlib.h>
#include <string.h>

#include "test_cmocka.h"

#include "sfit/sfit_incr.h"
#include "sfit_ref.h"
#include "sfit_ref_incr.h"

#define N_LONG 1000000u
#define R0 100.0
#define SIGMA 0.5

static const double C0[3] = {1500.0, -2000.0, 1000.0};
static const double AXIS[3] = {0.3, 0.5, -0.8};
/* Noise models: isotropic sigma^2, and a full covariance (XX,YY,ZZ,XY,XZ,YZ). */
static const double COV_ISO[6] = {0.25, 0.25, 0.25, 0.0, 0.0, 0.0};
static const double COV_FULL[6] = {0.30, 0.20, 0.25, 0.05, -0.04, 0.03};

static double g_x[N_LONG][3];

/* n samples on a cap of half-angle theta_deg, rounded to float. */
static void gen_cap(uint64_t seed, size_t n, double theta_deg)
{
    tu_rng_t g;
    size_t i;
    tu_rng_seed(&g, seed);
    for (i = 0; i < n; i++) {
        int k;
        tu_sample_cap(&g, C0, R0, AXIS, theta_deg * TU_PI / 180.0, SIGMA, g_x[i]);
        for (k = 0; k < 3; k++) {
            g_x[i][k] = (double)(float)g_x[i][k];
        }
    }
}

/* A slow sweep: azimuth grows with the sample index (one turn over n),
 * polar angle random on the cap: the mean wanders by ~r. */
static void gen_sweep(uint64_t seed, size_t n, double theta_deg)
{
    tu_rng_t g;
    double nn[3], e1[3], e2[3];
    const double h = 1.0 - cos(theta_deg * TU_PI / 180.0);
    size_t i;
    tu_rng_seed(&g, seed);
    tu_frame(AXIS, nn, e1, e2);
    for (i = 0; i < n; i++) {
        const double z = 1.0 - h * tu_rng_uniform(&g);
        const double sp = sqrt(1.0 - z * z);
        const double phi = 2.0 * TU_PI * (double)i / (double)n;
        int k;
        for (k = 0; k < 3; k++) {
            g_x[i][k] = C0[k] + R0 * (z * nn[k] + sp * (cos(phi) * e1[k] + sin(phi) * e2[k]));
        }
        tu_add_noise(&g, SIGMA, g_x[i]);
        for (k = 0; k < 3; k++) {
            g_x[i][k] = (double)(float)g_x[i][k];
        }
    }
}

static sfit_vec3_t vec_of(const double x[3])
{
    sfit_vec3_t v;
    tc_to_vec3(x, &v);
    return v;
}

static sfit_incr_cfg_t cfg_of(const double *cov)
{
    sfit_incr_cfg_t c = sfit_incr_cfg_default;
    if (cov == COV_ISO) {
        c.noise = SFIT_NOISE_ISO;
        c.noise_var = (float)cov[0];
    } else if (cov != NULL) {
        float *m = c.noise_cov.m;
        c.noise = SFIT_NOISE_COV;
        m[0] = (float)cov[0]; m[4] = (float)cov[1]; m[8] = (float)cov[2];
        m[1] = m[3] = (float)cov[3];
        m[2] = m[6] = (float)cov[4];
        m[5] = m[7] = (float)cov[5];
    }
    return c;
}

/* Checkpoints: 1-2-5 series from 10, plus both sides of folds. */
static const size_t CHECKS[] = {10, 20, 50, 100, 200, 500, 1000, 1024, 1025, 2000, 4096, 4097,
                                5000, 10000, 20000, 50000, 65536, 65537, 100000, 200000,
                                500000, 1000000};
#define N_CHECKS (sizeof CHECKS / sizeof CHECKS[0])

/* ------------------------------------------------------------------ */
/* Double recursions against the double batch fit                     */

static void run_chapter(const double *cov, int printed, double theta, size_t n,
                        double *worst)
{
    ref_incr_chapter_t s;
    size_t i, k = 0;
    *worst = 0.0;
    gen_cap(11u, n, theta);
    assert_int_equal(ref_incr_chapter_start(&s, REF_C3(g_x), 10, cov, printed), 0);
    for (i = 10; i < n; i++) {
        ref_incr_chapter_add(&s, g_x[i]);
        while (k < N_CHECKS && CHECKS[k] < i + 1u) {
            k++;
        }
        if (k < N_CHECKS && CHECKS[k] == i + 1u) {
            ref_fit_t b;
            double c[3], r;
            assert_int_equal(ref_fit_sphere(REF_C3(g_x), i + 1u, cov, &b), 0);
            if (ref_incr_chapter_estimate(&s, c, &r) != 0) {
                *worst = 1e300; /* no estimate: fail */
                return;
            }
            if (tu_dist3(c, b.center) / R0 > *worst) {
                *worst = tu_dist3(c, b.center) / R0;
            }
            if (fabs(r - b.radius) / R0 > *worst) {
                *worst = fabs(r - b.radius) / R0;
            }
        }
    }
}

static void test_ref_chapter_matches_batch(void **state)
{
    const double thetas[] = {45.0, 90.0, 180.0};
    const double *covs[] = {NULL, COV_ISO, COV_FULL};
    size_t i, j;
    (void)state;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double worst;
            char what[64];
            run_chapter(covs[j], 0, thetas[i], 20000, &worst);
            snprintf(what, sizeof what, "chapter recursion, cap %.0f, noise model %u", thetas[i],
                     (unsigned)j);
            assert_near(worst, 0.0, 1e-9, what);
        }
    }
}

/* Eq. 229 as printed ('+' before the correction) is not the inverse of C. */
static void test_ref_chapter_printed_229_is_wrong(void **state)
{
    double worst;
    (void)state;
    run_chapter(NULL, 1, 90.0, 1000, &worst);
    assert_true(worst > 1e-3);
}

static void run_lib_ref(const double *cov, double theta, size_t n, size_t block, int sweep)
{
    ref_incr_lib_t s;
    size_t i, k = 0;
    if (sweep) {
        gen_sweep(12u, n, theta);
    } else {
        gen_cap(12u, n, theta);
    }
    ref_incr_lib_init(&s, cov, block);
    for (i = 0; i < n; i++) {
        ref_incr_lib_add(&s, g_x[i]);
        while (k < N_CHECKS && CHECKS[k] < i + 1u) {
            k++;
        }
        if (k < N_CHECKS && CHECKS[k] == i + 1u) {
            ref_fit_t b;
            double c[3], r;
            assert_int_equal(ref_fit_sphere(REF_C3(g_x), i + 1u, cov, &b), 0);
            assert_int_equal(ref_incr_lib_estimate(&s, c, &r), 0);
            assert_near(tu_dist3(c, b.center) / R0, 0.0, 1e-9, "library form (double), centre");
            assert_near((r - b.radius) / R0, 0.0, 1e-9, "library form (double), radius");
        }
    }
}

static void test_ref_lib_form_matches_batch(void **state)
{
    (void)state;
    run_lib_ref(NULL, 45.0, 20000, 1024, 0);
    run_lib_ref(COV_ISO, 90.0, 20000, 1024, 0);
    run_lib_ref(COV_FULL, 180.0, 20000, 1024, 0);
    run_lib_ref(NULL, 60.0, 20000, 3, 1);     /* a rebase every 3 samples */
    run_lib_ref(COV_FULL, 60.0, 20000, 5, 1);
}

/* ------------------------------------------------------------------ */
/* Float library against the double batch fit                          */

typedef struct {
    double worst_c, worst_r;
    size_t at;
    double batch_c; /* GDKE only: worst centre error of the float batch path */
} worst_t;

/* Run GDKE, UGDK (iso) and UGDK (full) (only GDKE when models == 1) on
 * g_x[0..n-1]; compare at every checkpoint >= from with the batch reference. */
static void run_float(size_t n, size_t from, double tol, int models, worst_t w[3],
                      const char *label)
{
    const double *covs[3] = {NULL, COV_ISO, COV_FULL};
    sfit_incr_t s[3];
    sfit_moments_t mom; /* the batch float path, for comparison (info only) */
    size_t i, k = 0;
    int j;
    memset(w, 0, 3 * sizeof w[0]);
    (void)sfit_moments_init(&mom);
    for (j = 0; j < models; j++) {
        const sfit_incr_cfg_t cfg = cfg_of(covs[j]);
        assert_int_equal(sfit_incr_init(&s[j], &cfg), SFIT_OK);
        memset(&w[j], 0, sizeof w[j]);
    }
    for (i = 0; i < n; i++) {
        const sfit_vec3_t x = vec_of(g_x[i]);
        for (j = 0; j < models; j++) {
            assert_int_equal(sfit_incr_add(&s[j], &x), SFIT_OK);
        }
        assert_int_equal(sfit_moments_add(&mom, &x), SFIT_OK);
        while (k < N_CHECKS && CHECKS[k] < i + 1u) {
            k++;
        }
        if (k < N_CHECKS && CHECKS[k] == i + 1u && i + 1u >= from) {
            for (j = 0; j < models; j++) {
                ref_fit_t b;
                sfit_sphere_t e;
                double ec, er;
                char what[96];
                assert_int_equal(ref_fit_sphere(REF_C3(g_x), i + 1u, covs[j], &b), 0);
                assert_int_equal(sfit_incr_fit(&s[j], &e), SFIT_OK);
                assert_int_equal(e.n, (uint32_t)(i + 1u));
                ec = tc_dist(&e.center, b.center) / R0;
                er = fabs((double)e.radius - b.radius) / R0;
                snprintf(what, sizeof what, "%s, noise model %d, n = %lu, centre / r", label, j,
                         (unsigned long)(i + 1u));
                assert_near(ec, 0.0, tol, what);
                snprintf(what, sizeof what, "%s, noise model %d, n = %lu, radius / r", label, j,
                         (unsigned long)(i + 1u));
                assert_near(er, 0.0, tol, what);
                if (ec > w[j].worst_c) {
                    w[j].worst_c = ec;
                    w[j].at = i + 1u;
                }
                if (er > w[j].worst_r) {
                    w[j].worst_r = er;
                }
                if (j == 0) {
                    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
                    sfit_result_t fr;
                    cfg.mode = SFIT_MODE_SPHERE;
                    if (sfit_fit_moments(&mom, &cfg, &fr) == SFIT_OK
                        && tc_dist(&fr.center, b.center) / R0 > w[0].batch_c) {
                        w[0].batch_c = tc_dist(&fr.center, b.center) / R0;
                    }
                }
            }
        }
    }
}

/* GDKE on 45, 90, 135 and 180 degree caps; UGDK (isotropic and full
 * noise covariance) on the two extremes (the batch reference dominates
 * the run time). */
static void test_float_matches_batch_1e6(void **state)
{
    const double thetas[] = {45.0, 90.0, 135.0, 180.0};
    size_t i;
    (void)state;
    for (i = 0; i < 4; i++) {
        worst_t w[3];
        char label[48];
        const int models = (i == 0 || i == 3) ? 3 : 1;
        int j;
        gen_cap(100u + i, N_LONG, thetas[i]);
        snprintf(label, sizeof label, "cap %.0f deg", thetas[i]);
        run_float(N_LONG, 10, 1e-4, models, w, label);
        for (j = 0; j < models; j++) {
            print_message("[ info     ] %s, noise model %d: worst centre %.2e r (n = %lu), "
                          "worst radius %.2e r\n",
                          label, j, w[j].worst_c, (unsigned long)w[j].at, w[j].worst_r);
        }
        print_message("[ info     ] %s, batch float path (moments + fit_solve): worst "
                      "centre %.2e r\n", label, w[0].batch_c);
    }
}

/* Why the library does not run the chapter's recursion: eq. 224-230 (with
 * the corrected eq. 229) in float, even in a frame shifted to the first
 * sample (so the 2700 mm offset never enters), drift by eps sqrt(N)
 * amplified by cond(C) |c - m| / r. Test-only code, a literal transcription. */
typedef struct {
    float o[3], d[3], C[3][3], Ci[3][3], S[3];
    float n;
} chapter_f_t;

static void chapter_f_start(chapter_f_t *s, size_t n0)
{
    float y[3], q, det, c[3][3];
    size_t k;
    int i, j;
    memset(s, 0, sizeof *s);
    for (i = 0; i < 3; i++) {
        s->o[i] = (float)g_x[0][i];
    }
    for (k = 0; k < n0; k++) {
        for (i = 0; i < 3; i++) {
            s->d[i] += ((float)g_x[k][i] - s->o[i]) / (float)n0;
        }
    }
    for (k = 0; k < n0; k++) {
        for (i = 0; i < 3; i++) {
            y[i] = ((float)g_x[k][i] - s->o[i]) - s->d[i];
        }
        q = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
        for (i = 0; i < 3; i++) {
            s->S[i] += q * y[i] / (float)(n0 - 1u);
            for (j = 0; j < 3; j++) {
                s->C[i][j] += y[i] * y[j] / (float)(n0 - 1u);
            }
        }
    }
    for (i = 0; i < 3; i++) { /* cofactors (symmetric) */
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (j = 0; j < 3; j++) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            c[i][j] = s->C[i1][j1] * s->C[i2][j2] - s->C[i1][j2] * s->C[i2][j1];
        }
    }
    det = s->C[0][0] * c[0][0] + s->C[0][1] * c[0][1] + s->C[0][2] * c[0][2];
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            s->Ci[i][j] = c[j][i] / det;
        }
    }
    s->n = (float)n0;
}

static void chapter_f_add(chapter_f_t *s, const double xd[3])
{
    const float n = s->n, a = (n - 1.0f) / n, b = (n + 1.0f) / (n * n);
    float e[3], dl[3], u[3], k, tr, g, v[3];
    int i, j;
    for (i = 0; i < 3; i++) {
        e[i] = ((float)xd[i] - s->o[i]) - s->d[i];
        s->d[i] += e[i] / (n + 1.0f);       /* eq. 224 */
        dl[i] = n / (n + 1.0f) * e[i];      /* eq. 225/226 */
    }
    for (i = 0; i < 3; i++) {
        u[i] = s->Ci[i][0] * dl[0] + s->Ci[i][1] * dl[1] + s->Ci[i][2] * dl[2];
    }
    k = n * (n - 1.0f) / (n + 1.0f) + (dl[0] * u[0] + dl[1] * u[1] + dl[2] * u[2]);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            s->Ci[i][j] = n / (n - 1.0f) * (s->Ci[i][j] - u[i] * u[j] / k); /* eq. 229 */
            s->C[i][j] = a * s->C[i][j] + b * dl[i] * dl[j];                /* eq. 227 */
        }
    }
    tr = s->C[0][0] + s->C[1][1] + s->C[2][2];
    g = (n + 1.0f) * (n + 2.0f) / (n * n) * (dl[0] * dl[0] + dl[1] * dl[1] + dl[2] * dl[2]);
    for (i = 0; i < 3; i++) {
        v[i] = -2.0f * (s->C[i][0] * dl[0] + s->C[i][1] * dl[1] + s->C[i][2] * dl[2])
               + (g - tr) * dl[i];
    }
    for (i = 0; i < 3; i++) {
        s->S[i] = a * s->S[i] + v[i] / n;   /* eq. 230 */
    }
    s->n = n + 1.0f;
}

static double chapter_f_err(const chapter_f_t *s, const ref_fit_t *b)
{
    double c[3];
    int i;
    for (i = 0; i < 3; i++) { /* eq. 231 */
        const float w = 0.5f * (s->Ci[i][0] * s->S[0] + s->Ci[i][1] * s->S[1]
                                + s->Ci[i][2] * s->S[2]);
        c[i] = (double)(s->o[i] + (s->d[i] + w));
    }
    return tu_dist3(c, b->center) / R0;
}

static void test_chapter_recursion_drifts_in_float(void **state)
{
    chapter_f_t s;
    ref_fit_t b;
    double e5 = 0.0, e6;
    size_t i;
    (void)state;
    gen_cap(100u, N_LONG, 45.0);
    chapter_f_start(&s, 10);
    for (i = 10; i < N_LONG; i++) {
        chapter_f_add(&s, g_x[i]);
        if (i + 1u == 100000u) {
            assert_int_equal(ref_fit_sphere(REF_C3(g_x), i + 1u, NULL, &b), 0);
            e5 = chapter_f_err(&s, &b);
        }
    }
    assert_int_equal(ref_fit_sphere(REF_C3(g_x), N_LONG, NULL, &b), 0);
    e6 = chapter_f_err(&s, &b);
    print_message("[ info     ] chapter recursion in float, 45 deg cap: %.2e r at 1e5, "
                  "%.2e r at 1e6\n", e5, e6);
    assert_true(e6 > 1e-4); /* fails the requirement the library meets */
}

/* The mean wanders by ~r over the run (a slow sweep): the frame must
 * follow it. Before ~1000 samples the samples form a thin sliver whose
 * batch fit is itself ill-conditioned in float, so the check starts there. */
static void test_float_sweep(void **state)
{
    worst_t w[3];
    (void)state;
    gen_sweep(7u, 200000u, 90.0);
    run_float(200000u, 1000u, 1e-4, 3, w, "sweep 90 deg");
    print_message("[ info     ] sweep: worst centre %.2e r (GDKE), %.2e r (UGDK iso); "
                  "batch float path %.2e r\n", w[0].worst_c, w[1].worst_c, w[0].batch_c);
}

/* Exact points on a sphere: the centre and radius come back to float
 * rounding of the samples (ulp(2693)/2 = 1.2e-4 mm = 1.2e-6 r). */
static void test_exact_sphere(void **state)
{
    static const double dirs[14][3] = {
        {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
        {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1},
        {-1, -1, 1}, {-1, -1, -1}};
    sfit_incr_t s;
    sfit_sphere_t e;
    double x[3];
    int i, k;
    (void)state;
    assert_int_equal(sfit_incr_init(&s, NULL), SFIT_OK);
    for (i = 0; i < 14; i++) {
        const double len = tu_norm3(dirs[i]);
        sfit_vec3_t v;
        for (k = 0; k < 3; k++) {
            x[k] = C0[k] + R0 * dirs[i][k] / len;
        }
        v = vec_of(x);
        assert_int_equal(sfit_incr_add(&s, &v), SFIT_OK);
    }
    assert_int_equal(sfit_incr_fit(&s, &e), SFIT_OK);
    assert_vec3_near(e.center.v, C0, 1e-5 * R0, "exact sphere centre");
    assert_near(e.radius, R0, 1e-5 * R0, "exact sphere radius");
    assert_int_equal(e.n, 14);
}

/* ------------------------------------------------------------------ */
/* Error handling                                                      */

static void fill_cap(sfit_vec3_t *v, size_t n, uint64_t seed)
{
    size_t i;
    gen_cap(seed, n, 90.0);
    for (i = 0; i < n; i++) {
        v[i] = vec_of(g_x[i]);
    }
}

static void test_args(void **state)
{
    sfit_incr_t s;
    sfit_sphere_t e;
    sfit_vec3_t x = {{1.0f, 2.0f, 3.0f}};
    sfit_incr_cfg_t cfg;
    (void)state;
    assert_int_equal(sfit_incr_init(NULL, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_init(&s, NULL), SFIT_OK);
    assert_int_equal(sfit_incr_reset(NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_add(NULL, &x), SFIT_E_ARG);
    assert_int_equal(sfit_incr_add(&s, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_fit(NULL, &e), SFIT_E_ARG);
    assert_int_equal(sfit_incr_fit(&s, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_update(&s, &x, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_update(NULL, &x, &e), SFIT_E_ARG);
    assert_int_equal(sfit_incr_start(NULL, &x, 1, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_start(&s, NULL, 5, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_incr_count(NULL), 0u);
    assert_int_equal(sfit_incr_count(&s), 0u);

    /* Invalid options leave the state untouched. */
    {
        sfit_incr_t before;
        assert_int_equal(sfit_incr_add(&s, &x), SFIT_OK);
        memcpy(&before, &s, sizeof s);
        cfg = sfit_incr_cfg_default;
        cfg.noise = SFIT_NOISE_ISO;
        cfg.noise_var = -1.0f;
        assert_int_equal(sfit_incr_init(&s, &cfg), SFIT_E_ARG);
        cfg.noise_var = NAN;
        assert_int_equal(sfit_incr_init(&s, &cfg), SFIT_E_ARG);
        cfg = sfit_incr_cfg_default;
        cfg.noise = (sfit_noise_kind_t)7;
        assert_int_equal(sfit_incr_init(&s, &cfg), SFIT_E_ARG);
        assert_memory_equal(&before, &s, sizeof s);
    }
}

static void test_too_few(void **state)
{
    sfit_incr_t s;
    sfit_sphere_t e, sentinel;
    sfit_vec3_t v[4];
    int i;
    (void)state;
    fill_cap(v, 4, 3u);
    memset(&sentinel, 0xA5, sizeof sentinel);
    assert_int_equal(sfit_incr_init(&s, NULL), SFIT_OK);
    for (i = 0; i < 4; i++) {
        e = sentinel;
        assert_int_equal(sfit_incr_fit(&s, &e), SFIT_E_TOO_FEW);
        assert_memory_equal(&e, &sentinel, sizeof e);
        /* update keeps a valid sample even when it cannot solve yet */
        assert_int_equal(sfit_incr_update(&s, &v[i], &e),
                         i < 3 ? SFIT_E_TOO_FEW : SFIT_OK);
        assert_int_equal(sfit_incr_count(&s), (uint32_t)(i + 1));
    }
    assert_int_equal(sfit_incr_start(&s, v, 3, &e), SFIT_E_TOO_FEW);
}

/* A rejected sample leaves the state bit for bit unchanged, at any point
 * (empty, early, the sample before a fold). */
static void test_reject_sample(void **state)
{
    static const size_t at[] = {0, 1, 5, SFIT_INCR_BLOCK - 1u, 2u * SFIT_INCR_BLOCK - 1u};
    const float bad[4] = {NAN, INFINITY, -INFINITY, 2.0e9f};
    const sfit_status_t why[4] = {SFIT_E_NONFINITE, SFIT_E_NONFINITE, SFIT_E_NONFINITE,
                                  SFIT_E_RANGE};
    static sfit_vec3_t v[2 * SFIT_INCR_BLOCK];
    sfit_incr_t s, before;
    sfit_sphere_t e;
    size_t a, i;
    int b, k;
    (void)state;
    fill_cap(v, 2 * SFIT_INCR_BLOCK, 5u);
    for (a = 0; a < sizeof at / sizeof at[0]; a++) {
        assert_int_equal(sfit_incr_init(&s, NULL), SFIT_OK);
        for (i = 0; i < at[a]; i++) {
            assert_int_equal(sfit_incr_add(&s, &v[i]), SFIT_OK);
        }
        memcpy(&before, &s, sizeof s);
        for (b = 0; b < 4; b++) {
            for (k = 0; k < 3; k++) {
                sfit_vec3_t x = v[at[a]];
                x.v[k] = bad[b];
                assert_int_equal(sfit_incr_add(&s, &x), why[b]);
                assert_int_equal(sfit_incr_update(&s, &x, &e), why[b]);
                assert_memory_equal(&before, &s, sizeof s);
            }
        }
    }
    /* A full counter. */
    memcpy(&before, &s, sizeof s);
    s.n = UINT32_MAX;
    memcpy(&before, &s, sizeof s);
    assert_int_equal(sfit_incr_add(&s, &v[0]), SFIT_E_RANGE);
    assert_memory_equal(&before, &s, sizeof s);
}

static void test_degenerate(void **state)
{
    sfit_incr_t s, before;
    sfit_sphere_t e;
    sfit_vec3_t v[40];
    sfit_incr_cfg_t cfg = cfg_of(COV_ISO);
    int i, kind;
    (void)state;
    for (kind = 0; kind < 3; kind++) {
        for (i = 0; i < 40; i++) {
            const double t = 0.05 * (double)i;
            double x[3];
            if (kind == 0) { /* coincident */
                x[0] = C0[0]; x[1] = C0[1]; x[2] = C0[2];
            } else if (kind == 1) { /* collinear */
                x[0] = C0[0] + 30.0 * t; x[1] = C0[1] - 20.0 * t; x[2] = C0[2] + 10.0 * t;
            } else { /* planar: a circle in the plane z = const */
                x[0] = C0[0] + R0 * cos(t * 3.0); x[1] = C0[1] + R0 * sin(t * 3.0); x[2] = C0[2];
            }
            v[i] = vec_of(x);
        }
        /* GDKE and UGDK alike: the geometry, not the noise model, fails. */
        assert_int_equal(sfit_incr_init(&s, NULL), SFIT_OK);
        for (i = 0; i < 40; i++) {
            assert_int_equal(sfit_incr_add(&s, &v[i]), SFIT_OK);
        }
        assert_int_equal(sfit_incr_fit(&s, &e), SFIT_E_DEGENERATE);
        assert_int_equal(sfit_incr_init(&s, &cfg), SFIT_OK);
        for (i = 0; i < 40; i++) {
            assert_int_equal(sfit_incr_add(&s, &v[i]), SFIT_OK);
        }
        assert_int_equal(sfit_incr_fit(&s, &e), SFIT_E_DEGENERATE);
        /* A degenerate start leaves the state as it was. */
        memcpy(&before, &s, sizeof s);
        assert_int_equal(sfit_incr_start(&s, v, 40, &e), SFIT_E_DEGENERATE);
        assert_memory_equal(&before, &s, sizeof s);
    }
}

/* A spread too small for float (SFIT_MIN_SPREAD): the third moments' cubes
 * lose their digits. sfit_fit_moments() refuses such samples; the
 * incremental fit returned a centre 2.8e-3 r off (radius 1e-14 at the
 * origin, exact samples) with SFIT_OK. A small sphere above the limit
 * still fits (radius 1e-6: within 1e-4 r). */
static void test_tiny_spread(void **state)
{
    static const double c0[3] = {0.0, 0.0, 0.0}, ax[3] = {0.0, 0.6, 0.8};
    sfit_vec3_t v[60];
    sfit_incr_t s;
    sfit_sphere_t e, sentinel;
    sfit_moments_t m;
    sfit_result_t r;
    tu_rng_t g;
    int i, k;
    (void)state;
    memset(&sentinel, 0xA5, sizeof sentinel);
    for (k = 0; k < 2; k++) {
        const double rad = (k == 0) ? 1e-14 : 1e-6;
        tu_rng_seed(&g, 71u);
        for (i = 0; i < 60; i++) {
            double x[3];
            tu_sample_cap(&g, c0, rad, ax, 1.2, 0.0, x);
            v[i] = vec_of(x);
        }
        (void)sfit_moments_init(&m);
        assert_int_equal(sfit_moments_add_block(&m, v, 60, NULL), SFIT_OK);
        assert_int_equal(sfit_incr_init(&s, NULL), SFIT_OK);
        for (i = 0; i < 60; i++) {
            assert_int_equal(sfit_incr_add(&s, &v[i]), SFIT_OK);
        }
        e = sentinel;
        if (k == 0) {
            assert_int_equal(sfit_fit_moments(&m, NULL, &r), SFIT_E_DEGENERATE);
            assert_int_equal(sfit_incr_fit(&s, &e), SFIT_E_DEGENERATE);
            assert_memory_equal(&e, &sentinel, sizeof e);
        } else {
            assert_int_equal(sfit_fit_moments(&m, NULL, &r), SFIT_OK);
            assert_int_equal(sfit_incr_fit(&s, &e), SFIT_OK);
            assert_true(tc_dist(&e.center, c0) < 1e-4 * rad);
        }
    }
}

static void test_ugdk_not_posdef(void **state)
{
    sfit_incr_t s, before;
    sfit_sphere_t e;
    sfit_vec3_t v[50];
    sfit_incr_cfg_t cfg = sfit_incr_cfg_default;
    int i;
    (void)state;
    fill_cap(v, 50, 9u);
    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = 1.0e4f; /* sigma = r: larger than the spread */
    assert_int_equal(sfit_incr_init(&s, &cfg), SFIT_OK);
    for (i = 0; i < 50; i++) {
        assert_int_equal(sfit_incr_add(&s, &v[i]), SFIT_OK);
    }
    assert_int_equal(sfit_incr_fit(&s, &e), SFIT_E_NOT_POSDEF);
    memcpy(&before, &s, sizeof s);
    assert_int_equal(sfit_incr_start(&s, v, 50, &e), SFIT_E_NOT_POSDEF);
    assert_memory_equal(&before, &s, sizeof s);
}

/* start = batch of the first samples, then per-sample updates; equals the
 * batch reference. start rejects a bad sample without touching the state;
 * reset keeps the noise model. */
static void test_start_update_reset(void **state)
{
    static sfit_vec3_t v[3000];
    const sfit_incr_cfg_t cfg = cfg_of(COV_ISO);
    sfit_incr_t s, fresh, before;
    sfit_sphere_t e, e2;
    ref_fit_t b;
    size_t i;
    (void)state;
    fill_cap(v, 3000, 21u);
    assert_int_equal(sfit_incr_init(&s, &cfg), SFIT_OK);
    assert_int_equal(sfit_incr_start(&s, v, 8, &e), SFIT_OK);
    assert_int_equal(e.n, 8u);
    assert_int_equal(ref_fit_sphere(REF_C3(g_x), 8, COV_ISO, &b), 0);
    assert_near(tc_dist(&e.center, b.center) / R0, 0.0, 1e-4, "start centre");
    for (i = 8; i < 3000; i++) {
        assert_int_equal(sfit_incr_update(&s, &v[i], &e), SFIT_OK);
    }
    assert_int_equal(ref_fit_sphere(REF_C3(g_x), 3000, COV_ISO, &b), 0);
    assert_near(tc_dist(&e.center, b.center) / R0, 0.0, 1e-4, "after updates, centre");
    assert_near(((double)e.radius - b.radius) / R0, 0.0, 1e-4, "after updates, radius");

    /* start with a NaN inside: rejected, state unchanged */
    memcpy(&before, &s, sizeof s);
    v[3].v[1] = NAN;
    assert_int_equal(sfit_incr_start(&s, v, 10, &e), SFIT_E_NONFINITE);
    assert_memory_equal(&before, &s, sizeof s);
    v[3] = vec_of(g_x[3]);

    /* restart replaces the samples */
    assert_int_equal(sfit_incr_start(&s, v, 100, &e), SFIT_OK);
    assert_int_equal(sfit_incr_count(&s), 100u);

    /* reset keeps UGDK: same estimate as a fresh UGDK state */
    assert_int_equal(sfit_incr_reset(&s), SFIT_OK);
    assert_int_equal(sfit_incr_count(&s), 0u);
    assert_int_equal(sfit_incr_init(&fresh, &cfg), SFIT_OK);
    for (i = 0; i < 100; i++) {
        assert_int_equal(sfit_incr_add(&s, &v[i]), SFIT_OK);
        assert_int_equal(sfit_incr_add(&fresh, &v[i]), SFIT_OK);
    }
    assert_int_equal(sfit_incr_fit(&s, &e), SFIT_OK);
    assert_int_equal(sfit_incr_fit(&fresh, &e2), SFIT_OK);
    assert_memory_equal(&e, &e2, sizeof e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ref_chapter_matches_batch),
        cmocka_unit_test(test_ref_chapter_printed_229_is_wrong),
        cmocka_unit_test(test_ref_lib_form_matches_batch),
        cmocka_unit_test(test_float_matches_batch_1e6),
        cmocka_unit_test(test_chapter_recursion_drifts_in_float),
        cmocka_unit_test(test_float_sweep),
        cmocka_unit_test(test_exact_sphere),
        cmocka_unit_test(test_args),
        cmocka_unit_test(test_too_few),
        cmocka_unit_test(test_reject_sample),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_tiny_spread),
        cmocka_unit_test(test_ugdk_not_posdef),
        cmocka_unit_test(test_start_update_reset),
    };
    return cmocka_run_group_tests_name("incr", tests, NULL, NULL);
}
