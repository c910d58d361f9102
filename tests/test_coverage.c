/* SPDX-License-Identifier: MIT */
/**
 * @file test_coverage.c
 * @brief Coverage aids (eq. 203-213): closed-form cap / arc eigenvalues
 * against numerical quadrature and large sampled sets, the inverses, the
 * real hip recordings, every error path. (Split from test_noise.c in 0.3.)
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit/sfit_coverage.h"
#include "sfit_ref.h"
#include "test_capset.h"



/* ------------------------------------------------------------ eigenvalues */

static const double k_grid_deg[] = {0.5,  1.0,   2.0,   5.0,   10.0,  20.0,  30.0,  45.0,
                                    60.0, 90.0,  120.0, 150.0, 170.0, 179.0, 180.0};

/* Closed forms (series in the library) vs the oracle's quadrature, at the
 * float theta the library sees: relative 1e-5 (float evaluation error is a
 * few 1e-7; the quadrature agrees with the exact integrals to ~1e-13). */
static void test_eigs_vs_quadrature(void **state)
{
    const double radii[] = {1.0, 100.0};
    size_t k, j;
    (void)state;
    for (j = 0; j < 2; j++) {
        for (k = 0; k < sizeof k_grid_deg / sizeof k_grid_deg[0]; k++) {
            const float th = (float)(k_grid_deg[k] * DEG);
            const double thd = (double)th; /* (float)pi is 8.7e-8 above pi */
            float a, b;
            double ra, rb;
            char what[64];
            /* cap */
            assert_int_equal(sfit_coverage_cap_eigs(th, (float)radii[j], &a, &b), SFIT_OK);
            ref_cap_eigs_numeric(thd > TU_PI ? TU_PI : thd, radii[j], &ra, &rb);
            snprintf(what, sizeof what, "cap lmin %g deg", k_grid_deg[k]);
            assert_near(a, ra, 1e-5 * ra, what);
            snprintf(what, sizeof what, "cap lmax %g deg", k_grid_deg[k]);
            assert_near(b, rb, 1e-5 * rb, what);
            /* arc */
            assert_int_equal(sfit_coverage_arc_eigs(th, (float)radii[j], &a, &b), SFIT_OK);
            ref_arc_eigs_numeric(thd > TU_PI ? TU_PI : thd, radii[j], &ra, &rb);
            snprintf(what, sizeof what, "arc lmin %g deg", k_grid_deg[k]);
            assert_near(a, ra, 1e-5 * ra, what);
            snprintf(what, sizeof what, "arc lmax %g deg", k_grid_deg[k]);
            assert_near(b, rb, 1e-5 * rb, what);
            /* the generic entry point is the same function */
            {
                float a2, b2;
                assert_int_equal(sfit_coverage_eigs(SFIT_COVERAGE_ARC, th, (float)radii[j],
                                                    &a2, &b2),
                                 SFIT_OK);
                assert_true(a2 == a && b2 == b);
            }
        }
    }
}

/* The chapter's printed eq. 212 / 213 (evaluated here in double, at angles
 * where the closed form of eq. 213 has no cancellation problem). */
static void test_max_sigma_printed_forms(void **state)
{
    const double grid[] = {20.0, 30.0, 45.0, 60.0, 90.0, 135.0, 180.0};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof grid / sizeof grid[0]; k++) {
        const float th = (float)(grid[k] * DEG);
        const double t = (double)th > TU_PI ? TU_PI : (double)th;
        const double r0 = 250.0;
        const double s = sin(t / 2.0);
        const double eq212 = r0 * s * s / sqrt(3.0);
        const double eq213 =
            r0 * sqrt(t * (2.0 * t + sin(2.0 * t)) - 4.0 * sin(t) * sin(t)) / (2.0 * t);
        float sm;
        assert_int_equal(sfit_coverage_max_sigma(SFIT_COVERAGE_CAP, th, (float)r0, &sm),
                         SFIT_OK);
        assert_near(sm, eq212, 1e-5 * eq212, "eq. 212");
        assert_int_equal(sfit_coverage_max_sigma(SFIT_COVERAGE_ARC, th, (float)r0, &sm),
                         SFIT_OK);
        assert_near(sm, eq213, 1e-5 * eq213, "eq. 213");
    }
}

/* lmin < lmax on (0, pi) for both kinds (no crossover: the axial / radial
 * eigenvalue always limits the trust), equal at pi; lmin increasing (the
 * bisections rely on it) and so is the ratio lmin / lmax. Dense grid. */
