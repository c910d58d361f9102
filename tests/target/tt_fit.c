/* SPDX-License-Identifier: MIT */
/**
 * @file tt_fit.c
 * @brief On-target: sphere / circle fits. Known answer (noise-free whole
 * sphere: the exact centre and radius, to the float rounding of the
 * samples), GDKE / UGDK / planar against the double oracle on the same
 * float samples (tolerance: tt_tol_centre(), i.e. the tt_data.h error model
 * with the condition number of C), batch = accumulate + solve bit for bit,
 * and the status of every degenerate input.
 */
#include <string.h>

#include "tt_data.h"

void tt_fit(void);

static sfit_vec3_t tt_f[TT_N];
static double tt_d[TT_N][3];

static void tt_cmp(const sfit_result_t *res, const ref_fit_t *rf, double tol)
{
    int i;
    for (i = 0; i < 3; i++) {
        TT_NEAR(res->center.v[i], rf->center[i], tol);
    }
    TT_NEAR(res->radius, rf->radius, tol);
}

void tt_fit(void)
{
    static sfit_moments_t m;
    sfit_result_t res, res2;
    sfit_fit_cfg_t cfg;
    ref_fit_t rf;
    const double r = 100.0;
    double cov[6] = {0.25, 0.25, 0.25, 0.0, 0.0, 0.0};
    size_t i;
    int k;

    tt_case("fit.known_sphere");
    /* noise-free whole sphere: the only error is the float rounding of
     * the samples (<= ulp/2 per coordinate) and of the computation */
    tt_cap(11u, r, TU_PI, 0.0, TT_N, tt_f, tt_d);
    if (TT_EQ_INT(sfit_fit_points(tt_f, TT_N, NULL, &res), SFIT_OK)) {
        double tol = tt_tol_centre(TT_N, r, tt_kappa(REF_C3(tt_d), TT_N));
        for (k = 0; k < 3; k++) {
            TT_NEAR(res.center.v[k], tt_c[k], tol);
        }
        TT_NEAR(res.radius, r, tol);
        TT_EQ_INT(res.method, SFIT_METHOD_GDKE);
        TT_EQ_INT(res.mode, SFIT_MODE_SPHERE);
        TT_EQ_INT(res.n, TT_N);
    }

    tt_case("fit.gdke_cap_vs_ref");
    tt_cap(12u, r, 0.25 * TU_PI, 0.5, TT_N, tt_f, tt_d);
    (void)sfit_moments_init(&m);
    (void)sfit_moments_add_block(&m, tt_f, TT_N, NULL);
    cfg = sfit_fit_cfg_default;
    cfg.eigen = true; /* eigenvalues checked below */
    if (TT_EQ_INT(sfit_fit_moments(&m, &cfg, &res), SFIT_OK)
        && TT_EQ_INT(ref_fit_sphere(REF_C3(tt_d), TT_N, NULL, &rf), 0)) {
        tt_cmp(&res, &rf, tt_tol_centre(TT_N, r, tt_kappa(REF_C3(tt_d), TT_N)));
        for (k = 0; k < 3; k++) {
            TT_NEAR(res.eigenvalues.v[k], rf.eig[k], 4.0 * tt_sum_rel(TT_N) * rf.eig[2]);
        }
    }

    tt_case("fit.batch_equals_solve");
    if (TT_EQ_INT(sfit_fit_points(tt_f, TT_N, &cfg, &res2), SFIT_OK)) {
        TT_TRUE(memcmp(&res, &res2, sizeof res) == 0);
    }

    tt_case("fit.default_equals_eigen");
    /* sfit_fit_moments_default (the plain solver alone): the fit with
     * cfg.eigen true bit for bit (res, above, on the same accumulator). */
    if (TT_EQ_INT(sfit_fit_moments_default(&m, &res2), SFIT_OK)) {
        TT_TRUE(memcmp(&res, &res2, sizeof res) == 0);
    }
    TT_EQ_INT(sfit_fit_moments_default(NULL, &res2), SFIT_E_ARG);

    tt_case("fit.screened_equals_full");
    /* The default (screened) solve on the same cap: the sphere of the full
     * solver bit for bit, the same flags, a trust bound >= the exact ratio. */
    for (k = 0; k < 2; k++) {
        sfit_fit_cfg_t cs = sfit_fit_cfg_default;
        cs.noise = (k == 0) ? SFIT_NOISE_NONE : SFIT_NOISE_ISO;
        cs.noise_var = (k == 0) ? 0.0f : 0.25f;
        cfg = cs;
        cfg.eigen = true;
        if (TT_EQ_INT(sfit_fit_moments(&m, &cs, &res), SFIT_OK)
            && TT_EQ_INT(sfit_fit_moments(&m, &cfg, &res2), SFIT_OK)) {
            TT_EQ_INT(res.exact, 0);
            TT_EQ_INT(res2.exact, 1);
            TT_TRUE(memcmp(res.center.v, res2.center.v, sizeof res.center.v) == 0);
            TT_TRUE(res.radius == res2.radius);
            TT_EQ_INT((int)res.flags, (int)res2.flags);
            TT_TRUE(res.leontief_ratio >= res2.leontief_ratio);
        }
    }

    tt_case("fit.ugdk_cap_vs_ref");
    cfg = sfit_fit_cfg_default;
    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = 0.25f;
    if (TT_EQ_INT(sfit_fit_moments(&m, &cfg, &res), SFIT_OK)
        && TT_EQ_INT(ref_fit_sphere(REF_C3(tt_d), TT_N, cov, &rf), 0)) {
        tt_cmp(&res, &rf, tt_tol_centre(TT_N, r, tt_kappa(REF_C3(tt_d), TT_N)));
        TT_EQ_INT(res.method, SFIT_METHOD_UGDK);
        TT_TRUE(res.trust_ratio > 0.0f && res.trust_ratio < 0.5f);
    }

    tt_case("fit.planar_vs_ref");
    {
        tu_rng_t g;
        const double ax[3] = {0.0, 0.0, 1.0}, dir[3] = {1.0, 0.0, 0.0};
        double kap, mr[3], cr[3][3], sr[3], wr[3], vr[3][3];
        tu_rng_seed(&g, 13u);
        for (i = 0; i < TT_N; i++) {
            double p[3];
            tu_sample_arc(&g, tt_c, r, ax, dir, 0.5 * TU_PI, 0.2, p);
            tt_store(p, &tt_f[i], tt_d[i]);
        }
        (void)ref_moments(REF_C3(tt_d), TT_N, mr, cr, sr);
        ref_sym3_eig(REF_C3(cr), wr, vr);
        kap = wr[2] / wr[1]; /* in-plane condition */
        cfg = sfit_fit_cfg_default;
        cfg.mode = SFIT_MODE_PLANAR;
        if (TT_EQ_INT(sfit_fit_points(tt_f, TT_N, &cfg, &res), SFIT_OK)
            && TT_EQ_INT(ref_fit_circle(REF_C3(tt_d), TT_N, NULL, &rf), 0)) {
            tt_cmp(&res, &rf, tt_tol_centre(TT_N, r, kap));
            TT_EQ_INT(res.mode, SFIT_MODE_PLANAR);
            TT_NEAR(fabs((double)res.axis.v[2]), 1.0, 1e-2); /* hinge axis ~ z */
        }
    }

    tt_case("fit.degenerate");
    TT_EQ_INT(sfit_fit_points(tt_f, 3, NULL, &res), SFIT_E_TOO_FEW);
    for (i = 0; i < 20; i++) {
        tt_f[i] = tt_f[0]; /* coincident */
    }
    TT_EQ_INT(sfit_fit_points(tt_f, 20, NULL, &res), SFIT_E_DEGENERATE);
    for (i = 0; i < 20; i++) { /* collinear */
        tt_f[i].v[0] = 1500.0f + (float)i;
        tt_f[i].v[1] = -2000.0f + 2.0f * (float)i;
        tt_f[i].v[2] = 1000.0f;
    }
    TT_EQ_INT(sfit_fit_points(tt_f, 20, NULL, &res), SFIT_E_DEGENERATE);
    memset(&res2, 0x5A, sizeof res2);
    res = res2;
    TT_EQ_INT(sfit_fit_points(NULL, 20, NULL, &res), SFIT_E_ARG);
    TT_EQ_INT(sfit_fit_moments(&m, NULL, NULL), SFIT_E_ARG);
    TT_TRUE(memcmp(&res, &res2, sizeof res) == 0); /* untouched on failure */
    cfg = sfit_fit_cfg_default;
    cfg.noise = SFIT_NOISE_ISO;
    cfg.noise_var = -1.0f;
    TT_EQ_INT(sfit_fit_moments(&m, &cfg, &res), SFIT_E_ARG);
}
