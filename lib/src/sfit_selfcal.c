/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_selfcal.c
 * @brief Self-calibrated UGDK (noise variance estimated from the samples).
 *
 * Implementation notes
 * --------------------
 * The residual pass sums e_i = |x_i - c| - r (shifted by the current radius,
 * so the terms are ~ sigma and nothing cancels) and e_i^2 in two levels
 * (blocks of SFIT_SELFCAL_BLOCK samples), then
 * s^2 = (sum e^2 - (sum e)^2 / N) / (N - 4). The shift by r makes the
 * one-pass variance formula safe: the mean residual is ~ sigma^2/r << sigma.
 */
#include "sfit/sfit_selfcal.h"

#include <string.h>

#include "sfit/sfit_moments.h"
#include "sfit_internal.h"

#define SFIT_SELFCAL_BLOCK 64u


/* One residual pass: sigma^2 from s^2 with the curvature correction. */
/* Fewest samples: 4 sphere parameters plus one residual degree of freedom. */
#define PRV_SELFCAL_MIN_N ((SFIT_MIN_SAMPLES > 5u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)5u)

static sfit_status_t prv_noise_var(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c,
                                   float r, float *var)
{
    float s1 = 0.0f, s2 = 0.0f, b1 = 0.0f, b2 = 0.0f, nf, v, q;
    uint32_t inblk = 0u;
    size_t i;
    sfit_status_t st;

    for (i = 0; i < n; i++) {
        float d0, d1, d2, e;
        st = sfit_i_check_sample(pts[i].v);
        if (st != SFIT_OK) {
            return st;
        }
        d0 = pts[i].v[0] - c->v[0];
        d1 = pts[i].v[1] - c->v[1];
        d2 = pts[i].v[2] - c->v[2];
        e = SFIT_SQRTF(d0 * d0 + d1 * d1 + d2 * d2);
        if (!(e > 0.0f)) {
            return SFIT_E_DEGENERATE;
        }
        e -= r;
        b1 += e;
        b2 += e * e;
        if (++inblk == SFIT_SELFCAL_BLOCK) {
            s1 += b1;
            s2 += b2;
            b1 = 0.0f;
            b2 = 0.0f;
            inblk = 0u;
        }
    }
    s1 += b1;
    s2 += b2;
    nf = (float)n;
    v = (s2 - s1 * (s1 / nf)) / (nf - 4.0f);
    if (!sfit_i_isfinite(v)) {
        return SFIT_E_RANGE;
    }
    if (v < 0.0f) {
        v = 0.0f; /* rounding */
    }
    /* E s^2 = sigma^2 - sigma^4 / r^2 (curvature of the sphere). */
    q = 4.0f * v / (r * r);
    v = 2.0f * v / (1.0f + SFIT_SQRTF((q < 1.0f) ? (1.0f - q) : 0.0f));
    if (!sfit_i_isfinite(v)) {
        return SFIT_E_RANGE;
    }
    *var = v;
    return SFIT_OK;
}

sfit_status_t sfit_selfcal_noise_var(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                     float radius, float *noise_var)
{
    int i;
    if (pts == NULL || center == NULL || noise_var == NULL) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(radius) || !(radius > 0.0f)) {
        return SFIT_E_ARG;
    }
    for (i = 0; i < 3; i++) {
        if (!sfit_i_isfinite(center->v[i])) {
            return SFIT_E_ARG;
        }
    }
    if (n < 5u) {
        return SFIT_E_TOO_FEW;
    }
    if (n > (size_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    return prv_noise_var(pts, n, center, radius, noise_var);
}

sfit_status_t sfit_selfcal_fit(const sfit_vec3_t *pts, size_t n, const sfit_fit_cfg_t *cfg,
                               sfit_selfcal_result_t *out)
{
    sfit_moments_t acc;
    sfit_fit_cfg_t fc;
    sfit_result_t fit;
    sfit_selfcal_result_t res;
    float var = 0.0f, cap;
    int it;
    sfit_status_t st;

    if (pts == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    fc = (cfg != NULL) ? *cfg : sfit_fit_cfg_default;
    if (sfit_i_check_cfg(&fc) != SFIT_OK || fc.mode == SFIT_MODE_PLANAR) {
        return SFIT_E_ARG;
    }
    if (n < PRV_SELFCAL_MIN_N) {
        return SFIT_E_TOO_FEW;
    }
    if (n > (size_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    fc.mode = SFIT_MODE_SPHERE;
    fc.noise = SFIT_NOISE_NONE;
    fc.noise_var = 0.0f;
    (void)sfit_moments_init(&acc);
    st = sfit_moments_add_block(&acc, pts, n, NULL);
    if (st != SFIT_OK) {
        return st;
    }
    st = sfit_fit_solve(&acc, &fc, &fit); /* GDKE start */
    if (st != SFIT_OK) {
        return st;
    }
    if (!(fit.eigenvalues.v[0] > 0.0f)) {
        /* Rounding left C without a positive smallest eigenvalue: no noise
         * level can be compensated (the cap below would be negative). */
        return SFIT_E_DEGENERATE;
    }
    cap = SFIT_SELFCAL_MAX_TRUST * fit.eigenvalues.v[0];
    memset(&res, 0, sizeof res);
    for (it = 1; it <= SFIT_SELFCAL_MAX_ITERS; it++) {
        float v;
        int done;
        st = prv_noise_var(pts, n, &fit.center, fit.radius, &v);
        if (st != SFIT_OK) {
            return st;
        }
        if (v >= cap) {
            v = cap;
            res.flags |= (uint32_t)SFIT_SELFCAL_FLAG_CAPPED;
        } else {
            res.flags &= ~(uint32_t)SFIT_SELFCAL_FLAG_CAPPED;
        }
        done = (SFIT_FABSF(v - var) <= SFIT_SELFCAL_REL_TOL * v) || (v == var);
        var = v;
        fc.noise = SFIT_NOISE_ISO;
        fc.noise_var = var;
        st = sfit_fit_solve(&acc, &fc, &fit);
        if (st != SFIT_OK) {
            return st;
        }
        if (done) {
            res.fit = fit;
            res.noise_var = var;
            res.iterations = (uint32_t)it;
            *out = res;
            return SFIT_OK;
        }
    }
    return SFIT_E_NO_CONVERGENCE;
}