static void test_eigs_order_and_monotone(void **state)
{
    int k;
    int kind;
    (void)state;
    for (kind = 0; kind < 2; kind++) {
        float prev_min = 0.0f, prev_q = 0.0f;
        for (k = 1; k <= 3600; k++) {
            const float th = (float)(k * 0.05 * DEG);
            float a, b;
            assert_int_equal(sfit_coverage_eigs((sfit_coverage_kind_t)kind, th, 1.0f, &a, &b),
                             SFIT_OK);
            if (k < 3600) {
                assert_true(a < b);
            } else {
                assert_near(a, b, 1e-6, "lmin = lmax at pi");
            }
            assert_true(a >= prev_min);
            assert_true(a / b >= prev_q * (1.0f - 4.0f * FLT_EPSILON));
            prev_min = a;
            prev_q = a / b;
        }
    }
}

/* Sampled caps / arcs (noise-free, N = 1e5) vs the closed forms. The
 * sample variance along a direction has relative standard error
 * sqrt((kappa - 1) / N), kappa the kurtosis of the coordinate; these
 * coordinates are bounded with kappa <= 3, so 5 sqrt(2 / N) = 2.2 % is at
 * least 5 standard errors. */
static void test_eigs_vs_sampled(void **state)
{
    const double grid[] = {10.0, 45.0, 90.0, 150.0};
    const size_t n = NMAX;
    const double tol = 5.0 * sqrt(2.0 / (double)n);
    tu_rng_t g;
    size_t k;
    int arc;
    (void)state;
    tu_rng_seed(&g, 203u);
    for (arc = 0; arc < 2; arc++) {
        for (k = 0; k < sizeof grid / sizeof grid[0]; k++) {
            const double r = 100.0;
            const float th = (float)(grid[k] * DEG);
            double mean[3], C[3][3], S[3], w[3], v[3][3];
            float a, b;
            make_pts(&g, arc, n, r, (double)th, 0.0);
            assert_int_equal(ref_moments(REF_C3(g_pts), n, mean, C, S), 0);
            ref_sym3_eig(REF_C3(C), w, v);
            assert_int_equal(sfit_coverage_eigs(arc ? SFIT_COVERAGE_ARC : SFIT_COVERAGE_CAP, th,
                                                (float)r, &a, &b),
                             SFIT_OK);
            if (arc) {
                assert_near(w[0], 0.0, 1e-6 * r * r, "arc normal eigenvalue");
                assert_near(w[1], a, tol * (double)a, "sampled arc radial");
                assert_near(w[2], b, tol * (double)b, "sampled arc tangential");
            } else {
                assert_near(w[0], a, tol * (double)a, "sampled cap axial");
                assert_near(w[1], b, tol * (double)b, "sampled cap lateral 1");
                assert_near(w[2], b, tol * (double)b, "sampled cap lateral 2");
            }
        }
    }
}

/* -------------------------------------------------------------- inverses */

/* theta -> sigma_max -> min_theta, and theta -> eigenvalues ->
 * estimate_theta, for both kinds. Up to 170 deg the functions inverted
 * have slopes well away from 0 and the round trip holds to 2e-5 relative
 * (the float error of g, a few 1e-7, divided by its log-slope, >= 0.02 at
 * 170 deg). At 179 / 180 deg the slopes vanish (dg/dtheta -> 0 at pi), so
 * only 0.02 rad is asked there. */
static void test_inverse_round_trips(void **state)
{
    size_t k;
    int kind;
    (void)state;
    for (kind = 0; kind < 2; kind++) {
        const sfit_coverage_kind_t kd = (sfit_coverage_kind_t)kind;
        for (k = 0; k < sizeof k_grid_deg / sizeof k_grid_deg[0]; k++) {
            const float th = (float)(k_grid_deg[k] * DEG);
            const double tol = (k_grid_deg[k] <= 170.0) ? 2e-5 * (double)th : 0.02;
            float sm, th2, lmin, lmax, sm2;
            sfit_vec3_t eig;
            assert_int_equal(sfit_coverage_max_sigma(kd, th, 50.0f, &sm), SFIT_OK);
            assert_int_equal(sfit_coverage_min_theta(kd, sm / 50.0f, &th2), SFIT_OK);
            assert_near(th2, th, tol, "min_theta(max_sigma(theta))");
            /* at the returned angle the noise is tolerated (up to rounding) */
            assert_int_equal(sfit_coverage_max_sigma(kd, th2, 50.0f, &sm2), SFIT_OK);
            assert_true(sm2 >= sm * (1.0f - 1e-6f));
            assert_int_equal(sfit_coverage_eigs(kd, th, 7.0f, &lmin, &lmax), SFIT_OK);
            if (kd == SFIT_COVERAGE_CAP) {
                eig.v[0] = lmin;
                eig.v[1] = lmax;
                eig.v[2] = lmax;
            } else {
                eig.v[0] = 0.0f;
                eig.v[1] = lmin;
                eig.v[2] = lmax;
            }
            assert_int_equal(sfit_coverage_estimate_theta(kd, &eig, &th2), SFIT_OK);
            assert_near(th2, th, tol, "estimate_theta(eigs(theta))");
        }
    }
}

