/* SPDX-License-Identifier: MIT */
/**
 * @file test_uncert.c
 * @brief Centre covariance / radius variance: the first-order formulas
 * against the double Cramer-Rao oracle (same points, same centre), and the
 * reported covariance against the Monte Carlo covariance (must-show 2).
 *
 * "rho" is the trust ratio sigma^2 / lambda_min(C) (C of the noisy samples).
 */
#include "test_cmocka.h"

#include "sfit/sfit_refine.h"
#include "sfit/sfit_selfcal.h"
#include "sfit/sfit_uncert.h"
#include "sfit_ref.h"

#define NMAX 1000

static double g_xt[NMAX][3], g_xn[NMAX][3];
static sfit_vec3_t g_pf[NMAX];
static const double k_c[3] = {1200.0, -800.0, 300.0};
static const double k_axis[3] = {0.3, -0.5, 0.8};
#define K_R 100.0

static void gen(tu_rng_t *g, double theta, double sigma, int n)
{
    int i, k;
    for (i = 0; i < n; i++) {
        tu_sample_cap(g, k_c, K_R, k_axis, theta, 0.0, g_xt[i]);
        for (k = 0; k < 3; k++) {
            g_xn[i][k] = g_xt[i][k] + sigma * tu_rng_gauss(g);
        }
        tc_to_vec3(g_xn[i], &g_pf[i]);
        tc_to_double3(&g_pf[i], g_xn[i]);
    }
}

static double trace3(const sfit_mat3_t *p)
{
    return (double)p->m[0] + (double)p->m[4] + (double)p->m[8];
}

/* sigma^2 (J^T J)^-1 at given points and centre: the oracle computes the
 * same quantity (ref_crlb_sphere with the points as "true" positions). */
static void test_points_vs_oracle(void **state)
{
    const sfit_vec3_t cf = {{1201.0f, -799.5f, 299.0f}};
    double cd[3], cr[4][4];
    sfit_uncert_t u;
    tu_rng_t g;
    int i, j;
    (void)state;
    tu_rng_seed(&g, 41u);
    gen(&g, 40.0 * TU_PI / 180.0, 1.0, 500);
    tc_to_double3(&cf, cd);
    assert_int_equal(sfit_uncert_points(g_pf, 500, &cf, 100.0f, 2.0f, &u), SFIT_OK);
    ref_crlb_sphere(REF_C3(g_xn), 500, cd, 100.0, 2.0, cr);
    /* float sums of unit vectors, centred: ~1e-6 relative, amplified by the
     * cap's condition number (~40): 1e-3 relative */
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            assert_near(u.center_cov.m[3 * i + j], cr[i][j], 1e-3 * cr[i][i], "cov_c");
        }
        assert_near(u.center_radius_cov[i], cr[i][3], 1e-3 * sqrt(cr[i][i] * cr[3][3]), "cov_cr");
    }
    assert_near(u.radius_var, cr[3][3], 1e-3 * cr[3][3], "var_r");
    assert_true(u.noise_var == 2.0f);
}

/* From moments, on noise-free samples with a tiny sigma^2 the second-order
 * terms vanish and the first order is exactly the CRLB (u = (x - c)/r
 * holds exactly on the sphere). */
static void test_moments_first_order(void **state)
{
    const float s2 = 1e-4f;
    double cr[4][4];
    sfit_moments_t m;
    sfit_uncert_t u;
    sfit_vec3_t cf;
    tu_rng_t g;
    int i, j;
    (void)state;
    tu_rng_seed(&g, 42u);
    gen(&g, 50.0 * TU_PI / 180.0, 0.0, 400);
    tc_to_vec3(k_c, &cf);
    (void)sfit_moments_init(&m);
    assert_int_equal(sfit_moments_add_block(&m, g_pf, 400, NULL), SFIT_OK);
    assert_int_equal(sfit_uncert_moments(&m, &cf, 100.0f, s2, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_OK);
    ref_crlb_sphere(REF_C3(g_xn), 400, k_c, K_R, (double)s2, cr);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            assert_near(u.center_cov.m[3 * i + j], cr[i][j], 2e-3 * cr[i][i], "cov_c moments");
        }
        assert_near(u.center_radius_cov[i], cr[i][3], 2e-3 * sqrt(cr[i][i] * cr[3][3]),
                    "cov_cr moments");
    }
    assert_near(u.radius_var, cr[3][3], 2e-3 * cr[3][3], "var_r moments");
}

