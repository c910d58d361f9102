/* SPDX-License-Identifier: MIT */
/**
 * @file test_validation.c
 * @brief CI-sized subset of the statistical validation (docs/validation.md,
 * tools/montecarlo): UGDK against the Cramer-Rao lower bound, UGDK's
 * residual bias, GDKE's cap bias against rho r (1 + cos theta)/2, and the
 * double-precision ML fit against the same bound (a check of the oracle the
 * full harness uses). Fixed seeds; a few seconds.
 *
 * Samples: uniform on a cap of half-angle theta of a sphere of r = 100 mm
 * centred far from the origin, isotropic Gaussian noise sigma, rounded to
 * float once (library and oracle see the same numbers).
 *
 * rho = sigma^2 / (lambda_min(C0) + sigma^2) = rho(C^-1 Sigma) with C the
 * covariance of the noisy samples (the library's trust_ratio);
 * lambda_min(C0) = r^2 sin^4(theta/2)/3 for a cap, r^2/3 for the sphere.
 *
 * The bound: the CRLB of the centre given the true sample positions
 * (ref_crlb_sphere). Positions are random, so each trial has its own bound;
 * for an (essentially) unbiased estimator E|c_hat - c0|^2 >= E tr CRLB_c,
 * so the RMSE over the trials is compared with sqrt(mean tr CRLB_c).
 */
#include "test_cmocka.h"

#include <string.h>

#include "sfit_ref.h"

#define NMAX 10000
#define R0 100.0
static double g_true[NMAX][3];
static double g_x[NMAX][3];
static sfit_vec3_t g_f[NMAX];

static const double k_c0[3] = {2100.0, -1500.0, 900.0}; /* |c0| = 2731 mm */
static const double k_axis[3] = {0.267261241912424, 0.534522483824849, 0.801783725737273};

#define DEG (TU_PI / 180.0)

static double lmin0(double theta)
{
    const double s = sin(theta / 2.0);
    return theta >= TU_PI ? R0 * R0 / 3.0 : R0 * R0 * s * s * s * s / 3.0;
}

static void draw(tu_rng_t *g, size_t n, double theta, double sigma)
{
    size_t i;
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_cap(g, k_c0, R0, k_axis, theta, 0.0, g_true[i]);
        memcpy(p, g_true[i], sizeof p);
        tu_add_noise(g, sigma, p);
        tc_to_vec3(p, &g_f[i]);
        tc_to_double3(&g_f[i], g_x[i]);
    }
}

static sfit_fit_cfg_t cfg_for(double sigma2)
{
    sfit_fit_cfg_t c = sfit_fit_cfg_default;
    c.mode = SFIT_MODE_SPHERE;
    if (sigma2 > 0.0) {
        c.noise = SFIT_NOISE_ISO;
        c.noise_var = (float)sigma2;
    }
    return c;
}

/* Monte Carlo summary of one estimator. */
typedef struct {
    double s_ax, s_ax2;       /* axial error */
    double s_l1, s_l1_2;      /* one lateral error */
    double sa, sa2, sb, sb2, sab; /* a = |e|^2, b = tr CRLB_c */
    double strust;
    int n;
} mc_t;

static void mc_add(mc_t *m, const double c[3], double crlb_tr, double trust)
{
    double e[3], n[3], e1[3], e2[3], ax, l1, a;
    int k;
    for (k = 0; k < 3; k++) {
        e[k] = c[k] - k_c0[k];
    }
    tu_frame(k_axis, n, e1, e2);
    ax = tu_dot3(e, n);
    l1 = tu_dot3(e, e1);
    a = tu_dot3(e, e);
    m->s_ax += ax;
    m->s_ax2 += ax * ax;
    m->s_l1 += l1;
    m->s_l1_2 += l1 * l1;
    m->sa += a;
    m->sa2 += a * a;
    m->sb += crlb_tr;
    m->sb2 += crlb_tr * crlb_tr;
    m->sab += a * crlb_tr;
    m->strust += trust;
    m->n++;
}

static double mean_se(double s, double s2, int n, double *se)
{
    const double m = s / n;
    *se = sqrt((s2 / n - m * m) / (n - 1));
    return m;
}

/* RMSE / sqrt(mean tr CRLB) and its standard error (delta method:
 * Var(R^2) ~ Var(a - R^2 b) / (T mean(b)^2), SE(R) = SE(R^2)/(2R)). */