static void test_min_theta_limits(void **state)
{
    float th, th_prev = 0.0f;
    int k;
    (void)state;
    /* sigma = 0: any coverage will do */
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, 0.0f, &th), SFIT_OK);
    assert_true(th == 0.0f);
    /* no coverage suffices beyond r / sqrt(3) (cap) and r / sqrt(2) (arc) */
    th = -1.0f;
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, 0.5774f, &th), SFIT_E_RANGE);
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_ARC, 0.7072f, &th), SFIT_E_RANGE);
    assert_true(th == -1.0f);
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, 0.577f, &th), SFIT_OK);
    assert_true(th > 2.9f);
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_ARC, 0.707f, &th), SFIT_OK);
    assert_true(th > 2.9f);
    /* more noise needs more coverage */
    for (k = 1; k <= 50; k++) {
        assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, 0.01f * (float)k, &th),
                         SFIT_OK);
        assert_true(th > th_prev);
        th_prev = th;
    }
    /* a known value: sigma / r = 0.01 on a cap needs
     * sin^2(theta/2) = sqrt(3) 0.01, theta = 2 asin(sqrt(0.0173205)) */
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, 0.01f, &th), SFIT_OK);
    assert_near(th, 2.0 * asin(sqrt(sqrt(3.0) * 0.01)), 1e-5, "cap min theta at 1 %");
}

/* Coverage estimated from the library's own fit of sampled, noisy caps and
 * arcs (N = 20000, sigma = 1, r = 100), after removing sigma^2 from the
 * eigenvalues: within 2 % of the true half-angle. The eigenvalue ratio has a
 * relative sampling error of about sqrt(2 * 0.8 / N) ~ 0.9 %, theta about
 * half of that for small angles; 2 % is > 4 standard errors. Without the
 * noise removal the estimate is larger (noise inflates the small
 * eigenvalue), visibly so for the small cap. */
static void test_estimate_from_sampled_fit(void **state)
{
    const double grid[] = {15.0, 30.0, 60.0, 120.0};
    const size_t n = 20000u;
    tu_rng_t g;
    size_t k;
    int arc;
    (void)state;
    tu_rng_seed(&g, 212u);
    for (arc = 0; arc < 2; arc++) {
        for (k = 0; k < sizeof grid / sizeof grid[0]; k++) {
            const sfit_coverage_kind_t kd = arc ? SFIT_COVERAGE_ARC : SFIT_COVERAGE_CAP;
            sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
            sfit_result_t r;
            sfit_vec3_t eig;
            float th_raw, th;
            int i;
            cfg.mode = arc ? SFIT_MODE_PLANAR : SFIT_MODE_SPHERE;
            cfg.eigen = true; /* the coverage estimate needs the eigenvalues */
            make_pts(&g, arc, n, 100.0, grid[k] * DEG, 1.0);
            assert_int_equal(sfit_fit_points(g_fpts, n, &cfg, &r), SFIT_OK);
            assert_int_equal(sfit_coverage_estimate_theta(kd, &r.eigenvalues, &th_raw),
                             SFIT_OK);
            eig = r.eigenvalues;
            for (i = 0; i < 3; i++) {
                eig.v[i] -= 1.0f;
            }
            assert_int_equal(sfit_coverage_estimate_theta(kd, &eig, &th), SFIT_OK);
            assert_near(th, grid[k] * DEG, 0.02 * grid[k] * DEG, "estimated half-angle");
            assert_true(th_raw > th);
        }
    }
}

/* The documented ratios, against the closed-form inverse of the cap ratio
 * (q = s2 / (3 - 2 s2), s2 = sin^2(theta/2), so s2 = 3 q / (1 + 2 q)):
 * the cap uses lambda0 over the MEAN of the two lateral eigenvalues, the
 * arc lambda1 / lambda2 (lambda0, the out-of-plane noise, is ignored). */