/* Must-show 2: mean reported trace / Monte Carlo covariance trace in
 * [0.8, 1.2]. The MC trace (dominated by the cap axis) has relative SE
 * ~ sqrt(2/T): 3.2 % for T = 2000, 4.5 % for T = 1000. Measured ratios
 * (several seeds) are in the calls; the worst is 2.5 SE inside the band. */
typedef struct mc_acc {
    double s[3], ss[3][3], rep;
    int n;
} mc_acc_t;

static void mc_add(mc_acc_t *a, const sfit_vec3_t *c, const sfit_uncert_t *u)
{
    int i, j;
    for (i = 0; i < 3; i++) {
        a->s[i] += (double)c->v[i] - k_c[i];
        for (j = 0; j < 3; j++) {
            a->ss[i][j] += ((double)c->v[i] - k_c[i]) * ((double)c->v[j] - k_c[j]);
        }
    }
    a->rep += trace3(&u->center_cov);
    a->n++;
}

static double mc_ratio(const mc_acc_t *a)
{
    double tr = 0.0;
    int i;
    for (i = 0; i < 3; i++) {
        tr += (a->ss[i][i] - a->s[i] * a->s[i] / a->n) / (a->n - 1);
    }
    return (a->rep / a->n) / tr;
}

static void coverage(double theta_deg, double rho, int n, int trials, uint64_t seed)
{
    const double theta = theta_deg * TU_PI / 180.0;
    double lmin, lmax, s2, rs, rr, rk;
    mc_acc_t asc, arf, akn;
    sfit_fit_cfg_t kcfg = sfit_fit_cfg_default;
    tu_rng_t g;
    int t;
    ref_cap_eigs_numeric(theta, K_R, &lmin, &lmax);
    s2 = rho / (1.0 - rho) * lmin;
    memset(&asc, 0, sizeof asc);
    memset(&arf, 0, sizeof arf);
    memset(&akn, 0, sizeof akn);
    kcfg.mode = SFIT_MODE_SPHERE;
    kcfg.noise = SFIT_NOISE_ISO;
    kcfg.noise_var = (float)s2;
    tu_rng_seed(&g, seed);
    for (t = 0; t < trials; t++) {
        sfit_moments_t m;
        sfit_selfcal_result_t sc;
        sfit_refine_result_t rf;
        sfit_result_t kn;
        sfit_uncert_t u;
        gen(&g, theta, sqrt(s2), n);
        (void)sfit_moments_init(&m);
        assert_int_equal(sfit_moments_add_block(&m, g_pf, (size_t)n, NULL), SFIT_OK);
        assert_int_equal(sfit_selfcal_points(g_pf, (size_t)n, NULL, &sc), SFIT_OK);
        assert_int_equal(sfit_uncert_moments(&m, &sc.fit.center, sc.fit.radius, sc.noise_var,
                                             SFIT_UNCERT_NOISE_ESTIMATED, &u),
                         SFIT_OK);
        mc_add(&asc, &sc.fit.center, &u);
        assert_int_equal(sfit_refine_points(g_pf, (size_t)n, &sc.fit.center, NULL, &rf), SFIT_OK);
        assert_int_equal(sfit_uncert_geometric(g_pf, (size_t)n, &rf.center, &u), SFIT_OK);
        mc_add(&arf, &rf.center, &u);
        assert_int_equal(sfit_fit_moments(&m, &kcfg, &kn), SFIT_OK);
        assert_int_equal(sfit_uncert_moments(&m, &kn.center, kn.radius, (float)s2,
                                             SFIT_UNCERT_NOISE_KNOWN, &u),
                         SFIT_OK);
        mc_add(&akn, &kn.center, &u);
    }
    rs = mc_ratio(&asc);
    rr = mc_ratio(&arf);
    rk = mc_ratio(&akn);
    print_message("coverage: theta %.0f rho %.2f N %d T %d: reported/MC trace: selfcal %.3f "
                  "refined %.3f known-sigma UGDK %.3f\n",
                  theta_deg, rho, n, trials, rs, rr, rk);
    assert_near(rs, 1.0, 0.2, "selfcal cov trace / MC");
    assert_near(rr, 1.0, 0.2, "refined cov trace / MC");
    assert_near(rk, 1.0, 0.2, "known-sigma cov trace / MC");
}

