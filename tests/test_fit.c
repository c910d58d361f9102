/* SPDX-License-Identifier: MIT */
/**
 * @file test_fit.c
 * @brief GDKE / UGDK / planar solutions against the independent double
 * reference (tests/ref), on exact, noisy far-offset synthetic data and on
 * the real recordings in tests/data; the cap-bias Monte Carlo; every error
 * path of the solve.
 */
#include "test_cmocka.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "sfit_ref.h"

#define NMAX 100000
static double g_pts[NMAX][3];
static sfit_vec3_t g_fpts[NMAX];

static const double k_center[3] = {2100.0, -1500.0, 900.0}; /* |c| = 2731 mm */
static const double k_axis[3] = {0.267261241912424, 0.534522483824849, 0.801783725737273};

/* n cap samples (half-angle theta, noise sigma) rounded to float; g_pts
 * holds exactly the float values so library and reference see the same
 * data. */
static void make_cap(tu_rng_t *g, size_t n, double r, double theta, double sigma)
{
    size_t i;
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_cap(g, k_center, r, k_axis, theta, sigma, p);
        tc_to_vec3(p, &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
}

static sfit_status_t fit_array(size_t n, const sfit_fit_cfg_t *cfg, sfit_result_t *r)
{
    return sfit_fit_points(g_fpts, n, cfg, r);
}

static sfit_fit_cfg_t cfg_iso(float var, sfit_mode_t mode)
{
    sfit_fit_cfg_t c = sfit_fit_cfg_default;
    c.mode = mode;
    if (var > 0.0f) {
        c.noise = SFIT_NOISE_ISO;
        c.noise_var = var;
    }
    return c;
}

/* ---------------------------------------------------------------- exact */

static void test_exact_sphere_far_offset(void **state)
{
    const double thetas[] = {30.0, 45.0, 90.0, 180.0};
    tu_rng_t g;
    size_t k;
    (void)state;
    tu_rng_seed(&g, 100);
    for (k = 0; k < 4; k++) {
        sfit_result_t r;
        make_cap(&g, 2000, 100.0, thetas[k] * TU_PI / 180.0, 0.0);
        assert_int_equal(fit_array(2000, NULL, &r), SFIT_OK);
        /* The samples are the truth rounded to float (|x| ~ 2.7e3: half an
         * ulp is 1.2e-4 mm), so the fit matches the truth to ~1e-5 r. */
        assert_true(tc_dist(&r.center, k_center) <= 1e-5 * 100.0);
        assert_near(r.radius, 100.0, 1e-5 * 100.0, "exact radius");
        assert_int_equal(r.mode, SFIT_MODE_SPHERE);
        assert_int_equal(r.method, SFIT_METHOD_GDKE);
        assert_int_equal(r.n, 2000u);
        assert_true(r.trust_ratio == 0.0f && r.flags == 0u);
    }
}

static void test_tetrahedron_minimum(void **state)
{
    /* Four points determine a sphere: the regular tetrahedron on the unit
     * sphere around (1, 2, 3). */
    const double s = 1.0 / sqrt(3.0);
    const double v[4][3] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
    sfit_vec3_t p[4];
    sfit_result_t r;
    int i;
    (void)state;
    for (i = 0; i < 4; i++) {
        p[i].v[0] = (float)(1.0 + v[i][0]);
        p[i].v[1] = (float)(2.0 + v[i][1]);
        p[i].v[2] = (float)(3.0 + v[i][2]);
    }
    assert_int_equal(sfit_fit_points(p, 4, NULL, &r), SFIT_OK);
    assert_vec3_near(r.center.v, ((const double[3]){1.0, 2.0, 3.0}), 1e-6, "tetra centre");
    assert_near(r.radius, 1.0, 1e-6, "tetra radius");
    assert_true((r.flags & SFIT_FLAG_FEW_SAMPLES) != 0u);
}

/* ------------------------------------------------------ float accuracy */

/* Must-show 3 of the core issue: GDKE (and UGDK with the true sigma^2) in
 * float vs the double reference on the same samples, centre ~2731 mm from
 * the origin, r = 100 mm, sigma 0.5..5 mm, caps 30 deg..full sphere,
 * N = 10..100000. Criterion: |c - c_ref| and |r - r_ref| <= 1e-4 r. */
static void test_float_accuracy_sweep(void **state)
{
    const double thetas[] = {30.0, 45.0, 60.0, 90.0, 180.0};
    const double sigmas[] = {0.5, 1.0, 2.0, 5.0};
    const size_t ns[] = {10, 100, 1000, 10000, 100000};
    double worst_c = 0.0, worst_r = 0.0, worst_cu = 0.0;
    char where_c[96] = "", where_r[96] = "";
    size_t a, b, k;
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 200);
    for (a = 0; a < 5; a++) {
        for (b = 0; b < 4; b++) {
            for (k = 0; k < 5; k++) {
                const size_t n = ns[k];
                sfit_result_t r;
                ref_fit_t ref;
                double ec, er;
                sfit_fit_cfg_t cfg = cfg_iso(0.0f, SFIT_MODE_SPHERE);
                make_cap(&g, n, 100.0, thetas[a] * TU_PI / 180.0, sigmas[b]);
                assert_int_equal(ref_fit_sphere(REF_C3(g_pts), n, NULL, &ref), 0);
                assert_int_equal(fit_array(n, &cfg, &r), SFIT_OK);
                ec = tc_dist(&r.center, ref.center) / 100.0;
                er = fabs((double)r.radius - ref.radius) / 100.0;
                if (ec > worst_c) {
                    worst_c = ec;
                    snprintf(where_c, sizeof where_c, "cap %g deg, sigma %g, N %zu", thetas[a],
                             sigmas[b], n);
                }
                if (er > worst_r) {
                    worst_r = er;
                    snprintf(where_r, sizeof where_r, "cap %g deg, sigma %g, N %zu", thetas[a],
                             sigmas[b], n);
                }
                assert_true(ec <= 1e-4);
                assert_true(er <= 1e-4);
                /* UGDK with the true noise, where the reference can solve. */
                {
                    const double cov[6] = {sigmas[b] * sigmas[b], sigmas[b] * sigmas[b],
                                           sigmas[b] * sigmas[b], 0, 0, 0};
                    cfg = cfg_iso((float)(sigmas[b] * sigmas[b]), SFIT_MODE_SPHERE);
                    if (ref_fit_sphere(REF_C3(g_pts), n, cov, &ref) == 0
                        && ref.trust_ratio < 1.0) {
                        assert_int_equal(fit_array(n, &cfg, &r), SFIT_OK);
                        ec = tc_dist(&r.center, ref.center) / 100.0;
                        if (ec > worst_cu) {
                            worst_cu = ec;
                        }
                        assert_true(ec <= 1e-4);
                        assert_true(fabs((double)r.radius - ref.radius) / 100.0 <= 1e-4);
                    }
                }
            }
        }
    }
    print_message("worst GDKE centre error %.2e r (%s)\n", worst_c, where_c);
    print_message("worst GDKE radius error %.2e r (%s)\n", worst_r, where_r);
    print_message("worst UGDK centre error %.2e r (Leontief ratio < 1 cases)\n", worst_cu);
}

