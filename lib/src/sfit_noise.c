/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_noise.c
 * @brief Noise calibration against a known sphere (eq. 177, 189, 190).
 *
 * Implementation notes
 * --------------------
 * Calibration. With the accumulator's total (n, d = mean - origin, centred
 * M2), sum |x - c0|^2 = tr(M2) + n |e|^2 with e = (origin - c0) + d, so
 * T = tr(M2)/n + |e|^2 - r0^2. r0^2 is subtracted from the larger of the two
 * positive terms: for a whole sphere tr(M2)/n ~ r0^2, for a small cap
 * |e|^2 ~ r0^2, and in both cases the subtraction is then exact (Sterbenz)
 * or nearly so; the remaining error is a few ulp of r0^2.
 */
#include "sfit/sfit_noise.h"

#include <string.h>

#include "sfit_moments_i.h"

sfit_status_t sfit_noise_calib_std(float noise_var, float r0, uint32_t n, float *sd)
{
    float v;
    if (sd == NULL || n == 0u) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(noise_var) || !sfit_i_isfinite(r0)) {
        return SFIT_E_NONFINITE;
    }
    if (noise_var < 0.0f || r0 < 0.0f) {
        return SFIT_E_ARG;
    }
    /* eq. 190 with D = 3: 2 s2 (3 s2 + 2 r0^2) / (9 N) */
    v = 2.0f * noise_var * (3.0f * noise_var + 2.0f * r0 * r0) / (9.0f * (float)n);
    if (!sfit_i_isfinite(v)) {
        return SFIT_E_RANGE;
    }
    *sd = SFIT_SQRTF(v);
    return SFIT_OK;
}

sfit_status_t sfit_noise_calibrate(const sfit_moments_t *m, const sfit_vec3_t *c0, float r0,
                                   sfit_noise_est_t *out)
{
    sfit_cmom_t t;
    sfit_noise_est_t e;
    float ee = 0.0f, tr, rr, tsum, sd;
    int i;
    sfit_status_t st;

    if (m == NULL || c0 == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    if (sfit_i_check_fit(c0, NULL) != SFIT_OK || !sfit_i_isfinite(r0)) {
        return SFIT_E_NONFINITE;
    }
    if (r0 < 0.0f) {
        return SFIT_E_ARG;
    }
    if (sfit_moments_count(m) == 0u) {
        return SFIT_E_TOO_FEW;
    }
    sfit_i_moments_total(m, &t);
    for (i = 0; i < 3; i++) {
        const float d = (m->origin[i] - c0->v[i]) + t.d[i];
        ee += d * d;
    }
    tr = (t.m2[0] + t.m2[1] + t.m2[2]) / (float)t.n;
    rr = r0 * r0;
    tsum = (tr >= ee) ? (tr - rr) + ee : (ee - rr) + tr;
    if (!sfit_i_isfinite(tsum)) {
        return SFIT_E_RANGE;
    }
    memset(&e, 0, sizeof e);
    e.n = t.n;
    e.noise_trace = tsum;
    e.noise_var = tsum / 3.0f;
    st = sfit_noise_calib_std(SFIT_FABSF(e.noise_var), r0, t.n, &sd);
    if (st != SFIT_OK) {
        return SFIT_E_RANGE;
    }
    e.noise_var_std = sd;
    if (e.noise_var < 0.0f) {
        e.flags |= (uint32_t)SFIT_NOISE_FLAG_NEGATIVE;
    }
    if (e.noise_var < 2.0f * sd) {
        e.flags |= (uint32_t)SFIT_NOISE_FLAG_IMPRECISE;
    }
    *out = e;
    return SFIT_OK;
}
