/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_selfcal.c
 * @brief Self-calibrated UGDK (noise variance estimated from the samples).
 *
 * The residual pass sums e_i = |x_i - c| - r (shifted by the current radius,
 * so the terms are ~ sigma and nothing cancels) and e_i^2 in two levels,
 * then s^2 = (sum e^2 - (sum e)^2 / N) / (N - 4).
 */
#include "sfit/sfit_selfcal.h"

#include "sfit_pass.h"
#include "sfit_solve.h"

/* Fewest samples: 4 sphere parameters plus one residual degree of freedom. */
#define PRV_SELFCAL_MIN_N ((SFIT_MIN_SAMPLES > 5u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)5u)

const sfit_selfcal_cfg_t sfit_selfcal_cfg_default = {.planar_ratio = 0.0f};

/* One residual pass over validated samples: sigma^2 from s^2 with the
 * curvature correction. */
static sfit_status_t prv_noise_var(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c,
                                   float r, float *var)
{
    sfit_i_sum_t s;
    sfit_i_rows_t q;
    float nf = (float)n, v;

    sfit_i_rows_init(&q, SFIT_I_ROWS_RESID, r, NULL, 0.0f);
    if (!sfit_i_pass(pts, n, c->v, NULL, &q, 2, &s)) {
        return SFIT_E_DEGENERATE;
    }
    v = (s.tot[1] - s.tot[0] * (s.tot[0] / nf)) / (nf - 4.0f);
    if (!sfit_i_isfinite(v)) {
        return SFIT_E_RANGE;
    }
    v = sfit_i_curvature_var((v < 0.0f) ? 0.0f : v, r); /* v < 0: rounding */
    if (!sfit_i_isfinite(v)) {
        return SFIT_E_RANGE;
    }
    *var = v;
    return SFIT_OK;
}

sfit_status_t sfit_selfcal_noise_var(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                     float radius, float *noise_var)
{
    sfit_status_t st;
    if (pts == NULL || center == NULL || noise_var == NULL) {
        return SFIT_E_ARG;
    }
    st = sfit_i_check_fit(center, &radius);
    if (st == SFIT_OK) {
        st = sfit_i_check_points(pts, n, PRV_SELFCAL_MIN_N);
    }
    return (st == SFIT_OK) ? prv_noise_var(pts, n, center, radius, noise_var) : st;
}

sfit_status_t sfit_selfcal_points(const sfit_vec3_t *pts, size_t n, const sfit_selfcal_cfg_t *cfg,
                               sfit_selfcal_result_t *out)
{
    sfit_moments_t acc;
    sfit_fit_cfg_t fc = sfit_fit_cfg_default;
    sfit_result_t fit;
    sfit_selfcal_result_t res;
    float var = 0.0f, cap, lmin;
    int it, exact;
    sfit_status_t st;

    if (pts == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    fc.mode = SFIT_MODE_SPHERE;
    /* The cap below needs lambda_min(C): the full solver's eigenvalues, or
     * without it the screen's lower bound (sfit_i_solve_lmin). */
    fc.eigen = sfit_i_solve_has_eigen();
    fc.planar_ratio = (cfg != NULL) ? cfg->planar_ratio : 0.0f;
    if (sfit_i_check_cfg(&fc) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    st = sfit_i_check_points(pts, n, PRV_SELFCAL_MIN_N);
    if (st != SFIT_OK) {
        return st;
    }
    (void)sfit_i_moments_of(pts, n, &acc); /* validated above */
    st = sfit_fit_moments(&acc, &fc, &fit); /* GDKE start */
    if (st != SFIT_OK) {
        return st;
    }
    lmin = sfit_i_solve_lmin(&acc, &fit, &exact);
    if (!exact && !(lmin > 0.0f)) {
        return SFIT_E_UNSUPPORTED; /* the bound proves nothing: the full solver would decide */
    }
    if (!(lmin > 0.0f)) {
        /* Rounding left C without a positive smallest eigenvalue: no noise
         * level can be compensated (the cap below would be negative). */
        return SFIT_E_DEGENERATE;
    }
    cap = SFIT_SELFCAL_MAX_TRUST * lmin;
    memset(&res, 0, sizeof res);
    for (it = 1; it <= SFIT_SELFCAL_MAX_ITERS; it++) {
        float v;
        int done;
        st = prv_noise_var(pts, n, &fit.center, fit.radius, &v);
        if (st != SFIT_OK) {
            return st;
        }
        if (v >= cap) {
            if (!exact) {
                /* cap from a lower bound: whether the exact cap binds, and
                 * where, only the full solver's eigenvalue can tell */
                return SFIT_E_UNSUPPORTED;
            }
            v = cap;
            res.flags |= (uint32_t)SFIT_SELFCAL_FLAG_CAPPED;
        } else {
            res.flags &= ~(uint32_t)SFIT_SELFCAL_FLAG_CAPPED;
        }
        done = (SFIT_FABSF(v - var) <= SFIT_SELFCAL_REL_TOL * v) || (v == var);
        var = v;
        fc.noise = SFIT_NOISE_ISO;
        fc.noise_var = var;
        st = sfit_fit_moments(&acc, &fc, &fit);
        if (st != SFIT_OK) {
            return st;
        }
        if (done) {
            if ((res.flags & (uint32_t)SFIT_SELFCAL_FLAG_CAPPED) != 0u) {
                /* the data cannot separate noise from geometry: the fit and
                 * any covariance of it are not to be believed */
                fit.flags |= (uint32_t)SFIT_FLAG_UNTRUSTED | (uint32_t)SFIT_SELFCAL_FLAG_CAPPED;
            }
            res.fit = fit;
            res.noise_var = var;
            res.iterations = (uint32_t)it;
            *out = res;
            return SFIT_OK;
        }
    }
    return SFIT_E_NO_CONVERGENCE;
}