static void test_estimate_documented_ratio(void **state)
{
    sfit_vec3_t eig = {{1.0f, 2.0f, 4.0f}}; /* q = 1 / 3 for the cap */
    float th, th2;
    (void)state;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, &th), SFIT_OK);
    assert_near(th, 2.0 * asin(sqrt(3.0 / 5.0)), 1e-5, "cap: lambda0 / mean(lambda1, lambda2)");
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_ARC, &eig, &th), SFIT_OK);
    eig.v[0] = 0.0f;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_ARC, &eig, &th2), SFIT_OK);
    assert_true(th == th2);
    {
        /* the arc ratio at that angle is lambda1 / lambda2 = 1/2 */
        float a, b;
        assert_int_equal(sfit_coverage_arc_eigs(th, 1.0f, &a, &b), SFIT_OK);
        assert_near(a / b, 0.5, 1e-5, "arc: lambda1 / lambda2");
    }
}

/* -------------------------------------------------------------- real data */

/* The hip recordings (tests/data/README.md): thigh markers in the pelvis
 * frame. The "equivalent uniform cap" half-angle from the eigenvalue ratio
 * is compared with the largest angle between a marker direction (from the
 * oracle's geometric-fit centre) and the mean direction, computed here in
 * double: a uniform cap of half-angle theta has that largest angle equal to
 * theta, and real motions (circumduction at the rim, soft tissue) spread
 * less evenly, so the estimate must lie below it but in the same range;
 * measured 0.73..0.87 of it (21..31 deg). RGT, 66 mm from the centre, is
 * noise-dominated (smallest eigenvalue 8 mm^2 against ~3 mm^2 of residual
 * noise: 37.7 deg estimated for 31 deg largest angle) and is only
 * reported. */
static void test_real_hip_coverage(void **state)
{
    const char *names[] = {"RTHI1", "RTHI2", "RTHI3", "RLFE", "RMFE", "RGT"};
    size_t k;
    (void)state;
    sfit_fit_cfg_t fc = sfit_fit_cfg_default;
    fc.eigen = true; /* the coverage estimate needs the eigenvalues */
    for (k = 0; k < sizeof names / sizeof names[0]; k++) {
        char path[512];
        size_t n = 0, i;
        sfit_result_t r;
        ref_fit_t rf;
        double c[3], rad, u[3] = {0.0, 0.0, 0.0}, un, maxang = 0.0;
        float th;
        snprintf(path, sizeof path, "%s/mocap/hip_right/%s.csv", SFIT_TEST_DATA_DIR, names[k]);
        assert_int_equal(tu_load_csv(path, g_pts, NMAX, &n), 0);
        assert_true(n > 1000u);
        for (i = 0; i < n; i++) {
            tc_to_vec3(g_pts[i], &g_fpts[i]);
        }
        assert_int_equal(sfit_fit_points(g_fpts, n, &fc, &r), SFIT_OK);
        assert_int_equal(r.mode, SFIT_MODE_SPHERE);
        assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &r.eigenvalues, &th),
                         SFIT_OK);
        /* oracle: geometric centre, then the angular spread about it */
        assert_int_equal(ref_fit_sphere(REF_C3(g_pts), n, NULL, &rf), 0);
        assert_int_equal(ref_fit_geometric(REF_C3(g_pts), n, rf.center, rf.radius, c, &rad,
                                           NULL),
                         0);
        for (i = 0; i < n; i++) {
            const double d = tu_dist3(g_pts[i], c);
            int j;
            for (j = 0; j < 3; j++) {
                u[j] += (g_pts[i][j] - c[j]) / d;
            }
        }
        un = tu_norm3(u);
        for (i = 0; i < n; i++) {
            const double d = tu_dist3(g_pts[i], c);
            double cs = 0.0, a;
            int j;
            for (j = 0; j < 3; j++) {
                cs += (g_pts[i][j] - c[j]) / d * u[j] / un;
            }
            a = acos(cs > 1.0 ? 1.0 : cs);
            if (a > maxang) {
                maxang = a;
            }
        }
        print_message("  %-6s estimated half-angle %.1f deg, largest angle %.1f deg "
                      "(ratio %.2f)\n",
                      names[k], (double)th / DEG, maxang / DEG, (double)th / maxang);
        if (k < 5u) {
            assert_true((double)th >= 20.0 * DEG && (double)th <= 40.0 * DEG);
            assert_true((double)th >= 0.6 * maxang && (double)th <= 1.0 * maxang);
        }
    }
}

/* ----------------------------------------------------------------- errors */