/* Independent second oracle: GDKE equals the direct algebraic (Kasa) fit. */
static void test_gdke_is_kasa(void **state)
{
    tu_rng_t g;
    sfit_result_t r;
    double c[3], rad;
    (void)state;
    tu_rng_seed(&g, 300);
    make_cap(&g, 5000, 100.0, 50.0 * TU_PI / 180.0, 2.0);
    assert_int_equal(ref_kasa_sphere_direct(REF_C3(g_pts), 5000, c, &rad), 0);
    assert_int_equal(fit_array(5000, NULL, &r), SFIT_OK);
    assert_true(tc_dist(&r.center, c) <= 1e-4 * 100.0);
    assert_near(r.radius, rad, 1e-4 * 100.0, "Kasa radius");
}

/* --------------------------------------------------------- UGDK / trust */

static void test_ugdk_full_covariance(void **state)
{
    /* Anisotropic noise: Sigma = A A^T with a fixed A; samples get A z. */
    const double A[3][3] = {{1.5, 0.0, 0.0}, {0.4, 0.8, 0.0}, {-0.3, 0.5, 1.1}};
    double cov[6], S[3][3];
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    sfit_result_t r;
    ref_fit_t ref;
    tu_rng_t g;
    size_t i;
    int a, b, k;
    (void)state;
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            S[a][b] = 0.0;
            for (k = 0; k < 3; k++) {
                S[a][b] += A[a][k] * A[b][k];
            }
        }
    }
    cov[0] = S[0][0]; cov[1] = S[1][1]; cov[2] = S[2][2];
    cov[3] = S[0][1]; cov[4] = S[0][2]; cov[5] = S[1][2];
    tu_rng_seed(&g, 400);
    for (i = 0; i < 3000; i++) {
        double p[3], z[3];
        tu_sample_cap(&g, k_center, 100.0, k_axis, 30.0 * TU_PI / 180.0, 0.0, p);
        for (a = 0; a < 3; a++) {
            z[a] = tu_rng_gauss(&g);
        }
        for (a = 0; a < 3; a++) {
            p[a] += A[a][0] * z[0] + A[a][1] * z[1] + A[a][2] * z[2];
        }
        tc_to_vec3(p, &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
    cfg.noise = SFIT_NOISE_COV;
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            cfg.noise_cov.m[3 * a + b] = (float)S[a][b];
        }
    }
    /* The reference sees the float-rounded covariance, too. */
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            S[a][b] = (double)cfg.noise_cov.m[3 * a + b];
        }
    }
    cov[0] = S[0][0]; cov[1] = S[1][1]; cov[2] = S[2][2];
    cov[3] = S[0][1]; cov[4] = S[0][2]; cov[5] = S[1][2];
    assert_int_equal(ref_fit_sphere(REF_C3(g_pts), 3000, cov, &ref), 0);
    assert_int_equal(fit_array(3000, &cfg, &r), SFIT_OK);
    assert_int_equal(r.method, SFIT_METHOD_UGDK);
    assert_true(tc_dist(&r.center, ref.center) <= 1e-4 * 100.0);
    assert_near(r.radius, ref.radius, 1e-4 * 100.0, "UGDK cov radius");
    /* Trust ratios: Leontief ratio = rho(C'^-1 Sigma) (the reference's
     * trust_ratio), trust ratio = rho(C^-1 Sigma) = nu/(1+nu); 1e-4 relative. */
    assert_true(ref.trust_ratio > 0.01);
    assert_near(r.leontief_ratio, ref.trust_ratio, 1e-4 * ref.trust_ratio, "leontief ratio");
    assert_near(r.trust_ratio, ref.trust_ratio / (1.0 + ref.trust_ratio),
                1e-4 * ref.trust_ratio, "trust ratio");
    /* Isotropic special case: rho(C^-1 sigma^2 I) = sigma^2 / lambda_min(C). */
    cfg = cfg_iso(2.0f, SFIT_MODE_SPHERE);
    cfg.eigen = true; /* eigenvalues and the exact trust ratio */
    assert_int_equal(fit_array(3000, &cfg, &r), SFIT_OK);
    assert_near(r.trust_ratio, 2.0 / (double)r.eigenvalues.v[0], 1e-5, "iso trust");
}

