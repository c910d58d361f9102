/* SPDX-License-Identifier: MIT */
/**
 * @file tt_beyond.c
 * @brief On-target: self-calibration, geometric refinement and the
 * sandwich covariance against the double oracles on the same float
 * samples (TT_N = 400 on a 60-degree cap, centre 2693 mm away, r = 100,
 * sigma = 2).
 *
 * Tolerances (the host tests' models, tests/test_selfcal.c,
 * test_refine.c, test_uncert.c):
 *  - selfcal centre vs double UGDK at the estimated sigma^2: the moments'
 *    relative error tt_sum_rel(N) of the spread squared, amplified by the
 *    cap's conditioning kappa = tr C / lambda_min (~ 20 here), on r: x 4;
 *  - noise_var vs the residual formula in double at the library's fit: the
 *    residuals d - r are ~ sigma, each off by ~ eps |x - c| ~ eps r, so
 *    s^2 is off by ~ 2 eps r / sigma relative, x 4 plus the sum error;
 *  - refined centre vs double LM: the step tolerance 1e-5 r plus the
 *    float residual noise eps |x - c0| / sqrt(N) per iteration, x 4;
 *  - sandwich vs the double 4x4: the profiled 3x3 in float, relative
 *    ~ kappa eps per entry of A^-1 and two products: 1e-3 (as on host).
 */
#include <string.h>

#include "sfit/sfit_refine.h"
#include "sfit/sfit_selfcal.h"
#include "sfit/sfit_uncert.h"
#include "tt_data.h"

void tt_beyond(void);

static sfit_vec3_t tt_f[TT_N];
static double tt_d[TT_N][3];

static double tt_dist_f(const sfit_vec3_t *a, const double b[3])
{
    double s = 0.0;
    int k;
    for (k = 0; k < 3; k++) {
        const double e = (double)a->v[k] - b[k];
        s += e * e;
    }
    return sqrt(s);
}

void tt_beyond(void)
{
    const double r0 = 100.0, sigma = 2.0, kappa = 20.0;
    sfit_selfcal_result_t sc;
    sfit_refine_result_t rf;
    sfit_uncert_t u;
    ref_fit_t ref;
    double cov[6], cd[3], cg[3], rg, s1 = 0.0, s2 = 0.0, v, rr, cr[4][4];
    int i, j, it;

    tt_cap(31u, r0, 60.0 * TU_PI / 180.0, sigma, TT_N, tt_f, tt_d);

    tt_case("beyond.selfcal_vs_ref");
    if (!TT_EQ_INT(sfit_selfcal_points(tt_f, TT_N, NULL, &sc), SFIT_OK)) {
        return; /* the rest starts from this fit */
    }
    {
        cov[0] = cov[1] = cov[2] = (double)sc.noise_var;
        cov[3] = cov[4] = cov[5] = 0.0;
        if (TT_EQ_INT(ref_fit_sphere(REF_C3(tt_d), TT_N, cov, &ref), 0)) {
            TT_NEAR(tt_dist_f(&sc.fit.center, ref.center), 0.0,
                    4.0 * kappa * tt_sum_rel(TT_N) * r0 + 4.0 * tt_ulp(2693.0));
        }
        for (j = 0; j < 3; j++) {
            cd[j] = (double)sc.fit.center.v[j];
        }
        rr = (double)sc.fit.radius;
        for (i = 0; i < TT_N; i++) {
            const double e = tu_dist3(tt_d[i], cd) - rr;
            s1 += e;
            s2 += e * e;
        }
        v = (s2 - s1 * s1 / TT_N) / (TT_N - 4);
        v = 2.0 * v / (1.0 + sqrt(1.0 - 4.0 * v / (rr * rr)));
        TT_NEAR(sc.noise_var, v, 4.0 * (2.0 * TT_EPS * r0 / sigma + tt_sum_rel(TT_N)) * v);
        TT_TRUE(sc.iterations >= 1u && sc.iterations <= SFIT_SELFCAL_MAX_ITERS);
    }

    tt_case("beyond.refine_vs_ref");
    if (!TT_EQ_INT(sfit_refine_points(tt_f, TT_N, &sc.fit.center, NULL, &rf), SFIT_OK)) {
        return;
    }
    {
        if (TT_EQ_INT(ref_fit_geometric(REF_C3(tt_d), TT_N, cd, rr, cg, &rg, &it), 0)) {
            const double tol = 4.0 * (1e-5 * r0 + TT_EPS * 2693.0 / sqrt((double)TT_N));
            TT_NEAR(tt_dist_f(&rf.center, cg), 0.0, tol);
            TT_NEAR(rf.radius, rg, tol);
        }
        TT_TRUE(rf.converged && rf.iterations <= SFIT_REFINE_MAX_ITERS);
    }

    tt_case("beyond.sandwich_vs_ref");
    for (j = 0; j < 3; j++) {
        cg[j] = (double)rf.center.v[j];
    }
    if (TT_EQ_INT(sfit_uncert_geometric(tt_f, TT_N, &rf.center, &u), SFIT_OK)
        && TT_EQ_INT(ref_sandwich_geometric(REF_C3(tt_d), TT_N, cg, cr), 0)) {
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                TT_NEAR(u.center_cov.m[3 * i + j], cr[i][j], 1e-3 * sqrt(cr[i][i] * cr[j][j]));
            }
            TT_NEAR(u.center_radius_cov[i], cr[i][3], 1e-3 * sqrt(cr[i][i] * cr[3][3]));
        }
        TT_NEAR(u.radius_var, cr[3][3], 1e-3 * cr[3][3]);
    }

    tt_case("beyond.selfcal_sandwich_vs_ref");
    {
        double cs[3][3];
        sfit_uncert_t us;
        for (j = 0; j < 3; j++) {
            cd[j] = (double)sc.fit.center.v[j];
        }
        if (TT_EQ_INT(sfit_uncert_selfcal(tt_f, TT_N, &sc.fit.center, sc.fit.radius,
                                          sc.noise_var, &us),
                      SFIT_OK)
            && TT_EQ_INT(ref_sandwich_selfcal(REF_C3(tt_d), TT_N, cd, (double)sc.fit.radius,
                                              (double)sc.noise_var, cs),
                         0)) {
            for (i = 0; i < 3; i++) {
                for (j = 0; j < 3; j++) {
                    TT_NEAR(us.center_cov.m[3 * i + j], cs[i][j], 2e-3 * sqrt(cs[i][i] * cs[j][j]));
                }
            }
        }
        TT_EQ_INT(sfit_uncert_selfcal(tt_f, 13, &sc.fit.center, sc.fit.radius,
                                      sc.noise_var, &us),
                  SFIT_E_TOO_FEW);
    }

    tt_case("beyond.errors");
    TT_EQ_INT(sfit_selfcal_points(NULL, TT_N, NULL, &sc), SFIT_E_ARG);
    TT_EQ_INT(sfit_refine_points(tt_f, 4, &sc.fit.center, NULL, &rf), SFIT_E_TOO_FEW);
    TT_EQ_INT(sfit_uncert_geometric(tt_f, 4, &rf.center, &u), SFIT_E_TOO_FEW);
    tt_f[7].v[1] = NAN;
    TT_EQ_INT(sfit_uncert_geometric(tt_f, TT_N, &rf.center, &u), SFIT_E_NONFINITE);
    TT_EQ_INT(sfit_selfcal_points(tt_f, TT_N, NULL, &sc), SFIT_E_NONFINITE);
}