static void test_errors(void **state)
{
    const float nan = (float)NAN, inf = (float)INFINITY;
    sfit_vec3_t eig;
    float out = 123.0f, out2 = 456.0f;
    (void)state;

    /* eigenvalues / max sigma: theta in (0, pi], r > 0, finite */
    assert_int_equal(sfit_coverage_cap_eigs(0.0f, 1.0f, &out, &out2), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_cap_eigs(-0.1f, 1.0f, &out, &out2), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_cap_eigs(3.1416f, 1.0f, &out, &out2), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_arc_eigs(1.0f, 0.0f, &out, &out2), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_arc_eigs(1.0f, -2.0f, &out, &out2), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_arc_eigs(nan, 1.0f, &out, &out2), SFIT_E_NONFINITE);
    assert_int_equal(sfit_coverage_cap_eigs(1.0f, inf, &out, &out2), SFIT_E_NONFINITE);
    assert_int_equal(sfit_coverage_cap_eigs(1.0f, 1e30f, &out, &out2), SFIT_E_RANGE);
    assert_int_equal(sfit_coverage_eigs((sfit_coverage_kind_t)7, 1.0f, 1.0f, &out, &out2),
                     SFIT_E_ARG);
    assert_true(out == 123.0f && out2 == 456.0f);
    /* NULL outputs are allowed for the eigenvalues */
    assert_int_equal(sfit_coverage_cap_eigs(1.0f, 1.0f, NULL, NULL), SFIT_OK);
    /* theta = (float)pi, just above pi, is accepted */
    assert_int_equal(sfit_coverage_cap_eigs(3.14159265f, 1.0f, NULL, NULL), SFIT_OK);
    assert_int_equal(sfit_coverage_max_sigma(SFIT_COVERAGE_CAP, 1.0f, 1.0f, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_max_sigma(SFIT_COVERAGE_CAP, 4.0f, 1.0f, &out), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_max_sigma(SFIT_COVERAGE_ARC, 1.0f, nan, &out),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_coverage_max_sigma((sfit_coverage_kind_t)-1, 1.0f, 1.0f, &out),
                     SFIT_E_ARG);
    assert_true(out == 123.0f);
    /* a huge radius is fine for max sigma (no r^2) */
    assert_int_equal(sfit_coverage_max_sigma(SFIT_COVERAGE_CAP, 1.0f, 1e30f, &out), SFIT_OK);
    assert_true(out > 0.0f && out < 1e30f);
    out = 123.0f;

    /* min theta */
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, -0.1f, &out), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_CAP, nan, &out), SFIT_E_NONFINITE);
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_ARC, inf, &out), SFIT_E_NONFINITE);
    assert_int_equal(sfit_coverage_min_theta(SFIT_COVERAGE_ARC, 0.1f, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_min_theta((sfit_coverage_kind_t)2, 0.1f, &out), SFIT_E_ARG);
    assert_true(out == 123.0f);

    /* estimate theta */
    eig.v[0] = 1.0f;
    eig.v[1] = 2.0f;
    eig.v[2] = 3.0f;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, NULL, &out), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_coverage_estimate_theta((sfit_coverage_kind_t)9, &eig, &out),
                     SFIT_E_ARG);
    eig.v[1] = 0.5f; /* not ascending */
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, &out), SFIT_E_ARG);
    eig.v[1] = nan;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_ARC, &eig, &out),
                     SFIT_E_NONFINITE);
    eig.v[0] = -3.0f;
    eig.v[1] = -2.0f;
    eig.v[2] = -1.0f; /* lambda2 <= 0 */
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, &out), SFIT_E_ARG);
    eig.v[0] = -0.5f; /* axial eigenvalue below the noise that was removed */
    eig.v[1] = 2.0f;
    eig.v[2] = 3.0f;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, &out),
                     SFIT_E_DEGENERATE);
    eig.v[1] = 0.0f;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_ARC, &eig, &out),
                     SFIT_E_DEGENERATE);
    assert_true(out == 123.0f);
    /* equal eigenvalues: the whole sphere */
    eig.v[0] = 2.0f;
    eig.v[1] = 2.0f;
    eig.v[2] = 2.0f;
    assert_int_equal(sfit_coverage_estimate_theta(SFIT_COVERAGE_CAP, &eig, &out), SFIT_OK);
    assert_near(out, TU_PI, 1e-6, "full sphere");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_eigs_vs_quadrature),
        cmocka_unit_test(test_max_sigma_printed_forms),
        cmocka_unit_test(test_eigs_order_and_monotone),
        cmocka_unit_test(test_eigs_vs_sampled),
        cmocka_unit_test(test_inverse_round_trips),
        cmocka_unit_test(test_min_theta_limits),
        cmocka_unit_test(test_estimate_from_sampled_fit),
        cmocka_unit_test(test_estimate_documented_ratio),
        cmocka_unit_test(test_real_hip_coverage),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests_name("coverage", tests, NULL, NULL);
}