static void test_untrusted_flag(void **state)
{
    /* 30-degree cap: lambda_min = r^2 sin^4(15 deg)/3 = 14.96 mm^2. A noise
     * model of 10 mm^2 passes C' > 0 but the Leontief ratio is > 1. */
    tu_rng_t g;
    sfit_result_t r;
    sfit_fit_cfg_t cfg = cfg_iso(10.0f, SFIT_MODE_SPHERE);
    (void)state;
    tu_rng_seed(&g, 500);
    make_cap(&g, 20000, 100.0, 30.0 * TU_PI / 180.0, 0.0);
    assert_int_equal(fit_array(20000, &cfg, &r), SFIT_OK);
    assert_true(r.leontief_ratio >= 1.0f);
    assert_true(r.trust_ratio >= 0.5f && r.trust_ratio < 1.0f);
    assert_true((r.flags & SFIT_FLAG_UNTRUSTED) != 0u);
    cfg = cfg_iso(3.0f, SFIT_MODE_SPHERE);
    assert_int_equal(fit_array(20000, &cfg, &r), SFIT_OK);
    assert_true((r.flags & SFIT_FLAG_UNTRUSTED) == 0u);
}

/* ----------------------------------------------------------- Monte Carlo */

/* GDKE is biased along the cap axis by about trust_ratio * |c - m| =
 * rho r (1 + cos theta)/2 (DESIGN.md section 2); UGDK is not. 45-degree
 * cap, r = 100 mm: lambda_min(C0) = r^2 sin^4(22.5 deg)/3 = 71.5 mm^2;
 * sigma^2 = 7.9 mm^2 gives rho = sigma^2/lambda_min(C) = 0.1 (C = C0 +
 * sigma^2 I). T trials of N samples; standard errors from the spread.
 * UGDK keeps an O(1/N) bias (E C'^-1 != C0^-1 at second order). Measured
 * with the double reference (1000 trials each): -0.27 +- 0.07 mm along the
 * axis at N = 250, -0.047 +- 0.038 at N = 1000, -0.019 +- 0.019 at
 * N = 4000, i.e. ~ -67 mm / N. N = 4000 makes it small against the
 * standard error, which is what "unbiased" can mean here. */
static void test_monte_carlo_cap_bias(void **state)
{
    const int T = 250;
    const size_t N = 4000;
    const double theta = 45.0 * TU_PI / 180.0, r0 = 100.0;
    const double lmin0 = r0 * r0 * pow(sin(theta / 2.0), 4.0) / 3.0;
    const double rho = 0.1, sigma2 = rho * lmin0 / (1.0 - rho);
    double sg[3] = {0, 0, 0}, sg2[3] = {0, 0, 0}, su[3] = {0, 0, 0}, su2[3] = {0, 0, 0};
    double ax_g = 0, ax_g2 = 0, mrho = 0;
    tu_rng_t g;
    int t, i;
    (void)state;
    tu_rng_seed(&g, 600);
    for (t = 0; t < T; t++) {
        sfit_result_t rg, ru;
        sfit_fit_cfg_t cu = cfg_iso((float)sigma2, SFIT_MODE_SPHERE);
        double eg[3], eu[3], a;
        cu.eigen = true; /* the exact trust ratio */
        make_cap(&g, N, r0, theta, sqrt(sigma2));
        assert_int_equal(fit_array(N, NULL, &rg), SFIT_OK);
        assert_int_equal(fit_array(N, &cu, &ru), SFIT_OK);
        for (i = 0; i < 3; i++) {
            eg[i] = (double)rg.center.v[i] - k_center[i];
            eu[i] = (double)ru.center.v[i] - k_center[i];
            sg[i] += eg[i]; sg2[i] += eg[i] * eg[i];
            su[i] += eu[i]; su2[i] += eu[i] * eu[i];
        }
        a = tu_dot3(eg, k_axis);
        ax_g += a;
        ax_g2 += a * a;
        mrho += (double)ru.trust_ratio;
    }
    mrho /= T;
    {
        const double mean_ax = ax_g / T;
        const double se_ax = sqrt((ax_g2 / T - mean_ax * mean_ax) / (T - 1));
        const double predicted = rho * r0 * (1.0 + cos(theta)) / 2.0; /* 8.5 mm */
        print_message("GDKE axial bias %.3f mm (SE %.3f), predicted %.3f; mean trust %.4f\n",
                      mean_ax, se_ax, predicted, mrho);
        /* Biased towards the samples (+axis), by many standard errors. */
        assert_true(mean_ax > 10.0 * se_ax);
        /* Magnitude: the first-order prediction within 5 % + 3 SE. */
        assert_true(fabs(mean_ax - predicted) <= 0.05 * predicted + 3.0 * se_ax);
        /* The measured trust ratio is the rho of the prediction. */
        assert_near(mrho, rho, 0.01, "mean trust ratio");
    }
    for (i = 0; i < 3; i++) {
        const double mu = su[i] / T;
        const double se = sqrt((su2[i] / T - mu * mu) / (T - 1));
        const double mg = sg[i] / T;
        const double seg = sqrt((sg2[i] / T - mg * mg) / (T - 1));
        print_message("axis %d: GDKE %.3f +- %.3f, UGDK %.3f +- %.3f mm\n", i, mg, seg, mu, se);
        assert_true(fabs(mu) <= 3.0 * se); /* UGDK unbiased within 3 SE */
    }
}