static double mc_ratio(const mc_t *m, double *se)
{
    const double n = (double)m->n, ma = m->sa / n, mb = m->sb / n, r2 = ma / mb;
    const double va = m->sa2 / n - ma * ma, vb = m->sb2 / n - mb * mb;
    const double cab = m->sab / n - ma * mb;
    const double vq = va - 2.0 * r2 * cab + r2 * r2 * vb;
    *se = sqrt((vq > 0.0 ? vq : 0.0) / (n - 1.0)) / mb / (2.0 * sqrt(r2));
    return sqrt(r2);
}

static double crlb_trace(size_t n, double sigma)
{
    double crlb[4][4];
    ref_crlb_sphere(REF_C3(g_true), n, k_c0, R0, sigma * sigma, crlb);
    return crlb[0][0] + crlb[1][1] + crlb[2][2];
}

/* T trials: UGDK (float library, known sigma) and, when geo, the double
 * ML fit started from UGDK. */
static void run(uint64_t seed, double theta, double sigma, size_t n, int T, int geo,
                mc_t *mu, mc_t *mg)
{
    const sfit_fit_cfg_t cu = cfg_for(sigma * sigma);
    tu_rng_t g;
    int t;
    memset(mu, 0, sizeof *mu);
    memset(mg, 0, sizeof *mg);
    tu_rng_seed(&g, seed);
    for (t = 0; t < T; t++) {
        sfit_result_t ru;
        double c[3], tr, cg[3], rg;
        draw(&g, n, theta, sigma);
        assert_int_equal(sfit_fit_points(g_f, n, &cu, &ru), SFIT_OK);
        tc_to_double3(&ru.center, c);
        tr = crlb_trace(n, sigma);
        mc_add(mu, c, tr, (double)ru.trust_ratio);
        if (geo) {
            assert_int_equal(ref_fit_geometric(REF_C3(g_x), n, c, (double)ru.radius, cg, &rg,
                                               NULL),
                             0);
            mc_add(mg, cg, tr, 0.0);
        }
    }
}

/* Claim 1: UGDK with known sigma, RMSE / sqrt(tr CRLB) <= 1.10 where
 * rho <= 0.1 and N >= 100. The full harness (2000 trials) measured 1.00 to
 * 1.06 in these two scenarios. Here T = 1500: the SE of the ratio is
 * ~0.7/sqrt(T) of it (|e|^2 has a coefficient of variation ~sqrt 2 when
 * one direction dominates), ~1.8 %, so 1.10 is > 3 SE above the expected
 * value. The ratio must also not be below 1 by more than 3 SE: an
 * essentially unbiased estimator cannot beat the bound (this catches a
 * wrong CRLB or a wrong error accumulation). The double ML fit is held to
 * the same two bounds (it is asymptotically efficient). */
static void test_ugdk_efficiency(void **state)
{
    static const struct {
        double theta_deg, sigma;
        size_t n;
        int T;
    } sc[] = {{180.0, 5.0, 100, 1500}, {60.0, 2.0, 300, 1500}, {90.0, 5.0, 100, 1500}};
    size_t i;
    (void)state;
    for (i = 0; i < sizeof sc / sizeof sc[0]; i++) {
        const double theta = sc[i].theta_deg * DEG, sg = sc[i].sigma;
        const double rho = sg * sg / (lmin0(theta) + sg * sg);
        mc_t mu, mg;
        double ru, seu, rg, seg;
        run(UINT64_C(7100) + i, theta, sg, sc[i].n, sc[i].T, sc[i].n <= 100, &mu, &mg);
        ru = mc_ratio(&mu, &seu);
        print_message("theta %g sigma %g N %zu rho %.4f: UGDK RMSE/sqrt(trCRLB) %.3f +- %.3f\n",
                      sc[i].theta_deg, sg, sc[i].n, rho, ru, seu);
        assert_true(rho <= 0.1);
        assert_true(ru <= 1.10);
        assert_true(ru >= 1.0 - 3.0 * seu);
        if (mg.n > 0) {
            rg = mc_ratio(&mg, &seg);
            print_message("  ML RMSE/sqrt(trCRLB) %.3f +- %.3f\n", rg, seg);
            assert_true(rg <= 1.10);
            assert_true(rg >= 1.0 - 3.0 * seg);
        }
    }
}

/* Claim 1: |bias| <= 0.03 sigma at N >= 1000, rho <= 0.1. 60-degree cap,
 * sigma 2 mm (rho = 0.019), N = 1000, T = 600: the axial spread is ~0.22
 * sigma (N tr-axial CRLB ~ 48 sigma^2 for this cap), so SE ~ 0.009 sigma;
 * the claim's 0.03 sigma plus 2 SE. Lateral components are zero by
 * symmetry and are checked the same way. (GDKE's bias here is 1.41 mm =
 * 0.7 sigma: a UGDK that under-compensated by half would fail.) */
