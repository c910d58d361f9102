/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_fit.c
 * @brief GDKE / UGDK sphere and planar (circle) solutions from moments.
 *
 * Derivation of the estimators and of the trust ratios: docs/api.md#fit.
 */
#include "sfit_solve.h"

#include <float.h>
#include <string.h>

/* lambda_min(C') for the rounding flag of the full solver: C's smallest used
 * eigenvalue minus an upper bound of the noise (sigma^2, or tr Sigma). */
static float prv_lmin(const sfit_i_solution_t *sol, const sfit_fit_cfg_t *cfg)
{
    const float *lam = sol->eigenvalues.v;
    float noise = 0.0f;
    if (cfg->noise == SFIT_NOISE_ISO) {
        noise = cfg->noise_var;
    } else if (cfg->noise == SFIT_NOISE_COV) {
        noise = cfg->noise_cov.m[0] + cfg->noise_cov.m[4] + cfg->noise_cov.m[8];
    } else {
        /* GDKE: C' = C */
    }
    return ((sol->mode == SFIT_MODE_PLANAR) ? lam[1] : lam[0]) - noise;
}

const sfit_fit_cfg_t sfit_fit_cfg_default = {
    .mode = SFIT_MODE_AUTO, .noise = SFIT_NOISE_NONE, .noise_var = 0.0f, .planar_ratio = 0.0f,
    .eigen = false};

/* The system of the fit of an accumulator's totals (tot, and blk: the
 * open block or NULL) about origin, with cfg's noise model: n, the sample
 * count. */
static uint32_t prv_system(const float origin[3], const sfit_cmom_t *tot, const sfit_cmom_t *blk,
                           const sfit_fit_cfg_t *cfg, sfit_i_system_t *sys)
{
    /* C = M2/(N-1); b = S/2 = M3/(2(N-1)). */
    const uint32_t n = sfit_i_moments_system(tot, blk, &sys->ms);
    sys->noisy = (int)cfg->noise;
    if (cfg->noise == SFIT_NOISE_COV) {
        sys->sigma.m = &cfg->noise_cov;
    } else {
        sys->sigma.var = (cfg->noise == SFIT_NOISE_ISO) ? cfg->noise_var : 0.0f;
    }
    sys->scale = sfit_i_coincident_scale(origin, sys->ms.d);
    return n;
}

/* The sphere of a solution: sol->w becomes the centre (origin + d + w) and
 * sol->trace the radius (no longer needed). Returns the rounding test on
 * lmax = sol->eigenvalues.v[2] and lmin (sfit_i_rounding_test: 0 or 1),
 * or a status below 0 (SFIT_E_NOT_POSDEF, SFIT_E_RANGE). */
static int prv_sphere_of(const float origin[3], const float d[3], uint32_t n, float lmin,
                         sfit_i_solution_t *sol)
{
    float r2;
    int i;
    /* r^2 = (N-1)/N tr C' (over the directions used) + |w|^2 (eq. 176/218). */
    r2 = ((float)(n - 1u) / (float)n) * sol->trace + sfit_i_dot3(sol->w.v, sol->w.v);
    if (!(r2 > 0.0f)) {
        return (int)SFIT_E_NOT_POSDEF;
    }
    r2 = SFIT_SQRTF(r2);
    for (i = 0; i < 3; i++) {
        sol->w.v[i] = origin[i] + (d[i] + sol->w.v[i]); /* the centre */
    }
    if (!sfit_i_sphere_finite(&sol->w, r2)) {
        return (int)SFIT_E_RANGE;
    }
    sol->trace = r2;
    return sfit_i_rounding_test(n, sol->eigenvalues.v[2], lmin, r2, sol->w.v);
}

/* The result of a solution (every check passed; sol->trace: the radius,
 * prv_sphere_of): exact 1 for the full
 * solver (eigenvalues kept), 0 for the screen (its bounds cleared). */
static void prv_result(sfit_i_solution_t *sol, uint32_t n, int exact, int noisy,
                       sfit_result_t *out)
{
    if (!exact) { /* the screen's bounds */
        sol->eigenvalues.v[0] = 0.0f;
        sol->eigenvalues.v[1] = 0.0f;
        sol->eigenvalues.v[2] = 0.0f;
    }
    if (n < SFIT_FEW_SAMPLES) {
        sol->flags |= (uint8_t)SFIT_FLAG_FEW_SAMPLES;
    }
    memset(out, 0, sizeof *out);
    out->center = sol->w;
    out->radius = sol->trace;
    out->n = n;
    out->eigenvalues = sol->eigenvalues;
    out->axis = sol->axis;
    out->leontief_ratio = sol->rho;
    out->trust_ratio = sol->rho / (1.0f + sol->rho);
    /* docs/coverage.md: outside the validated range the covariance no
     * longer describes the error (decided on the exact ratio: see above). */
    out->flags = (uint32_t)sol->flags | sfit_i_cov_limit(out->trust_ratio, n);
    out->method = noisy ? SFIT_METHOD_UGDK : SFIT_METHOD_GDKE;
    out->mode = sol->mode;
    out->exact = (exact != 0);
}