/* ---------------------------------------------------------------- planar */

static void rotate_offset(const double p[2], double out[3])
{
    /* In-plane basis e1, e2 of a tilted plane far from the origin. */
    const double o[3] = {-1800.0, 2200.0, 650.0};
    const double e1[3] = {0.6, 0.8, 0.0};
    const double e2[3] = {-0.48, 0.36, 0.8};
    int i;
    for (i = 0; i < 3; i++) {
        out[i] = o[i] + p[0] * e1[i] + p[1] * e2[i];
    }
}

/* Gander, Golub & Strebel (1994), "Least-squares fitting of circles and
 * ellipses", BIT 34: the six points below. The algebraic (Kasa) circle is
 * computed here by the independent 2-D reference. */
static void test_ggs_circle(void **state)
{
    const double p2[6][2] = {{1, 7}, {2, 6}, {5, 8}, {7, 7}, {9, 5}, {3, 7}};
    double c2[2], r2, c3[3], cz[3];
    sfit_vec3_t pts[6];
    sfit_result_t r;
    sfit_fit_cfg_t cfg = cfg_iso(0.0f, SFIT_MODE_AUTO);
    int i;
    (void)state;
    assert_int_equal(ref_kasa_circle_2d((const double (*)[2])p2, 6, c2, &r2), 0);
    print_message("GGS Kasa circle (double reference): (%.6f, %.6f) r %.6f\n", c2[0], c2[1], r2);
    /* In the plane z = 0: exactly planar, auto mode must pick planar. */
    for (i = 0; i < 6; i++) {
        pts[i].v[0] = (float)p2[i][0];
        pts[i].v[1] = (float)p2[i][1];
        pts[i].v[2] = 0.0f;
    }
    assert_int_equal(sfit_fit_points(pts, 6, &cfg, &r), SFIT_OK);
    assert_int_equal(r.mode, SFIT_MODE_PLANAR);
    cz[0] = c2[0]; cz[1] = c2[1]; cz[2] = 0.0;
    assert_true(tc_dist(&r.center, cz) <= 1e-4 * r2);
    assert_near(r.radius, r2, 1e-4 * r2, "GGS radius z=0");
    assert_vec3_near(r.axis.v, ((const double[3]){0, 0, 1}), 1e-6, "GGS axis");
    /* A sphere fit of exactly planar data is degenerate. */
    cfg.mode = SFIT_MODE_SPHERE;
    assert_int_equal(sfit_fit_points(pts, 6, &cfg, &r), SFIT_E_DEGENERATE);
    /* Rotated into a tilted plane and offset ~2900 mm from the origin. */
    for (i = 0; i < 6; i++) {
        double q[3];
        rotate_offset(p2[i], q);
        tc_to_vec3(q, &pts[i]);
    }
    rotate_offset(c2, c3);
    cfg.mode = SFIT_MODE_AUTO;
    assert_int_equal(sfit_fit_points(pts, 6, &cfg, &r), SFIT_OK);
    assert_int_equal(r.mode, SFIT_MODE_PLANAR);
    print_message("GGS rotated: centre error %.3g (rel %.3g), radius error rel %.3g\n",
                  tc_dist(&r.center, c3), tc_dist(&r.center, c3) / r2,
                  fabs((double)r.radius - r2) / r2);
    assert_true(tc_dist(&r.center, c3) <= 1e-4 * r2);
    assert_near(r.radius, r2, 1e-4 * r2, "GGS radius rotated");
    {
        /* Axis = plane normal e1 x e2 = (0.64, -0.48, 0.6) (sign-normalised). */
        const double nrm[3] = {0.64, -0.48, 0.6};
        assert_vec3_near(r.axis.v, nrm, 1e-4, "GGS rotated axis");
    }
}

