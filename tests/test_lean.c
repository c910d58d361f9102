/* SPDX-License-Identifier: MIT */
/**
 * @file test_lean.c
 * @brief The screened solve (the default, cfg.eigen = false) against the full
 * solver (cfg.eigen = true) and the double reference: random cases and sweeps
 * across each threshold of the screen (planar ratio, trust, collinear,
 * coincident). Wherever the screen passes, the result must be the full
 * solver's sphere bit for bit with the same status, flags, mode and method,
 * and a trust bound not below the exact ratio; the double reference must
 * agree that the fit is neither near-planar nor untrusted.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit_ref.h"

#define NMAX 2000
static double g_pts[NMAX][3];
static sfit_vec3_t g_fpts[NMAX];

static const double k_center[3] = {2100.0, -1500.0, 900.0}; /* |c| = 2731 mm */
static const double k_axis[3] = {0.267261241912424, 0.534522483824849, 0.801783725737273};

/* Cases where the screen passed / tripped, over a whole test. */
static int g_lean, g_full;

/* n cap samples; the component along the cap axis (about the cap's mean
 * height) is scaled by squash, which sets lambda_min(C). g_pts holds the
 * float values exactly. */
static void make_cap(tu_rng_t *g, size_t n, double r, double theta, double sigma,
                     double squash)
{
    double n0[3], e1[3], e2[3];
    const double h = r * (1.0 + cos(theta)) / 2.0; /* mean height of the cap */
    size_t i;
    int k;
    tu_frame(k_axis, n0, e1, e2);
    for (i = 0; i < n; i++) {
        double p[3], a;
        tu_sample_cap(g, k_center, r, k_axis, theta, sigma, p);
        a = 0.0;
        for (k = 0; k < 3; k++) {
            a += (p[k] - k_center[k]) * n0[k];
        }
        for (k = 0; k < 3; k++) {
            p[k] -= (1.0 - squash) * (a - h) * n0[k];
        }
        tc_to_vec3(p, &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
}

/* Both paths on the first n samples; every agreement the screen promises.
 * Returns 1 when the screened path was used. */
static int compare(size_t n, const sfit_fit_cfg_t *cfg)
{
    sfit_fit_cfg_t cs = *cfg, ce = *cfg;
    sfit_result_t rs, re;
    sfit_status_t ss, se;
    cs.eigen = false;
    ce.eigen = true;
    memset(&rs, 0, sizeof rs);
    memset(&re, 0, sizeof re);
    ss = sfit_fit_points(g_fpts, n, &cs, &rs);
    se = sfit_fit_points(g_fpts, n, &ce, &re);
    assert_int_equal(ss, se);
    if (ss != SFIT_OK) {
        g_full++;
        return 0;
    }
    assert_int_equal(re.exact, 1);
    assert_int_equal(rs.flags, re.flags);
    assert_int_equal(rs.mode, re.mode);
    assert_int_equal(rs.method, re.method);
    assert_int_equal(rs.n, re.n);
    assert_memory_equal(rs.center.v, re.center.v, sizeof rs.center.v);
    assert_true(rs.radius == re.radius);
    if (rs.exact) {
        /* The full solver ran on the default path as well: identical. */
        assert_memory_equal(&rs, &re, sizeof rs);
        g_full++;
        return 0;
    }
    /* Screened: a trusted, not near-planar sphere; the bound covers the
     * exact ratio. */
    assert_int_equal(rs.mode, SFIT_MODE_SPHERE);
    assert_true((rs.flags & (uint32_t)(SFIT_FLAG_NEAR_PLANAR | SFIT_FLAG_UNTRUSTED)) == 0u);
    assert_true(rs.leontief_ratio >= re.leontief_ratio);
    assert_true(rs.leontief_ratio < 1.0f);
    assert_true(rs.trust_ratio >= re.trust_ratio);
    {
        /* Double reference: eigenvalues of C, the exact trust ratio. */
        const float ratio = (cfg->planar_ratio > 0.0f) ? cfg->planar_ratio : SFIT_PLANAR_RATIO;
        double mean[3], c[3][3], s[3], w[3], v[3][3];
        assert_int_equal(ref_moments(REF_C3(g_pts), n, mean, c, s), 0);
        ref_sym3_eig(REF_C3(c), w, v);
        assert_true(w[0] >= (double)ratio * w[2]);
        assert_true(w[1] > (double)SFIT_COLLINEAR_RATIO * w[2]);
        if (cfg->noise == SFIT_NOISE_ISO) {
            const double var = (double)cfg->noise_var;
            assert_true(w[0] - var > 0.0);
            assert_true(var / (w[0] - var) < 1.0);
            assert_true((double)rs.leontief_ratio >= (var / (w[0] - var)) * (1.0 - 1e-3));
            /* The planar decision on C' as well (lambda_min(C') / lambda_max(C')). */
            assert_true(w[0] - var >= (double)ratio * (w[2] - var));
        }
    }
    g_lean++;
    return 1;
}

static sfit_fit_cfg_t cfg_of(sfit_mode_t mode, float var, float ratio)
{
    sfit_fit_cfg_t c = sfit_fit_cfg_default;
    c.mode = mode;
    c.planar_ratio = ratio;
    if (var > 0.0f) {
        c.noise = SFIT_NOISE_ISO;
        c.noise_var = var;
    }
    return c;
}

/* The default path is the screened one, and the result says so. */
static void test_default_is_screened(void **state)
{
    tu_rng_t g;
    sfit_result_t r;
    (void)state;
    tu_rng_seed(&g, 1601);
    make_cap(&g, 500, 100.0, 60.0 * TU_PI / 180.0, 0.5, 1.0);
    assert_int_equal(sfit_fit_points(g_fpts, 500, NULL, &r), SFIT_OK);
    assert_int_equal(r.exact, 0);
    assert_true(r.eigenvalues.v[0] == 0.0f && r.axis.v[0] == 0.0f);
    {
        const sfit_fit_cfg_t c = cfg_of(SFIT_MODE_AUTO, 0.25f, 0.0f);
        assert_int_equal(compare(500, &c), 1);
    }
    {
        /* eigen is a bool: a byte other than 0/1 in it (garbage RAM) is
         * refused, read as a byte (sfit_types.h, "Yes/no") */
        static const unsigned bytes[] = {2u, 0x80u, 0xFFu};
        size_t k;
        assert_int_equal(sizeof(bool), 1); /* the byte sfit_i_bool_byte reads is all of it */
        for (k = 0; k < sizeof bytes / sizeof bytes[0]; k++) {
            sfit_fit_cfg_t c = sfit_fit_cfg_default;
            tu_set_byte(&c.eigen, bytes[k]);
            assert_int_equal(sfit_fit_points(g_fpts, 500, &c, &r), SFIT_E_ARG);
        }
    }
}

/* Random caps, noise levels, offsets and thresholds. */
static void test_random_cases(void **state)
{
    static const float ratios[] = {0.0f, 1e-6f, 1e-3f, 2e-2f, 0.2f};
    tu_rng_t g;
    int t;
    (void)state;
    g_lean = g_full = 0;
    tu_rng_seed(&g, 1602);
    for (t = 0; t < 3000; t++) {
        const size_t n = 4u + (size_t)(tu_rng_uniform(&g) * 400.0);
        const double theta = (3.0 + 177.0 * tu_rng_uniform(&g)) * TU_PI / 180.0;
        const double r = 10.0 + 200.0 * tu_rng_uniform(&g);
        const double sigma = r * 0.05 * tu_rng_uniform(&g) * tu_rng_uniform(&g);
        const double squash = (tu_rng_uniform(&g) < 0.3) ? tu_rng_uniform(&g) : 1.0;
        const float ratio = ratios[(size_t)(tu_rng_uniform(&g) * 5.0) % 5u];
        const sfit_mode_t mode = (tu_rng_uniform(&g) < 0.5) ? SFIT_MODE_AUTO : SFIT_MODE_SPHERE;
        /* noise model: none, the true level, or up to 3x it */
        const double u = tu_rng_uniform(&g);
        const float var = (u < 0.3) ? 0.0f : (float)(sigma * sigma * 3.0 * tu_rng_uniform(&g));
        sfit_fit_cfg_t c = cfg_of(mode, var, ratio);
        make_cap(&g, n, r, theta, sigma, squash);
        (void)compare(n, &c);
    }
    print_message("random: %d screened, %d full solver\n", g_lean, g_full);
    assert_true(g_lean > 1000);
    assert_true(g_full > 300);
}

/* The planar threshold: lambda_min/lambda_max swept across planar_ratio by
 * squashing a cap; close to the threshold the screen must trip, far above
 * it the screen must pass. */
static void test_planar_boundary(void **state)
{
    static const float ratios[] = {0.0f, 2e-2f};
    tu_rng_t g;
    size_t k;
    int i, passed_far = 0, tripped_near = 0, near = 0;
    (void)state;
    g_lean = g_full = 0;
    for (k = 0; k < 2; k++) {
        const double ratio = (ratios[k] > 0.0f) ? (double)ratios[k] : (double)SFIT_PLANAR_RATIO;
        for (i = 0; i < 120; i++) {
            /* target lambda ratio from ratio/3 to 30 ratio (log steps) */
            const double q = ratio * pow(90.0, (double)i / 119.0) / 3.0;
            double mean[3], c[3][3], s[3], w[3], v[3][3], sq;
            sfit_fit_cfg_t cf;
            int used;
            tu_rng_seed(&g, 1603u + (uint64_t)i);
            make_cap(&g, 600, 100.0, 70.0 * TU_PI / 180.0, 0.0, 1.0);
            assert_int_equal(ref_moments(REF_C3(g_pts), 600, mean, c, s), 0);
            ref_sym3_eig(REF_C3(c), w, v);
            sq = sqrt(q * w[2] / w[0]); /* lambda_min scales with squash^2 */
            tu_rng_seed(&g, 1603u + (uint64_t)i);
            make_cap(&g, 600, 100.0, 70.0 * TU_PI / 180.0, 0.0, sq);
            cf = cfg_of((i % 2) ? SFIT_MODE_AUTO : SFIT_MODE_SPHERE, 0.0f, ratios[k]);
            used = compare(600, &cf);
            if (q > 4.0 * ratio && used) {
                passed_far++;
            }
            if (q < 1.02 * ratio) {
                near++;
                tripped_near += !used;
            }
            assert_true(!(used && q < ratio));
        }
    }
    print_message("planar sweep: %d screened, %d full; far passed %d, near tripped %d\n",
                  g_lean, g_full, passed_far, tripped_near);
    assert_true(passed_far >= 80);
    assert_true(near >= 50);
    assert_int_equal(tripped_near, near);
}

/* The trust threshold: sigma^2 swept across lambda_min(C)/2 (Leontief
 * ratio 1) on a cap; the screen must trip at and above the threshold and
 * pass well below it. */
static void test_trust_boundary(void **state)
{
    tu_rng_t g;
    double mean[3], c[3][3], s[3], w[3], v[3][3];
    int i, passed_far = 0;
    (void)state;
    g_lean = g_full = 0;
    tu_rng_seed(&g, 1604);
    make_cap(&g, 1000, 100.0, 40.0 * TU_PI / 180.0, 1.0, 1.0);
    assert_int_equal(ref_moments(REF_C3(g_pts), 1000, mean, c, s), 0);
    ref_sym3_eig(REF_C3(c), w, v);
    for (i = 0; i < 200; i++) {
        /* var / lambda_min(C) from 0.05 to 0.65 */
        const double f = 0.05 + 0.6 * (double)i / 199.0;
        const float var = (float)(f * w[0]);
        const sfit_fit_cfg_t cf = cfg_of(SFIT_MODE_AUTO, var, 0.0f);
        const int used = compare(1000, &cf);
        const double rho = (double)var / (w[0] - (double)var); /* Leontief ratio */
        assert_true(!(used && rho >= 1.0));
        if (rho < 0.5 && used) {
            passed_far++;
        }
        if (rho >= 0.97) {
            assert_false(used);
        }
    }
    print_message("trust sweep: %d screened, %d full; passed below rho 0.5: %d\n", g_lean,
                  g_full, passed_far);
    assert_true(passed_far >= 60);
}

/* Collinear, coincident and too-few samples: the full solver's statuses. */
static void test_degenerate_statuses(void **state)
{
    const sfit_fit_cfg_t cf = cfg_of(SFIT_MODE_AUTO, 0.0f, 0.0f);
    size_t i;
    (void)state;
    for (i = 0; i < 50; i++) { /* coincident */
        g_fpts[i].v[0] = 2100.0f;
        g_fpts[i].v[1] = -1500.0f;
        g_fpts[i].v[2] = 900.0f;
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
    g_fpts[7].v[0] = nextafterf(2100.0f, 3000.0f); /* one ulp of spread */
    tc_to_double3(&g_fpts[7], g_pts[7]);
    assert_int_equal(compare(50, &cf), 0);
    for (i = 0; i < 50; i++) { /* collinear, far away */
        g_fpts[i].v[0] = 2100.0f + (float)i;
        g_fpts[i].v[1] = -1500.0f + 2.0f * (float)i;
        g_fpts[i].v[2] = 900.0f - 0.5f * (float)i;
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
    assert_int_equal(compare(50, &cf), 0);
    assert_int_equal(compare(3, &cf), 0); /* too few */
}

/* Radii from 1e-8 to 6e7 (at the top, det C exceeds float's range unless
 * scaled: the fuzzer's finding), well conditioned and near-planar. */
static void test_extreme_scales(void **state)
{
    tu_rng_t g;
    int e, flat;
    (void)state;
    g_lean = g_full = 0;
    for (flat = 0; flat < 2; flat++) {
        for (e = -8; e <= 8; e++) {
            const double r = (e < 8) ? pow(10.0, (double)e) : 6e7;
            const sfit_fit_cfg_t cf = cfg_of(SFIT_MODE_AUTO, 0.0f, 0.0f);
            size_t i;
            int k;
            tu_rng_seed(&g, 1605u + (uint64_t)(e + 8));
            make_cap(&g, 300, 100.0, 60.0 * TU_PI / 180.0, 0.0, flat ? 0.03 : 1.0);
            for (i = 0; i < 300; i++) { /* about the origin, radius r */
                double p[3];
                for (k = 0; k < 3; k++) {
                    p[k] = (g_pts[i][k] - k_center[k]) * (r / 100.0);
                }
                tc_to_vec3(p, &g_fpts[i]);
                tc_to_double3(&g_fpts[i], g_pts[i]);
            }
            (void)compare(300, &cf);
        }
    }
    print_message("extreme scales: %d screened, %d full\n", g_lean, g_full);
    assert_true(g_lean >= 10);
}

/* Small caps, many samples, a tiny planar ratio: the conditioning crosses
 * the SFIT_FLAG_ROUNDING threshold, which the screen must also prove. */
static void test_rounding_boundary(void **state)
{
    tu_rng_t g;
    int i, flagged = 0;
    (void)state;
    g_lean = g_full = 0;
    for (i = 0; i < 40; i++) {
        const double theta = (6.0 + 0.5 * (double)i) * TU_PI / 180.0;
        const sfit_fit_cfg_t cf = cfg_of(SFIT_MODE_SPHERE, 0.0f, 1e-6f);
        sfit_result_t r;
        tu_rng_seed(&g, 1606u + (uint64_t)i);
        make_cap(&g, NMAX, 100.0, theta, 0.0, 1.0);
        (void)compare(NMAX, &cf);
        if (sfit_fit_points(g_fpts, NMAX, &cf, &r) == SFIT_OK
            && (r.flags & (uint32_t)SFIT_FLAG_ROUNDING) != 0u) {
            flagged++;
        }
    }
    print_message("rounding sweep: %d screened, %d full, %d flagged\n", g_lean, g_full, flagged);
    assert_true(flagged > 0 && flagged < 40);
    assert_true(g_lean > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_is_screened),
        cmocka_unit_test(test_random_cases),
        cmocka_unit_test(test_planar_boundary),
        cmocka_unit_test(test_trust_boundary),
        cmocka_unit_test(test_degenerate_statuses),
        cmocka_unit_test(test_extreme_scales),
        cmocka_unit_test(test_rounding_boundary),
    };
    return cmocka_run_group_tests_name("lean", tests, NULL, NULL);
}
