/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_points.c
 * @brief Fits over a caller's array: sfit_points_fit() and the combined
 * recipe (self-calibrated start, geometric refinement, sandwich covariance:
 * sfit_points_fit_refined()).
 */
#include "sfit/sfit_refine.h"

#include "sfit_solve.h"

/* In this file, not beside sfit_moments_fit(): the accumulator and the
 * solve then never share a frame (sfit_i_points_total keeps the one,
 * sfit_i_fit_totals the other), which bounds the stack. */
sfit_status_t sfit_points_fit(const sfit_vec3_t *pts, size_t n, const sfit_fit_cfg_t *cfg,
                              sfit_result_t *out)
{
    sfit_i_total_t t;
    sfit_status_t st;

    st = (out == NULL || (pts == NULL && n > 0u)) ? SFIT_E_ARG : sfit_i_points_total(pts, n, &t);
    return (st == SFIT_OK) ? sfit_i_fit_totals(NULL, &t, cfg, out) : st;
}

const sfit_refined_cfg_t sfit_refined_cfg_default = {
    .selfcal = {.planar_ratio = 0.0f},
    .refine = {.max_iters = 0u, .tol = 0.0f, .accept_unconverged = 0u}};

sfit_status_t sfit_points_fit_refined(const sfit_vec3_t *pts, size_t n,
                                      const sfit_refined_cfg_t *cfg, sfit_refined_t *out)
{
    sfit_refined_t r;
    sfit_status_t st;

    cfg = (cfg != NULL) ? cfg : &sfit_refined_cfg_default;
    st = (out == NULL) ? SFIT_E_ARG : sfit_points_selfcal(pts, n, &cfg->selfcal, &r.start);
    if (st == SFIT_OK) {
        st = sfit_points_refine(pts, n, &r.start.fit.center, &cfg->refine, &r.geometric);
    }
    if (st == SFIT_OK) {
        st = sfit_points_uncert_geometric(pts, n, &r.geometric.center, &r.uncert);
    }
    if (st == SFIT_OK) {
        /* The geometric fit has a second-order bias (~ sigma^2 / r along the
         * cap axis) that does not shrink with N; the self-calibrated centre
         * has none to that order, so b = geometric - start estimates it.
         * Reported: the mean squared error Cov + b b^T (docs/coverage.md). */
        sfit_mat3_t cov;
        float b[3], f;
        int i, j;
        for (i = 0; i < 3; i++) {
            b[i] = r.geometric.center.v[i] - r.start.fit.center.v[i];
        }
        f = sfit_i_cov_widen(r.start.noise_var, r.start.fit.radius, n);
        sfit_i_sym_unpack(r.uncert.center_cov, &cov);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                /* times the widening of docs/coverage.md rule 7 */
                cov.m[3 * i + j] = (cov.m[3 * i + j] + b[i] * b[j]) * f;
            }
        }
        sfit_i_sym_pack(&cov, r.uncert.center_cov);
        if (!sfit_i_isfinite(r.uncert.center_cov[0] + r.uncert.center_cov[1]
                             + r.uncert.center_cov[2])) {
            st = SFIT_E_RANGE;
        }
    }
    if (st == SFIT_OK) {
        *out = r;
    }
    return st;
}