static void test_planar_arcs_vs_reference(void **state)
{
    const double thetas[] = {20.0, 60.0, 120.0, 180.0};
    const double sigmas[] = {0.0, 0.5, 2.0};
    const double normal[3] = {0.64, -0.48, 0.6};
    const double refdir[3] = {0.6, 0.8, 0.0};
    tu_rng_t g;
    size_t a, b;
    (void)state;
    tu_rng_seed(&g, 700);
    for (a = 0; a < 4; a++) {
        for (b = 0; b < 3; b++) {
            const size_t n = 2000;
            size_t i;
            sfit_result_t r;
            ref_fit_t ref;
            sfit_fit_cfg_t cfg = cfg_iso(0.0f, SFIT_MODE_PLANAR);
            for (i = 0; i < n; i++) {
                double p[3];
                tu_sample_arc(&g, k_center, 100.0, normal, refdir, thetas[a] * TU_PI / 180.0,
                              sigmas[b], p);
                tc_to_vec3(p, &g_fpts[i]);
                tc_to_double3(&g_fpts[i], g_pts[i]);
            }
            assert_int_equal(ref_fit_circle(REF_C3(g_pts), n, NULL, &ref), 0);
            assert_int_equal(fit_array(n, &cfg, &r), SFIT_OK);
            assert_true(tc_dist(&r.center, ref.center) <= 1e-4 * 100.0);
            assert_near(r.radius, ref.radius, 1e-4 * 100.0, "arc radius");
            assert_vec3_near(r.axis.v, ref.axis, 1e-3, "arc axis");
            if (sigmas[b] == 0.0) {
                assert_true(tc_dist(&r.center, k_center) <= 1e-4 * 100.0);
            }
            /* Auto picks planar exactly when the set is near-planar: always
             * for a noise-free arc; a short noisy arc can be thicker than
             * the threshold (20 deg, sigma 2: ratio 4/395 > 5e-3). */
            cfg.mode = SFIT_MODE_AUTO;
            assert_int_equal(fit_array(n, &cfg, &r), SFIT_OK);
            assert_int_equal(r.mode == SFIT_MODE_PLANAR,
                             (r.flags & SFIT_FLAG_NEAR_PLANAR) != 0u);
            if (sigmas[b] == 0.0) {
                assert_int_equal(r.mode, SFIT_MODE_PLANAR);
            }
            /* UGDK in planar mode vs the reference circle with the same cov. */
            if (sigmas[b] > 0.0) {
                const double s2 = sigmas[b] * sigmas[b];
                const double cov[6] = {s2, s2, s2, 0, 0, 0};
                cfg = cfg_iso((float)s2, SFIT_MODE_PLANAR);
                assert_int_equal(ref_fit_circle(REF_C3(g_pts), n, cov, &ref), 0);
                assert_int_equal(fit_array(n, &cfg, &r), SFIT_OK);
                assert_true(tc_dist(&r.center, ref.center) <= 1e-4 * 100.0);
                assert_near(r.radius, ref.radius, 1e-4 * 100.0, "arc UGDK radius");
                assert_near(r.leontief_ratio, ref.trust_ratio, 1e-4 * ref.trust_ratio + 1e-7,
                            "arc leontief");
            }
        }
    }
}

/* ------------------------------------------------------------- real data */

typedef struct {
    const char *file;
    double scale; /* unit of the file in mm: tolerances are given in mm */
} real_case_t;

static size_t load(const char *rel)
{
    char path[512];
    size_t n = 0, i;
    snprintf(path, sizeof path, "%s/%s", SFIT_TEST_DATA_DIR, rel);
    assert_int_equal(tu_load_csv(path, g_pts, NMAX, &n), 0);
    for (i = 0; i < n; i++) {
        tc_to_vec3(g_pts[i], &g_fpts[i]);
        tc_to_double3(&g_fpts[i], g_pts[i]);
    }
    return n;
}

static void test_real_data_vs_reference(void **state)
{
    const real_case_t cases[] = {
        {"mocap/hip_right/RTHI1.csv", 1.0},   {"mocap/hip_right/RTHI2.csv", 1.0},
        {"mocap/hip_right/RTHI3.csv", 1.0},   {"mocap/hip_right/RLFE.csv", 1.0},
        {"mocap/hip_right/RMFE.csv", 1.0},    {"mocap/hip_right/RGT.csv", 1.0},
        {"mocap/elbow_right/ForearmR1.csv", 1000.0},
        {"mocap/elbow_right/ForearmR2.csv", 1000.0},
        {"mocap/elbow_right/ForearmR3.csv", 1000.0},
        {"mag/fusion_example/mag.csv", 1.0},
    };
    size_t k;
    (void)state;
    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const size_t n = load(cases[k].file);
        sfit_result_t r;
        ref_fit_t ref;
        sfit_fit_cfg_t cfg = cfg_iso(0.0f, SFIT_MODE_SPHERE);
        double err;
        assert_int_equal(ref_fit_sphere(REF_C3(g_pts), n, NULL, &ref), 0);
        assert_int_equal(fit_array(n, &cfg, &r), SFIT_OK);
        err = tc_dist(&r.center, ref.center) * cases[k].scale;
        print_message("%-32s n %5zu centre (%.4f, %.4f, %.4f) r %.4f  |float-double| %.2e mm\n",
                      cases[k].file, n, (double)r.center.v[0], (double)r.center.v[1],
                      (double)r.center.v[2], (double)r.radius, err);
        /* Must-show 2 (hip) and the same bar for every recording: 0.01 mm. */
        assert_true(err <= 0.01);
        assert_near((double)r.radius * cases[k].scale, ref.radius * cases[k].scale, 0.01,
                    "real radius");
    }
}

static void test_real_hip_published_value(void **state)
{
    /* tests/data/README.md: Kasa centre of RTHI1 (-66.129, -93.950, 76.081),
     * r 254.519, computed independently of sfit and printed to 3 decimals. */
    const double pub[3] = {-66.129, -93.950, 76.081};
    const size_t n = load("mocap/hip_right/RTHI1.csv");
    sfit_result_t r;
    (void)state;
    assert_int_equal(fit_array(n, NULL, &r), SFIT_OK);
    assert_vec3_near(r.center.v, pub, 0.0005 + 0.01, "RTHI1 published centre");
    assert_near(r.radius, 254.519, 0.0005 + 0.01, "RTHI1 published radius");
    assert_int_equal(r.mode, SFIT_MODE_SPHERE);
}