static void test_ugdk_bias(void **state)
{
    const double theta = 60.0 * DEG, sg = 2.0;
    mc_t mu, mg;
    double bax, se_ax, bl, se_l;
    (void)state;
    run(UINT64_C(7200), theta, sg, 1000, 600, 0, &mu, &mg);
    bax = mean_se(mu.s_ax, mu.s_ax2, mu.n, &se_ax);
    bl = mean_se(mu.s_l1, mu.s_l1_2, mu.n, &se_l);
    print_message("UGDK bias: axial %.4f +- %.4f sigma, lateral %.4f +- %.4f sigma\n", bax / sg,
                  se_ax / sg, bl / sg, se_l / sg);
    assert_true(se_ax <= 0.012 * sg); /* the test resolves the claim */
    assert_true(fabs(bax) <= 0.03 * sg + 2.0 * se_ax);
    assert_true(fabs(bl) <= 0.03 * sg + 2.0 * se_l);
}

/* Claim 2: GDKE's bias along the cap axis is rho r (1 + cos theta)/2 with
 * rho the trust ratio (population value sigma^2/(lambda_min(C0)+sigma^2)):
 * asymptotically C -> C0 + sigma^2 I and S -> S0 (the noise terms of S
 * average out for symmetric noise), so c_GDKE - m -> (C0 + sigma^2 I)^-1
 * C0 (c0 - m) and the offset c0 - m = r (1 + cos theta)/2 along the axis
 * (an eigenvector of C0) shrinks by exactly 1 - rho. Within 5 % + 3 SE at
 * N = 10000 (the O(1/N) part is then < 1 %). Includes the 30-degree cap
 * with sigma 5 mm, rho = 0.63 (rho0 = 1.67, beyond the Leontief limit):
 * the prediction with rho0 would be 156 mm instead of 58 mm. */
static void test_gdke_cap_bias(void **state)
{
    static const struct {
        double theta_deg, sigma;
        int T;
    } sc[] = {{60.0, 5.0, 30}, {30.0, 5.0, 30}, {45.0, 2.0, 30}};
    const size_t n = 10000;
    const sfit_fit_cfg_t cg = cfg_for(0.0), cu0 = cfg_for(1.0);
    size_t i;
    (void)state;
    for (i = 0; i < sizeof sc / sizeof sc[0]; i++) {
        const double theta = sc[i].theta_deg * DEG, sg = sc[i].sigma;
        const double rho = sg * sg / (lmin0(theta) + sg * sg);
        const double pred = rho * R0 * (1.0 + cos(theta)) / 2.0;
        sfit_fit_cfg_t cu = cu0;
        double s = 0.0, s2 = 0.0, st = 0.0, m, se;
        tu_rng_t g;
        int t;
        cu.noise_var = (float)(sg * sg);
        cu.eigen = true; /* the exact trust ratio */
        tu_rng_seed(&g, UINT64_C(7300) + i);
        for (t = 0; t < sc[i].T; t++) {
            sfit_result_t rg, ru;
            double c[3], e[3], nn[3], e1[3], e2[3], ax;
            int k;
            draw(&g, n, theta, sg);
            assert_int_equal(sfit_fit_points(g_f, n, &cg, &rg), SFIT_OK);
            assert_int_equal(sfit_fit_points(g_f, n, &cu, &ru), SFIT_OK);
            tc_to_double3(&rg.center, c);
            for (k = 0; k < 3; k++) {
                e[k] = c[k] - k_c0[k];
            }
            tu_frame(k_axis, nn, e1, e2);
            ax = tu_dot3(e, nn);
            s += ax;
            s2 += ax * ax;
            st += (double)ru.trust_ratio;
        }
        m = mean_se(s, s2, sc[i].T, &se);
        print_message("cap %g sigma %g: GDKE axial bias %.3f +- %.3f mm, predicted %.3f "
                      "(rho %.4f, mean trust_ratio %.4f)\n",
                      sc[i].theta_deg, sg, m, se, pred, rho, st / sc[i].T);
        assert_true(fabs(m - pred) <= 0.05 * pred + 3.0 * se);
        /* the library's measured trust ratio is that rho (its SE is far
         * below 1 % of rho at N = 10000) */
        assert_near(st / sc[i].T, rho, 0.01 * rho, "mean trust_ratio");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ugdk_efficiency),
        cmocka_unit_test(test_ugdk_bias),
        cmocka_unit_test(test_gdke_cap_bias),
    };
    return cmocka_run_group_tests_name("validation", tests, NULL, NULL);
}
