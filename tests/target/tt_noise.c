/* SPDX-License-Identifier: MIT */
/**
 * @file tt_noise.c
 * @brief On-target: noise calibration (eq. 177) against the double oracle
 * ref_noise_trace() on the same float samples, and the predicted spread
 * (eq. 190) against ref_noise_trace_var(). Tolerances: Tr Sigma_hat =
 * mean |x - c0|^2 - r0^2 is a centred sum of terms bounded by (r0 + 5
 * sigma)^2, so its float error is tt_sum_rel(N) (r0 + 5 sigma)^2 (x 4, as
 * everywhere); eq. 190 is a closed form of 8 float operations: 16 eps
 * relative.
 */
#include <string.h>

#include "sfit/sfit_noise.h"
#include "sfit/sfit_coverage.h"
#include "tt_data.h"

void tt_noise(void);

static sfit_vec3_t tt_f[TT_N];
static double tt_d[TT_N][3];

void tt_noise(void)
{
    static sfit_moments_t m;
    sfit_noise_est_t est;
    sfit_vec3_t c0;
    const double r0 = 100.0, sigma = 0.5;
    double tr, sd_ref, bnd;
    float sd;
    int k;

    tt_case("noise.calibrate_vs_ref");
    tt_cap(21u, r0, TU_PI, sigma, TT_N, tt_f, tt_d);
    (void)sfit_moments_init(&m);
    (void)sfit_moments_add_block(&m, tt_f, TT_N, NULL);
    for (k = 0; k < 3; k++) {
        c0.v[k] = (float)tt_c[k];
    }
    tr = ref_noise_trace(REF_C3(tt_d), TT_N, tt_c, r0);
    bnd = (r0 + 5.0 * sigma) * (r0 + 5.0 * sigma);
    if (TT_EQ_INT(sfit_noise_calibrate(&m, &c0, (float)r0, &est), SFIT_OK)) {
        TT_NEAR(est.noise_trace, tr, 4.0 * tt_sum_rel(TT_N) * bnd + 4.0 * tt_ulp(bnd));
        TT_NEAR(est.noise_var, tr / 3.0, 4.0 * tt_sum_rel(TT_N) * bnd + 4.0 * tt_ulp(bnd));
        TT_EQ_INT(est.n, TT_N);
    }

    tt_case("noise.calib_std_vs_ref");
    sd_ref = sqrt(ref_noise_trace_var(sigma * sigma, r0, TT_N, 3));
    if (TT_EQ_INT(sfit_noise_calib_std((float)(sigma * sigma), (float)r0, TT_N, &sd), SFIT_OK)) {
        TT_NEAR(sd, sd_ref, 16.0 * TT_EPS * sd_ref);
    }

    tt_case("noise.errors");
    TT_EQ_INT(sfit_noise_calibrate(NULL, &c0, 1.0f, &est), SFIT_E_ARG);
    TT_EQ_INT(sfit_noise_calibrate(&m, &c0, -1.0f, &est), SFIT_E_ARG);
    c0.v[0] = NAN;
    TT_EQ_INT(sfit_noise_calibrate(&m, &c0, 1.0f, &est), SFIT_E_NONFINITE);
}