static void test_real_knee_is_planar(void **state)
{
    const char *files[] = {"RATT", "RLM", "RSPH", "RLEG1", "RLEG2", "RLEG3"};
    double axes[6][3], maxang = 0.0;
    size_t k, j;
    (void)state;
    for (k = 0; k < 6; k++) {
        char rel[64];
        size_t n;
        sfit_result_t r;
        ref_fit_t ref;
        snprintf(rel, sizeof rel, "mocap/knee_right/%s.csv", files[k]);
        n = load(rel);
        assert_int_equal(fit_array(n, NULL, &r), SFIT_OK);
        assert_int_equal(r.mode, SFIT_MODE_PLANAR);
        assert_int_equal(ref_fit_circle(REF_C3(g_pts), n, NULL, &ref), 0);
        assert_true(tc_dist(&r.center, ref.center) <= 0.01);
        assert_near(r.radius, ref.radius, 0.01, "knee radius");
        tc_to_double3(&r.axis, axes[k]);
    }
    for (k = 0; k < 6; k++) {
        for (j = k + 1; j < 6; j++) {
            const double c = fabs(tu_dot3(axes[k], axes[j]));
            const double ang = acos(c > 1.0 ? 1.0 : c) * 180.0 / TU_PI;
            if (ang > maxang) {
                maxang = ang;
            }
        }
    }
    {
        /* Spread about the mean axis (axes are sign-normalised alike). */
        double mean[3] = {0, 0, 0}, rms = 0.0, nm;
        for (k = 0; k < 6; k++) {
            for (j = 0; j < 3; j++) {
                mean[j] += axes[k][j];
            }
        }
        nm = tu_norm3(mean);
        for (k = 0; k < 6; k++) {
            const double c = tu_dot3(axes[k], mean) / nm;
            const double ang = acos(c > 1.0 ? 1.0 : c) * 180.0 / TU_PI;
            rms += ang * ang;
        }
        print_message("knee: marker axes: largest pairwise angle %.2f deg, rms about the "
                      "mean axis %.2f deg\n", maxang, sqrt(rms / 6.0));
    }
    assert_true(maxang < 10.0);
}

/* ----------------------------------------------------------- error paths */

static void test_errors(void **state)
{
    sfit_moments_t m;
    sfit_result_t r, sentinel;
    sfit_fit_cfg_t cfg;
    sfit_vec3_t p[8];
    tu_rng_t g;
    int i;
    (void)state;
    memset(&sentinel, 0xC3, sizeof sentinel);
    r = sentinel;
    (void)sfit_moments_init(&m);
    assert_int_equal(sfit_fit_moments(NULL, NULL, &r), SFIT_E_ARG);
    assert_int_equal(sfit_fit_moments(&m, NULL, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_fit_points(NULL, 5, NULL, &r), SFIT_E_ARG);
    assert_int_equal(sfit_fit_points(p, 5, NULL, NULL), SFIT_E_ARG);
    /* Too few: 0..3 samples. */
    tu_rng_seed(&g, 800);
    make_cap(&g, 8, 100.0, 1.0, 0.0);
    for (i = 0; i < 4; i++) {
        assert_int_equal(sfit_fit_points(g_fpts, (size_t)i, NULL, &r), SFIT_E_TOO_FEW);
    }
    /* Coincident. */
    for (i = 0; i < 8; i++) {
        p[i] = g_fpts[0];
    }
    assert_int_equal(sfit_fit_points(p, 8, NULL, &r), SFIT_E_DEGENERATE);
    /* Collinear (on a line through a far point). */
    for (i = 0; i < 8; i++) {
        p[i].v[0] = 2000.0f + 3.0f * (float)i;
        p[i].v[1] = -1000.0f + 2.0f * (float)i;
        p[i].v[2] = 500.0f - 1.0f * (float)i;
    }
    assert_int_equal(sfit_fit_points(p, 8, NULL, &r), SFIT_E_DEGENERATE);
    cfg = cfg_iso(0.0f, SFIT_MODE_PLANAR);
    assert_int_equal(sfit_fit_points(p, 8, &cfg, &r), SFIT_E_DEGENERATE);
    /* Non-finite / out-of-range sample in a batch. */
    p[3].v[1] = NAN;
    assert_int_equal(sfit_fit_points(p, 8, NULL, &r), SFIT_E_NONFINITE);
    p[3].v[1] = 1e20f;
    assert_int_equal(sfit_fit_points(p, 8, NULL, &r), SFIT_E_RANGE);
    /* Noise larger than the spread: C' not positive definite. */
    cfg = cfg_iso(1e6f, SFIT_MODE_SPHERE);
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_NOT_POSDEF);
    cfg.mode = SFIT_MODE_PLANAR;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_NOT_POSDEF);
    cfg.mode = SFIT_MODE_AUTO;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_NOT_POSDEF);
    /* Invalid options. */
    cfg = sfit_fit_cfg_default;
    cfg.mode = (sfit_mode_t)7;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.noise = (sfit_noise_kind_t)9;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg = cfg_iso(1.0f, SFIT_MODE_AUTO);
    cfg.noise_var = -1.0f;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg.noise_var = NAN;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.noise = SFIT_NOISE_COV;
    cfg.noise_cov.m[0] = 1.0f;
    cfg.noise_cov.m[4] = INFINITY;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg.noise_cov.m[4] = -1.0f;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    /* Not positive semi-definite: a 2x2 principal minor < 0 (fuzz finding:
     * the planar trust ratio came out negative for such a Sigma). */
    cfg.noise_cov.m[0] = 1.0f; cfg.noise_cov.m[4] = 1.0f; cfg.noise_cov.m[8] = 2.0f;
    cfg.noise_cov.m[3] = 1e4f; cfg.noise_cov.m[6] = 0.0f; cfg.noise_cov.m[7] = 0.0f;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg.noise_cov.m[3] = 0.0f; cfg.noise_cov.m[7] = -2.0f;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg = sfit_fit_cfg_default;
    cfg.planar_ratio = 1.5f;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    cfg.planar_ratio = NAN;
    assert_int_equal(sfit_fit_points(g_fpts, 8, &cfg, &r), SFIT_E_ARG);
    /* Every failure above left the output untouched. */
    assert_memory_equal(&r, &sentinel, sizeof r);
    /* The solve does not modify the accumulator, and can be repeated. */
    {
        sfit_moments_t before;
        sfit_result_t r1, r2;
        (void)sfit_moments_add_block(&m, g_fpts, 8, NULL);
        before = m;
        assert_int_equal(sfit_fit_moments(&m, NULL, &r1), SFIT_OK);
        assert_int_equal(sfit_fit_moments(&m, NULL, &r2), SFIT_OK);
        assert_memory_equal(&m, &before, sizeof m);
        assert_memory_equal(&r1, &r2, sizeof r1);
    }
}

