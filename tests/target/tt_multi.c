/* SPDX-License-Identifier: MIT */
/**
 * @file tt_multi.c
 * @brief On-target: multi-marker common centre (MGDK) against the double
 * oracle ref_fit_multi() on the same float samples: 4 markers on 45-degree
 * caps of radii 80..110 mm around one centre. Tolerance: tt_tol_centre()
 * with the condition number of the summed covariance (bounded here by the
 * largest single-marker condition number).
 */
#include <string.h>

#include "sfit/sfit_multi.h"
#include "tt_data.h"

void tt_multi(void);

#define TT_NM 4
#define TT_NP 100

static sfit_vec3_t tt_f[TT_NM][TT_NP];
static double tt_d[TT_NM][TT_NP][3];

void tt_multi(void)
{
    static sfit_moments_t mk[TT_NM];
    sfit_multi_result_t res, save;
    const double *xs[TT_NM];
    size_t ns[TT_NM];
    double c[3], radii_ref[TT_NM], kap = 1.0;
    float radii[TT_NM];
    int p, k;

    tt_case("multi.vs_ref");
    for (p = 0; p < TT_NM; p++) {
        double kp;
        tt_cap(100u + (uint64_t)p, 80.0 + 10.0 * p, 0.25 * TU_PI, 0.5, TT_NP, tt_f[p], tt_d[p]);
        (void)sfit_moments_init(&mk[p]);
        (void)sfit_moments_add_block(&mk[p], tt_f[p], TT_NP, NULL);
        xs[p] = &tt_d[p][0][0];
        ns[p] = TT_NP;
        kp = tt_kappa(REF_C3(tt_d[p]), TT_NP);
        if (kp > kap) {
            kap = kp;
        }
    }
    if (TT_EQ_INT(sfit_multi_fit(mk, TT_NM, NULL, &res, radii), SFIT_OK)
        && TT_EQ_INT(ref_fit_multi(xs, ns, TT_NM, NULL, c, radii_ref), 0)) {
        const double tol = tt_tol_centre(TT_NP, 110.0, kap);
        for (k = 0; k < 3; k++) {
            TT_NEAR(res.center.v[k], c[k], tol);
        }
        for (p = 0; p < TT_NM; p++) {
            TT_NEAR(radii[p], radii_ref[p], tol);
        }
        TT_EQ_INT(res.markers, TT_NM);
        TT_EQ_INT(res.n_total, TT_NM * TT_NP);
    }

    tt_case("multi.errors");
    memset(&save, 0x5A, sizeof save);
    res = save;
    TT_EQ_INT(sfit_multi_fit(NULL, TT_NM, NULL, &res, NULL), SFIT_E_ARG);
    TT_EQ_INT(sfit_multi_fit(mk, 0, NULL, &res, NULL), SFIT_E_TOO_FEW);
    TT_TRUE(memcmp(&res, &save, sizeof res) == 0);
}