static void test_mc_rho01(void **state)
{
    (void)state;
    /* measured (selfcal / refined / known sigma) 0.99 / 1.01 / 0.98 (cap)
     * and 1.01 / 1.07 / 1.01 (hemisphere); other seeds within +-0.08 */
    coverage(35.0, 0.1, 100, 2000, 51u);
    coverage(90.0, 0.1, 100, 2000, 52u);
    /* whole sphere: sigma / r = 0.19, the largest noise at rho = 0.1 */
    coverage(180.0, 0.1, 100, 2000, 54u);
}

static void test_mc_rho03(void **state)
{
    (void)state;
    /* measured 0.93-1.06 / 0.95-1.08 / 0.93-1.03 over seeds. The known-sigma
     * case needs the second-order term: first order alone would report
     * ~1/(1 + 2 sigma^2/lambda0) = 0.54 of the MC trace here */
    coverage(35.0, 0.3, 1000, 1000, 53u);
    /* wide coverage, large noise: sigma / r = 0.19 (hemisphere) and 0.38
     * (whole sphere). The refined fit's moments-formula covariance was
     * 1.32x the MC trace on the hemisphere; the sandwich is not. */
    coverage(90.0, 0.3, 1000, 1000, 55u);
    coverage(180.0, 0.3, 1000, 1000, 56u);
}

/* The sandwich against the double oracle (full 4x4, not profiled) on the
 * same float samples, far-offset centre, sigma / r = 0.05. */
static void test_geometric_vs_oracle(void **state)
{
    sfit_selfcal_result_t sc;
    sfit_refine_result_t rf;
    sfit_uncert_t u;
    double cd[3], cr[4][4];
    tu_rng_t g;
    int i, j;
    (void)state;
    tu_rng_seed(&g, 44u);
    gen(&g, 70.0 * TU_PI / 180.0, 5.0, 600);
    assert_int_equal(sfit_selfcal_points(g_pf, 600, NULL, &sc), SFIT_OK);
    assert_int_equal(sfit_refine_points(g_pf, 600, &sc.fit.center, NULL, &rf), SFIT_OK);
    assert_int_equal(sfit_uncert_geometric(g_pf, 600, &rf.center, &u), SFIT_OK);
    tc_to_double3(&rf.center, cd);
    assert_int_equal(ref_sandwich_geometric(REF_C3(g_xn), 600, cd, cr), 0);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            assert_near(u.center_cov.m[3 * i + j], cr[i][j], 1e-3 * sqrt(cr[i][i] * cr[j][j]),
                        "sandwich cov_c");
        }
        assert_near(u.center_radius_cov[i], cr[i][3], 1e-3 * sqrt(cr[i][i] * cr[3][3]),
                    "sandwich cov_cr");
    }
    assert_near(u.radius_var, cr[3][3], 1e-3 * cr[3][3], "sandwich var_r");
    /* noise_var is the residual variance the sandwich used */
    assert_near(u.noise_var, (double)rf.rms * (double)rf.rms * 600.0 / 596.0, 1e-3 * (double)u.noise_var,
                "sandwich s^2");
    /* with the same s^2 it exceeds the first-order s^2 Mu^-1 at the same
     * centre: the curvature term H2 = sum f (I - u u^T)/d is negative on
     * balance (samples outside the sphere have f > 0 and larger d), so
     * A = Mu + H2 < Mu. A sign error in H2 would fail this. */
    {
        sfit_uncert_t f;
        assert_int_equal(sfit_uncert_points(g_pf, 600, &rf.center, rf.radius, u.noise_var, &f),
                         SFIT_OK);
        assert_true(trace3(&u.center_cov) > trace3(&f.center_cov));
    }
}

/* Exact data: zero covariance, finite; a centre that is not a minimum of
 * the geometric cost: NOT_POSDEF. */