static void test_mode_threshold(void **state)
{
    /* A near-hinge set: an arc with 1 mm of out-of-plane wobble. Auto picks
     * planar with the default ratio and sphere when the threshold is set
     * below the measured ratio; sphere mode flags it. */
    const double normal[3] = {0, 0, 1}, refdir[3] = {1, 0, 0};
    tu_rng_t g;
    sfit_result_t r;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    size_t i;
    float ratio;
    (void)state;
    tu_rng_seed(&g, 900);
    for (i = 0; i < 1000; i++) {
        double p[3];
        tu_sample_arc(&g, k_center, 100.0, normal, refdir, 1.0, 0.0, p);
        p[2] += tu_rng_gauss(&g);
        tc_to_vec3(p, &g_fpts[i]);
    }
    assert_int_equal(fit_array(1000, &cfg, &r), SFIT_OK);
    assert_int_equal(r.mode, SFIT_MODE_PLANAR);
    assert_true((r.flags & SFIT_FLAG_NEAR_PLANAR) != 0u);
    ratio = r.eigenvalues.v[0] / r.eigenvalues.v[2];
    cfg.planar_ratio = 0.5f * ratio;
    assert_int_equal(fit_array(1000, &cfg, &r), SFIT_OK);
    assert_int_equal(r.mode, SFIT_MODE_SPHERE);
    assert_true((r.flags & SFIT_FLAG_NEAR_PLANAR) == 0u);
    cfg = cfg_iso(0.0f, SFIT_MODE_SPHERE);
    assert_int_equal(fit_array(1000, &cfg, &r), SFIT_OK);
    assert_int_equal(r.mode, SFIT_MODE_SPHERE);
    assert_true((r.flags & SFIT_FLAG_NEAR_PLANAR) != 0u);
}


/* --------------------------------------------- sfit_fit_moments_default */

/* The default fit by the plain solver (issue 30's minimal application):
 * bit for bit the fit with cfg.eigen true, and the same centre, radius,
 * status and flags as sfit_fit_moments(m, NULL): on random caps and arcs
 * (N 4-400, noise 0-5 % r, centres up to 3000 mm, radii 1-1000 mm) and on
 * degenerate sets; against the double reference on a cap and an arc. */