sfit_status_t sfit_i_fit_totals(const sfit_moments_t *m, const sfit_i_total_t *pt,
                                const sfit_fit_cfg_t *cfg, sfit_result_t *out)
{
    /* Each caller passes NULL for the one argument it lacks, never both
     * (sfit_fit_moments checks m): cppcheck cannot pair the two calls. */
    /* cppcheck-suppress nullPointer */
    const float *const origin = (pt != NULL) ? pt->origin : m->origin;
    const sfit_cmom_t *const tot = (pt != NULL) ? &pt->t : &m->tot;
    const sfit_cmom_t *const blk = (pt != NULL) ? NULL : &m->blk;
    sfit_i_system_t sys;
    sfit_i_solution_t sol;
    uint32_t n;
    int exact, flag;
    sfit_status_t st;

    st = SFIT_OK;
    if (cfg == NULL) {
        cfg = &sfit_fit_cfg_default; /* valid: no check */
    } else {
        st = sfit_i_check_cfg(cfg);
    }
    if (st == SFIT_OK && tot->n + ((blk != NULL) ? blk->n : 0u) < SFIT_MIN_SAMPLES) {
        st = SFIT_E_TOO_FEW;
    }
    if (st != SFIT_OK) {
        return st;
    }
    n = prv_system(origin, tot, blk, cfg, &sys);

    /* The solver's entry point chooses the screened or the full solve;
     * a second pass asks for the full solver when the screen's bounds
     * cannot prove the rounding flag clear (one call site: stack trick 6,
     * sfit_solve.h). */
    exact = 0;
    for (;;) {
        st = sfit_i_solve_fit(&sys, n, cfg, exact, &sol);
        if (st != SFIT_OK && st != SFIT_I_SCREENED) {
            return st;
        }
        exact = (st == SFIT_OK); /* SFIT_I_SCREENED: the screen's answer */
        /* The rounding flag: on the full solver's eigenvalues, or on the
         * screen's bounds (sfit_i_solve_lean leaves them in sol.eigenvalues). */
        flag = prv_sphere_of(origin, sys.ms.d, n,
                             exact ? prv_lmin(&sol, cfg) : sol.eigenvalues.v[0], &sol);
        if (flag < 0) {
            return (sfit_status_t)flag;
        }
        if (flag && exact) {
            sol.flags |= (uint8_t)SFIT_FLAG_ROUNDING;
        }
        if (!flag || exact) {
            break;
        }
        /* The bounds cannot prove the flag clear: the full solver after all
         * (sys is intact: the screen only reads it; exact is 0 here). */
        exact = 1;
    }
    prv_result(&sol, n, exact, sys.noisy, out);
    return SFIT_OK;
}

sfit_status_t sfit_fit_moments_default(const sfit_moments_t *m, sfit_result_t *out)
{
    sfit_i_system_t sys;
    sfit_i_solution_t sol;
    uint32_t n;
    int flag;

    if (m == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    if (m->tot.n + m->blk.n < SFIT_MIN_SAMPLES) {
        return SFIT_E_TOO_FEW;
    }
    n = prv_system(m->origin, &m->tot, &m->blk, &sfit_fit_cfg_default, &sys);
    flag = (int)sfit_i_solve_plain(&sys, SFIT_MODE_AUTO, 0.0f, &sol);
    if (flag == (int)SFIT_OK) {
        flag = prv_sphere_of(m->origin, sys.ms.d, n, prv_lmin(&sol, &sfit_fit_cfg_default), &sol);
    }
    if (flag < 0) {
        return (sfit_status_t)flag;
    }
    if (flag > 0) {
        sol.flags |= (uint8_t)SFIT_FLAG_ROUNDING;
    }
    prv_result(&sol, n, 1, 0, out);
    return SFIT_OK;
}

sfit_status_t sfit_fit_moments(const sfit_moments_t *m, const sfit_fit_cfg_t *cfg,
                             sfit_result_t *out)
{
    if (m == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    return sfit_i_fit_totals(m, NULL, cfg, out);
}

/* The accumulator and the solve never share a frame (sfit_i_points_total
 * keeps the one, sfit_i_fit_totals the other; stack trick 5, sfit_solve.h). */
sfit_status_t sfit_fit_points(const sfit_vec3_t *pts, size_t n, const sfit_fit_cfg_t *cfg,
                              sfit_result_t *out)
{
    sfit_i_total_t t;
    sfit_status_t st;

    st = (out == NULL || (pts == NULL && n > 0u)) ? SFIT_E_ARG : sfit_i_points_total(pts, n, &t);
    return (st == SFIT_OK) ? sfit_i_fit_totals(NULL, &t, cfg, out) : st;
}