static void test_geometric_edges(void **state)
{
    static const sfit_vec3_t centre_on_data = {{1200.0f, -800.0f, 390.0f}};
    sfit_uncert_t u;
    sfit_vec3_t cf;
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 45u);
    gen(&g, TU_PI, 0.0, 200);
    tc_to_vec3(k_c, &cf);
    assert_int_equal(sfit_uncert_geometric(g_pf, 200, &cf, &u), SFIT_OK);
    assert_true(trace3(&u.center_cov) < 1e-8 && u.radius_var >= 0.0f && u.radius_var < 1e-8f);
    /* 90 % of the way to the surface: the nearby samples make the Hessian
     * indefinite */
    assert_int_equal(sfit_uncert_geometric(g_pf, 200, &centre_on_data, &u), SFIT_E_NOT_POSDEF);
}

static void test_contract(void **state)
{
    sfit_moments_t m;
    sfit_uncert_t u, sentinel;
    const sfit_vec3_t c = {{0.0f, 0.0f, 0.0f}}, cbad = {{NAN, 0.0f, 0.0f}};
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 43u);
    gen(&g, 60.0 * TU_PI / 180.0, 0.5, 100);
    (void)sfit_moments_init(&m);
    memset(&sentinel, 0x3C, sizeof sentinel);
    u = sentinel;
    assert_int_equal(sfit_uncert_moments(&m, &c, 1.0f, 1.0f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_TOO_FEW);
    (void)sfit_moments_add_block(&m, g_pf, 100, NULL);
    assert_int_equal(sfit_uncert_moments(NULL, &c, 1.0f, 1.0f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_moments(&m, &c, -1.0f, 1.0f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_moments(&m, &c, 1.0f, -1.0f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_moments(&m, &cbad, 1.0f, 1.0f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_moments(&m, &c, NAN, 1.0f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_moments(&m, &c, 1.0f, INFINITY, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_moments(&m, &c, 1.0f, 1.0f, (sfit_uncert_noise_t)7, &u),
                     SFIT_E_ARG);
    /* sigma^2 above lambda_min(C): C - sigma^2 I not PD */
    assert_int_equal(sfit_uncert_moments(&m, &c, 100.0f, 1e6f, SFIT_UNCERT_NOISE_KNOWN, &u),
                     SFIT_E_NOT_POSDEF);
    /* a corrupted accumulator (enough samples, a non-finite origin): its
     * statistics are not finite, SFIT_E_RANGE as sfit_moments_stats() says
     * (the mean and C were read unwritten before: valgrind) */
    {
        sfit_moments_t bad = m;
        bad.origin[0] = INFINITY;
        assert_int_equal(sfit_uncert_moments(&bad, &c, 100.0f, 0.25f, SFIT_UNCERT_NOISE_KNOWN,
                                             &u),
                         SFIT_E_RANGE);
        bad = m;
        bad.tot.m2[0] = NAN;
        assert_int_equal(sfit_uncert_moments(&bad, &c, 100.0f, 0.25f,
                                             SFIT_UNCERT_NOISE_ESTIMATED, &u),
                         SFIT_E_RANGE);
    }
    assert_int_equal(sfit_uncert_points(g_pf, 3, &c, 1.0f, 1.0f, &u), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_uncert_points(g_pf, 100, &c, 0.0f, 1.0f, &u), SFIT_E_ARG);
    g_pf[9] = c;
    assert_int_equal(sfit_uncert_points(g_pf, 100, &c, 1.0f, 1.0f, &u), SFIT_E_DEGENERATE);
    g_pf[9].v[0] = NAN;
    assert_int_equal(sfit_uncert_points(g_pf, 100, &c, 1.0f, 1.0f, &u), SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_geometric(g_pf, 100, &c, &u), SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_geometric(NULL, 100, &c, &u), SFIT_E_ARG);
    assert_int_equal(sfit_uncert_geometric(g_pf, 100, NULL, &u), SFIT_E_ARG);
    assert_int_equal(sfit_uncert_geometric(g_pf, 100, &c, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_uncert_geometric(g_pf, 100, &cbad, &u), SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_geometric(g_pf, 4, &c, &u), SFIT_E_TOO_FEW);
    g_pf[9] = c;
    assert_int_equal(sfit_uncert_geometric(g_pf, 100, &c, &u), SFIT_E_DEGENERATE);
    assert_memory_equal(&u, &sentinel, sizeof u);
}

/* The self-calibrated sandwich against the double oracle (5 x 5 stacked
 * estimating equations, numerical Jacobian, not eliminated) on the same
 * float samples: a 70-degree cap at sigma / r = 0.05 and the whole sphere
 * at sigma / r = 0.38 (N = 100). */
static void selfcal_vs_oracle(double theta_deg, double sigma, int n, uint64_t seed)
{
    sfit_selfcal_result_t sc;
    sfit_uncert_t u;
    double cd[3], cr[3][3];
    tu_rng_t g;
    int i, j;
    tu_rng_seed(&g, seed);
    gen(&g, theta_deg * TU_PI / 180.0, sigma, n);
    assert_int_equal(sfit_selfcal_points(g_pf, (size_t)n, NULL, &sc), SFIT_OK);
    assert_int_equal(sfit_uncert_selfcal(g_pf, (size_t)n, &sc.fit.center, sc.fit.radius,
                                         sc.noise_var, &u),
                     SFIT_OK);
    tc_to_double3(&sc.fit.center, cd);
    assert_int_equal(ref_sandwich_selfcal(REF_C3(g_xn), (size_t)n, cd, (double)sc.fit.radius,
                                          (double)sc.noise_var, cr),
                     0);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            assert_near(u.center_cov.m[3 * i + j], cr[i][j], 2e-3 * sqrt(cr[i][i] * cr[j][j]),
                        "selfcal sandwich cov_c");
        }
    }
    assert_true(u.noise_var == sc.noise_var);
}

static void test_selfcal_vs_oracle(void **state)
{
    (void)state;
    selfcal_vs_oracle(70.0, 5.0, 600, 61u);
    selfcal_vs_oracle(180.0, 38.0, 100, 62u);
    selfcal_vs_oracle(30.0, 0.5, 1000, 63u);
}

/* Must-show 3 of issue 14: the self-calibrated sandwich is within 20 % of
 * the Monte Carlo covariance trace of the unflagged results, including
 * sigma / r = 0.38, N = 100 (the moments formula gave 1.23 there). The MC
 * trace's own relative SE is about sqrt(2/(3 T)) (< 3 % here), so the 20 %
 * band is more than 4 SE wide.
 *
 * Since issue 28 the reported covariance is the sandwich widened by
 * f = 1 + K (v / r^2) sqrt(96 / (N - 4)) (docs/coverage.md rule 7, K =
 * REF_COV_WIDEN_K), and issue 28 sets the bound for it: "where the
 * covariance is widened it may be up to 1.5 times the Monte Carlo
 * covariance (never below 0.9 times anywhere)". So both are checked: the
 * sandwich before the widening (reported / f, f computed here from the
 * fit's v and r) within 20 % (issue 14), and the reported, widened one in
 * 0.9-1.5 (issue 28). Measured (seeds below; K = 3.5), unwidened /
 * widened: 0.911 / 1.287 (sigma/r 0.38, N 100, 550 unflagged), 1.112 /
 * 1.152, 1.040 / 1.042, 0.993 / 0.995. */
static double selfcal_mc(double theta_deg, double sr, int n, int trials, uint64_t seed)
{
    mc_acc_t a;
    tu_rng_t g;
    int t, flagged = 0;
    double q, q0, rep0 = 0.0;
    memset(&a, 0, sizeof a);
    tu_rng_seed(&g, seed);
    for (t = 0; t < trials; t++) {
        sfit_selfcal_result_t sc;
        sfit_uncert_t u;
        double f;
        gen(&g, theta_deg * TU_PI / 180.0, sr * K_R, n);
        assert_int_equal(sfit_selfcal_points(g_pf, (size_t)n, NULL, &sc), SFIT_OK);
        if (sc.fit.flags & SFIT_FLAG_UNTRUSTED) {
            flagged++;
            continue;
        }
        assert_int_equal(sfit_uncert_selfcal(g_pf, (size_t)n, &sc.fit.center,
                                             sc.fit.radius, sc.noise_var, &u),
                         SFIT_OK);
        mc_add(&a, &sc.fit.center, &u);
        f = 1.0 + REF_COV_WIDEN_K * ((double)sc.noise_var
                                     / ((double)sc.fit.radius * (double)sc.fit.radius))
                      * sqrt(96.0 / (double)((n > 14) ? n - 4 : 10));
        assert_true(f >= 1.0);
        rep0 += trace3(&u.center_cov) / f;
    }
    q = mc_ratio(&a);
    q0 = q * rep0 / a.rep; /* the same MC trace, the unwidened sandwich */
    print_message("selfcal sandwich: cap %.0f sigma/r %.3f N %d: %d unflagged of %d, "
                  "reported/MC trace %.3f (before the widening of rule 7: %.3f)\n",
                  theta_deg, sr, n, a.n, trials, q, q0);
    /* enough unflagged results for the MC trace (relative SE <= 5 %); at
     * sigma / r = 0.38, N = 100 the trust rule flags ~63 % (the reported
     * trust ratio scatters around 0.37 against SFIT_COV_MAX_TRUST) */
    assert_true(a.n >= 300);
    assert_near(q0, 1.0, 0.2, "selfcal sandwich (unwidened) trace / MC");
    assert_true(q >= 0.9 && q <= 1.5); /* issue 28: widened, 0.9-1.5 x MC */
    return q;
}

static void test_selfcal_mc(void **state)
{
    (void)state;
    selfcal_mc(180.0, 0.38, 100, 1500, 71u);
    selfcal_mc(90.0, 0.1, 100, 1500, 72u);
    selfcal_mc(30.0, 0.02, 100, 1500, 73u);
    selfcal_mc(60.0, 0.05, 1000, 400, 74u);
}

static void test_selfcal_contract(void **state)
{
    sfit_uncert_t u, sentinel;
    sfit_selfcal_result_t sc;
    const sfit_vec3_t cbad = {{NAN, 0.0f, 0.0f}};
    tu_rng_t g;
    (void)state;
    tu_rng_seed(&g, 75u);
    gen(&g, 60.0 * TU_PI / 180.0, 2.0, 100);
    assert_int_equal(sfit_selfcal_points(g_pf, 100, NULL, &sc), SFIT_OK);
    memset(&sentinel, 0x3C, sizeof sentinel);
    u = sentinel;
    assert_int_equal(sfit_uncert_selfcal(NULL, 100, &sc.fit.center, 100.0f, 4.0f, &u),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, NULL, 100.0f, 4.0f, &u), SFIT_E_ARG);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 100.0f, 4.0f, NULL),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 0.0f, 4.0f, &u),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 100.0f, -1.0f, &u),
                     SFIT_E_ARG);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &cbad, 100.0f, 4.0f, &u),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 100.0f, NAN, &u),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_uncert_selfcal(g_pf, 13, &sc.fit.center, 100.0f, 4.0f, &u),
                     SFIT_E_TOO_FEW);
    /* sigma^2 above lambda_min(C): C - sigma^2 I not positive definite */
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, sc.fit.radius,
                                         sc.fit.eigenvalues.v[0] * 1.5f, &u),
                     SFIT_E_NOT_POSDEF);
    g_pf[9].v[1] = 1e30f;
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 100.0f, 4.0f, &u),
                     SFIT_E_RANGE);
    g_pf[9] = sc.fit.center;
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 100.0f, 4.0f, &u),
                     SFIT_E_DEGENERATE);
    g_pf[9].v[0] = NAN;
    assert_int_equal(sfit_uncert_selfcal(g_pf, 100, &sc.fit.center, 100.0f, 4.0f, &u),
                     SFIT_E_NONFINITE);
    assert_memory_equal(&u, &sentinel, sizeof u);
}