static void test_default_fit(void **state)
{
    sfit_fit_cfg_t eig = sfit_fit_cfg_default;
    sfit_moments_t m;
    sfit_result_t rd, re, rn;
    tu_rng_t g;
    unsigned planar = 0u, rounding = 0u, few = 0u, screened = 0u, refused = 0u, ok = 0u;
    int k;
    (void)state;
    eig.eigen = true;
    tu_rng_seed(&g, 1300);
    /* Arguments and too few samples: a specific status, out untouched. */
    assert_int_equal(sfit_moments_init(&m), SFIT_OK);
    memset(&rd, 0x5a, sizeof rd);
    rn = rd;
    assert_int_equal(sfit_fit_moments_default(NULL, &rd), SFIT_E_ARG);
    assert_int_equal(sfit_fit_moments_default(&m, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_fit_moments_default(&m, &rd), SFIT_E_TOO_FEW);
    assert_memory_equal(&rd, &rn, sizeof rd);
    for (k = 0; k < 4000; k++) {
        const double rad = pow(10.0, 3.0 * tu_rng_uniform(&g));
        const double theta = (1.0 + 179.0 * tu_rng_uniform(&g)) * TU_PI / 180.0;
        const double sigma = (k % 3 == 0) ? 0.0 : 0.05 * rad * tu_rng_uniform(&g);
        const size_t n = 4u + (size_t)(396.0 * tu_rng_uniform(&g) * tu_rng_uniform(&g));
        const int kind = k % 5; /* 0-2 cap, 3 arc, 4 degenerate */
        double c[3], ax[3], ref[3] = {1.0, 0.0, 0.0};
        sfit_status_t sd, se, sn;
        size_t i;
        for (i = 0; i < 3; i++) {
            c[i] = 3000.0 * (2.0 * tu_rng_uniform(&g) - 1.0);
            ax[i] = tu_rng_gauss(&g);
        }
        {
            const double l = tu_norm3(ax);
            for (i = 0; i < 3; i++) {
                ax[i] /= l;
            }
        }
        ref[0] = -ax[1]; /* a direction normal to ax */
        ref[1] = ax[0];
        ref[2] = 0.0;
        {
            const double l = tu_norm3(ref);
            for (i = 0; i < 3; i++) {
                ref[i] = (l > 1e-6) ? ref[i] / l : (i == 2 ? 1.0 : 0.0);
            }
        }
        (void)sfit_moments_init(&m);
        for (i = 0; i < n; i++) {
            double p[3];
            sfit_vec3_t x;
            if (kind <= 2) {
                tu_sample_cap(&g, c, rad, ax, theta, sigma, p);
            } else if (kind == 3) {
                tu_sample_arc(&g, c, rad, ax, ref, theta, sigma, p);
            } else { /* on a line (k % 2) or one point, with a little noise on some */
                const double t = (k % 2) ? rad * tu_rng_uniform(&g) : 0.0;
                int a;
                for (a = 0; a < 3; a++) {
                    p[a] = c[a] + t * ax[a] + ((k % 4 == 1) ? 1e-9 * rad * tu_rng_gauss(&g) : 0.0);
                }
            }
            tc_to_vec3(p, &x);
            assert_int_equal(sfit_moments_add(&m, &x), SFIT_OK);
        }
        memset(&rd, 0, sizeof rd);
        memset(&re, 0, sizeof re);
        memset(&rn, 0, sizeof rn);
        sd = sfit_fit_moments_default(&m, &rd);
        se = sfit_fit_moments(&m, &eig, &re);
        sn = sfit_fit_moments(&m, NULL, &rn);
        assert_int_equal(sd, se);
        assert_int_equal(sd, sn);
        if (sd != SFIT_OK) {
            refused++;
            continue;
        }
        ok++;
        assert_memory_equal(&rd, &re, sizeof rd); /* bit for bit */
        assert_true(rd.exact);
        assert_memory_equal(&rd.center, &rn.center, sizeof rd.center);
        assert_memory_equal(&rd.radius, &rn.radius, sizeof rd.radius);
        assert_int_equal(rd.flags, rn.flags);
        assert_int_equal(rd.mode, rn.mode);
        assert_int_equal(rd.n, rn.n);
        assert_int_equal(rd.method, rn.method);
        planar += (rd.mode == SFIT_MODE_PLANAR);
        rounding += ((rd.flags & SFIT_FLAG_ROUNDING) != 0u);
        few += ((rd.flags & SFIT_FLAG_FEW_SAMPLES) != 0u);
        screened += !rn.exact;
    }
    print_message("default fit: %u OK (planar %u, rounding %u, few %u; screened by "
                  "sfit_fit_moments %u), %u refused\n",
                  ok, planar, rounding, few, screened, refused);
    /* Every path of the comparison was taken. */
    assert_true(planar >= 100u && rounding >= 20u && few >= 20u && screened >= 500u);
    assert_true(refused >= 200u);
    /* Against the double reference (independent of the float solvers). */
    {
        ref_fit_t rf;
        make_cap(&g, 500, 100.0, 40.0 * TU_PI / 180.0, 0.2);
        (void)sfit_moments_init(&m);
        assert_int_equal(sfit_moments_add_block(&m, g_fpts, 500, NULL), SFIT_OK);
        assert_int_equal(sfit_fit_moments_default(&m, &rd), SFIT_OK);
        assert_int_equal(ref_fit_sphere(REF_C3(g_pts), 500, NULL, &rf), 0);
        assert_true(tc_dist(&rd.center, rf.center) <= 1e-4 * 100.0);
        assert_near(rd.radius, rf.radius, 1e-4 * 100.0, "default cap radius");
        assert_vec3_near(rd.axis.v, rf.axis, 1e-3, "default cap axis");
        assert_near(rd.eigenvalues.v[0], rf.eig[0], 1e-4 * rf.eig[2], "default cap eig");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_sphere_far_offset),
        cmocka_unit_test(test_tetrahedron_minimum),
        cmocka_unit_test(test_float_accuracy_sweep),
        cmocka_unit_test(test_gdke_is_kasa),
        cmocka_unit_test(test_ugdk_full_covariance),
        cmocka_unit_test(test_untrusted_flag),
        cmocka_unit_test(test_monte_carlo_cap_bias),
        cmocka_unit_test(test_ggs_circle),
        cmocka_unit_test(test_planar_arcs_vs_reference),
        cmocka_unit_test(test_real_data_vs_reference),
        cmocka_unit_test(test_real_hip_published_value),
        cmocka_unit_test(test_real_knee_is_planar),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_mode_threshold),
        cmocka_unit_test(test_default_fit),
    };
    return cmocka_run_group_tests_name("fit", tests, NULL, NULL);
}
