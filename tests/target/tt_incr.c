/* SPDX-License-Identifier: MIT */
/**
 * @file tt_incr.c
 * @brief On-target: the incremental estimator after a batch start and a run
 * of per-sample updates equals the double batch fit (ref_fit_sphere) of
 * the same samples (tolerance tt_tol_centre()); add + solve equals update
 * bit for bit; a rejected sample leaves the state unchanged.
 */
#include <string.h>

#include "sfit/sfit_incr.h"
#include "tt_data.h"

void tt_incr(void);

static sfit_vec3_t tt_f[TT_N];
static double tt_d[TT_N][3];

void tt_incr(void)
{
    static sfit_incr_t s, s2, save;
    sfit_sphere_t est, est2;
    ref_fit_t rf;
    sfit_vec3_t bad;
    const double r = 100.0;
    size_t i;
    int k, fails = 0;

    tt_case("incr.vs_batch_ref");
    tt_cap(31u, r, 0.25 * TU_PI, 0.5, TT_N, tt_f, tt_d);
    (void)sfit_incr_init(&s, NULL);
    if (TT_EQ_INT(sfit_incr_start(&s, tt_f, 10, &est), SFIT_OK)) {
        for (i = 10; i < TT_N; i++) {
            fails += (sfit_incr_update(&s, &tt_f[i], &est) != SFIT_OK);
        }
        TT_EQ_INT(fails, 0);
        TT_EQ_INT(est.n, TT_N);
        if (TT_EQ_INT(ref_fit_sphere(REF_C3(tt_d), TT_N, NULL, &rf), 0)) {
            const double tol = tt_tol_centre(TT_N, r, tt_kappa(REF_C3(tt_d), TT_N));
            for (k = 0; k < 3; k++) {
                TT_NEAR(est.center.v[k], rf.center[k], tol);
            }
            TT_NEAR(est.radius, rf.radius, tol);
        }
    }

    tt_case("incr.add_solve_equals_update");
    s2 = s;
    TT_EQ_INT(sfit_incr_update(&s, &tt_f[0], &est), SFIT_OK);
    TT_EQ_INT(sfit_incr_add(&s2, &tt_f[0]), SFIT_OK);
    TT_EQ_INT(sfit_incr_fit(&s2, &est2), SFIT_OK);
    TT_TRUE(memcmp(&s, &s2, sizeof s) == 0);
    TT_TRUE(memcmp(&est, &est2, sizeof est) == 0);

    tt_case("incr.reject_unchanged");
    save = s;
    bad = tt_f[1];
    bad.v[0] = NAN;
    TT_EQ_INT(sfit_incr_update(&s, &bad, &est), SFIT_E_NONFINITE);
    TT_TRUE(memcmp(&s, &save, sizeof s) == 0);
    TT_EQ_INT(sfit_incr_add(NULL, &bad), SFIT_E_ARG);
}