/* Issue 14, must-show 1 on a fixed-seed subset (tools/montecarlo/coverage.c
 * runs the full table): the fraction of unflagged OK results whose true
 * centre lies inside the reported 95 % ellipsoid (chi-square, 3 dof,
 * 7.815) is in 92-98 %, widened by 3 binomial SE at the trials run, for
 * UGDK with the true sigma^2, self-calibrated (sandwich) and refined. */
static void cover_add(int *in, int *tot, const sfit_vec3_t *c, const sfit_mat3_t *p)
{
    double e[3];
    int k;
    for (k = 0; k < 3; k++) {
        e[k] = (double)c->v[k] - k_c[k];
    }
    {
        const double d2 = tu_mahal(p->m, e);
        assert_true(d2 >= 0.0);
        *in += d2 <= 7.8147279;
    }
    (*tot)++;
}

static void coverage_subset(double theta_deg, double sr, int n, int trials, uint64_t seed)
{
    int in[3] = {0, 0, 0}, tot[3] = {0, 0, 0}, e, t;
    sfit_fit_cfg_t kc = sfit_fit_cfg_default;
    tu_rng_t g;
    tu_rng_seed(&g, seed);
    kc.mode = SFIT_MODE_SPHERE;
    kc.noise = SFIT_NOISE_ISO;
    kc.noise_var = (float)(sr * K_R * sr * K_R);
    for (t = 0; t < trials; t++) {
        sfit_moments_t m;
        sfit_result_t k;
        sfit_selfcal_result_t sc;
        sfit_refine_result_t rf;
        sfit_uncert_t u;
        gen(&g, theta_deg * TU_PI / 180.0, sr * K_R, n);
        (void)sfit_moments_init(&m);
        assert_int_equal(sfit_moments_add_block(&m, g_pf, (size_t)n, NULL), SFIT_OK);
        assert_int_equal(sfit_fit_moments(&m, &kc, &k), SFIT_OK);
        if (!(k.flags & SFIT_FLAG_UNTRUSTED)) {
            assert_int_equal(sfit_uncert_moments(&m, &k.center, k.radius, kc.noise_var,
                                                 SFIT_UNCERT_NOISE_KNOWN, &u),
                             SFIT_OK);
            cover_add(&in[0], &tot[0], &k.center, &u.center_cov);
        }
        assert_int_equal(sfit_selfcal_points(g_pf, (size_t)n, NULL, &sc), SFIT_OK);
        if (!(sc.fit.flags & SFIT_FLAG_UNTRUSTED)) {
            assert_int_equal(sfit_uncert_selfcal(g_pf, (size_t)n, &sc.fit.center,
                                                 sc.fit.radius, sc.noise_var, &u),
                             SFIT_OK);
            cover_add(&in[1], &tot[1], &sc.fit.center, &u.center_cov);
        }
        assert_int_equal(sfit_refine_fit(g_pf, (size_t)n, NULL, &rf), SFIT_OK);
        if (!(rf.flags & SFIT_FLAG_UNTRUSTED)) {
            cover_add(&in[2], &tot[2], &rf.center, &rf.center_cov);
        }
    }
    for (e = 0; e < 3; e++) {
        const double cv = (double)in[e] / (double)tot[e];
        const double se = sqrt(0.95 * 0.05 / (double)tot[e]);
        print_message("coverage: cap %.0f sigma/r %.3f N %d: %s %d unflagged of %d, "
                      "coverage %.3f (band 0.92-0.98 +- %.3f)\n",
                      theta_deg, sr, n, e == 0 ? "ugdk" : (e == 1 ? "selfcal" : "refined"),
                      tot[e], trials, cv, 3.0 * se);
        assert_true(tot[e] >= trials * 99 / 100); /* trust <= 0.1, N >= 100: <= 1 % flagged */
        assert_true(cv >= 0.92 - 3.0 * se && cv <= 0.98 + 3.0 * se);
    }
}

static void test_coverage_subset(void **state)
{
    (void)state;
    coverage_subset(90.0, 0.1, 100, 800, 81u);
    coverage_subset(180.0, 0.05, 100, 800, 82u);
    coverage_subset(45.0, 0.02, 100, 800, 83u);
    coverage_subset(30.0, 0.005, 1000, 300, 84u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_points_vs_oracle),
        cmocka_unit_test(test_moments_first_order),
        cmocka_unit_test(test_mc_rho01),
        cmocka_unit_test(test_mc_rho03),
        cmocka_unit_test(test_geometric_vs_oracle),
        cmocka_unit_test(test_geometric_edges),
        cmocka_unit_test(test_contract),
        cmocka_unit_test(test_selfcal_vs_oracle),
        cmocka_unit_test(test_selfcal_mc),
        cmocka_unit_test(test_selfcal_contract),
        cmocka_unit_test(test_coverage_subset),
    };
    return cmocka_run_group_tests_name("uncert", tests, NULL, NULL);
}
