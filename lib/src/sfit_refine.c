/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_refine.c
 * @brief Bounded Levenberg-Marquardt orthogonal-distance sphere fit (float).
 *
 * Parameters: the offset p of the centre from the start centre c0 (the
 * radius is profiled out); samples are used as z_i = (x_i - c0) - p. The
 * cost sum (d - dbar)^2 is summed as e = d - rref with rref the previous
 * mean distance, so the one-pass variance formula does not cancel.
 */
#include "sfit/sfit_refine.h"
#include "sfit/sfit_uncert.h"

#include <float.h>

#include "sfit_mat3_i.h"
#include "sfit_pass.h"

/* A step is accepted while the cost grows by less than this many float
 * epsilons (relative): near the minimum the change is below the rounding
 * of the summed cost and a strict comparison would stall the iteration. */
#define SFIT_REFINE_COST_ULPS 32.0f

const sfit_refine_cfg_t sfit_refine_cfg_default = {.max_iters = 0u, .tol = 0.0f, .accept_unconverged = false};

/* What pass A yields: mean direction, mean distance, cost. */
typedef struct prv_stats {
    float ubar[3];
    float dbar;
    float cost;
} prv_stats_t;

/* Pass A: mean direction, mean distance, cost; samples as z = (x - c0) - p,
 * the cost summed as e = d - rref. */
static sfit_status_t prv_pass_a(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c0,
                                const float p[3], float rref, prv_stats_t *st)
{
    sfit_i_sum_t s;
    sfit_i_rows_t q;
    const float nf = (float)n;
    float e1;
    int j;

    sfit_i_rows_init(&q, SFIT_I_ROWS_DIRS, rref, NULL, 0.0f);
    if (!sfit_i_pass(pts, n, c0->v, p, &q, 5, &s)) {
        return SFIT_E_DEGENERATE;
    }
    for (j = 0; j < 3; j++) {
        st->ubar[j] = s.tot[j] / nf;
    }
    e1 = s.tot[3] / nf;
    st->dbar = rref + e1;
    st->cost = s.tot[4] - s.tot[3] * e1;
    if (st->cost < 0.0f) {
        st->cost = 0.0f; /* rounding */
    }
    if (!sfit_i_isfinite(st->cost) || !sfit_i_isfinite(st->dbar)) {
        return SFIT_E_RANGE;
    }
    return SFIT_OK;
}

/* Pass B: A = sum (u - ubar)(u - ubar)^T (packed, s->tot[0..5]),
 * g = sum (u - ubar)(d - dbar) (s->tot[6..8]). */
static void prv_pass_b(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c0, const float p[3],
                       const prv_stats_t *st, sfit_i_sum_t *s)
{
    sfit_i_rows_t q;

    sfit_i_rows_init(&q, SFIT_I_ROWS_LM, 0.0f, st->ubar, st->dbar);
    (void)sfit_i_pass(pts, n, c0->v, p, &q, 9, s); /* pass A saw no zero distance */
}

/* Fewest samples a refinement accepts: 4 parameters plus one residual. */
#define PRV_REFINE_MIN_N ((SFIT_MIN_SAMPLES > 5u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)5u)

/* Arguments, options and samples; sets the tolerance and iteration bound. */
static sfit_status_t prv_check_args(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c0,
                                    const sfit_refine_cfg_t *cfg, float *tol, uint32_t *maxit)
{
    if (!sfit_i_isfinite(cfg->tol)
        || (cfg->tol != 0.0f && !(cfg->tol >= 1e-7f && cfg->tol <= 1e-2f))
        || sfit_i_bool_byte(&cfg->accept_unconverged) > 1u) {
        return SFIT_E_ARG;
    }
    *tol = (cfg->tol != 0.0f) ? cfg->tol : SFIT_REFINE_TOL;
    *maxit = (cfg->max_iters == 0u || cfg->max_iters > (uint32_t)SFIT_REFINE_MAX_ITERS)
                 ? (uint32_t)SFIT_REFINE_MAX_ITERS
                 : cfg->max_iters;
    if (sfit_i_check_fit(c0, NULL) != SFIT_OK) {
        return SFIT_E_NONFINITE;
    }
    return sfit_i_check_points(pts, n, PRV_REFINE_MIN_N);
}

/* The converged result from the offset p of the centre from c0. */
static sfit_status_t prv_finish(const sfit_vec3_t *c0, const float p[3], const prv_stats_t *cur,
                                size_t n, uint32_t it, bool converged,
                                sfit_refine_result_t *out)
{
    sfit_refine_result_t res;
    const float nf = (float)n;
    int j;
    memset(&res, 0, sizeof res);
    for (j = 0; j < 3; j++) {
        res.center.v[j] = c0->v[j] + p[j];
        if (!sfit_i_isfinite(res.center.v[j])) {
            return SFIT_E_RANGE;
        }
    }
    res.radius = cur->dbar;
    res.rms = SFIT_SQRTF(cur->cost / nf);
    res.noise_var = sfit_i_curvature_var(cur->cost / (nf - 4.0f), cur->dbar);
    res.n = (uint32_t)n;
    res.iterations = it;
    res.converged = converged;
    if (!(res.radius > 0.0f) || !sfit_i_isfinite(res.noise_var)) {
        return SFIT_E_RANGE;
    }
    *out = res;
    return SFIT_OK;
}

/* One Levenberg-Marquardt iteration: damped steps (at most
 * SFIT_REFINE_MAX_TRIALS) until one does not raise the cost. Returns 1 when
 * the accepted step is inside the tolerance (converged), 0 when a step was
 * accepted, or a negative status (SFIT_E_NO_CONVERGENCE when no trial was
 * accepted). */
static int prv_lm_iteration(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c0, float p[3],
                            prv_stats_t *cur, float *lambda, float tol)
{
    sfit_i_sum_t s;
    const float *const g = &s.tot[6];
    sfit_mat3_t am, l;
    int trials, j;

    prv_pass_b(pts, n, c0, p, cur, &s);
    sfit_i_sym_unpack(s.tot, &am);
    /* The undamped normal matrix itself must be regular: damping would make
     * a singular one (coincident samples) look solvable. */
    if (sfit_mat3_chol(&am, &l) != SFIT_OK) {
        return (int)SFIT_E_DEGENERATE;
    }
    for (trials = 0; trials < SFIT_REFINE_MAX_TRIALS; trials++) {
        sfit_mat3_t ad = am;
        sfit_vec3_t step = {{0.0f, 0.0f, 0.0f}};
        prv_stats_t trial;
        float pn[3], sn;
        int small;
        sfit_status_t st;
        for (j = 0; j < 3; j++) {
            ad.m[4 * j] += *lambda * am.m[4 * j];
        }
        if (sfit_mat3_chol(&ad, &l) != SFIT_OK) {
            return (int)SFIT_E_DEGENERATE;
        }
        sfit_i_chol_solve(&l, g, step.v);
        sn = SFIT_SQRTF(step.v[0] * step.v[0] + step.v[1] * step.v[1] + step.v[2] * step.v[2]);
        if (!sfit_i_isfinite(sn)) {
            return (int)SFIT_E_RANGE;
        }
        for (j = 0; j < 3; j++) {
            pn[j] = p[j] + step.v[j];
        }
        st = prv_pass_a(pts, n, c0, pn, cur->dbar, &trial);
        if (st != SFIT_OK) {
            return (int)st;
        }
        /* (1 + lambda) sn bounds the undamped step: a tiny step that only
         * reflects heavy damping does not count as converged */
        small = ((1.0f + *lambda) * sn <= tol * cur->dbar);
        if (trial.cost <= cur->cost * (1.0f + SFIT_REFINE_COST_ULPS * FLT_EPSILON) || small) {
            /* a step inside the tolerance is taken even if rounding made
             * the cost tick up: it is the converged answer */
            for (j = 0; j < 3; j++) {
                p[j] = pn[j];
            }
            *cur = trial;
            if (*lambda > 1e-6f) {
                *lambda *= 0.1f;
            }
            return small ? 1 : 0;
        }
        *lambda *= 10.0f;
    }
    return (int)SFIT_E_NO_CONVERGENCE;
}

sfit_status_t sfit_refine_points(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c0,
                              const sfit_refine_cfg_t *cfg, sfit_refine_result_t *out)
{
    prv_stats_t cur;
    float p[3] = {0.0f, 0.0f, 0.0f}, lambda = 1e-3f, tol = 0.0f;
    uint32_t maxit = 0u, it;
    sfit_status_t st;

    cfg = (cfg != NULL) ? cfg : &sfit_refine_cfg_default;
    st = (pts == NULL || c0 == NULL || out == NULL) ? SFIT_E_ARG
                                                    : prv_check_args(pts, n, c0, cfg, &tol, &maxit);
    if (st != SFIT_OK) {
        return st;
    }
    st = prv_pass_a(pts, n, c0, p, 0.0f, &cur);
    if (st != SFIT_OK) {
        return st;
    }
    /* once more with the mean distance as shift (exact cost) */
    st = prv_pass_a(pts, n, c0, p, cur.dbar, &cur);
    if (st != SFIT_OK) {
        return st;
    }
    for (it = 1u; it <= maxit; it++) {
        const int rc = prv_lm_iteration(pts, n, c0, p, &cur, &lambda, tol);
        if (rc < 0) {
            return (sfit_status_t)rc;
        }
        if (rc == 1) {
            return prv_finish(c0, p, &cur, n, it, true, out);
        }
    }
    if (cfg->accept_unconverged) {
        return prv_finish(c0, p, &cur, n, maxit, false, out);
    }
    return SFIT_E_NO_CONVERGENCE;
}

/* The combined recipe: self-calibrated start, geometric refinement,
 * sandwich covariance plus the bias estimate. */
const sfit_refined_cfg_t sfit_refined_cfg_default = {
    .selfcal = {.planar_ratio = 0.0f},
    .refine = {.max_iters = 0u, .tol = 0.0f, .accept_unconverged = false}};

sfit_status_t sfit_refine_fit(const sfit_vec3_t *pts, size_t n,
                              const sfit_refined_cfg_t *cfg, sfit_refine_result_t *out)
{
    sfit_selfcal_result_t s;
    sfit_refine_result_t r;
    sfit_uncert_t u;
    sfit_status_t st;

    cfg = (cfg != NULL) ? cfg : &sfit_refined_cfg_default;
    st = (out == NULL) ? SFIT_E_ARG : sfit_selfcal_points(pts, n, &cfg->selfcal, &s);
    if (st == SFIT_OK) {
        st = sfit_refine_points(pts, n, &s.fit.center, &cfg->refine, &r);
    }
    if (st == SFIT_OK) {
        st = sfit_uncert_geometric(pts, n, &r.center, &u);
    }
    if (st == SFIT_OK) {
        /* The geometric fit has a second-order bias (~ sigma^2 / r along the
         * cap axis) that does not shrink with N; the self-calibrated centre
         * has none to that order, so b = geometric - start estimates it.
         * Reported: the mean squared error Cov + b b^T (docs/coverage.md). */
        float *const cov = r.center_cov.m;
        float b[3], f;
        int i, j;
        for (i = 0; i < 3; i++) {
            b[i] = r.center.v[i] - s.fit.center.v[i];
        }
        f = sfit_i_cov_widen(s.noise_var, s.fit.radius, n);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                /* times the widening of docs/coverage.md rule 7; symmetric */
                cov[3 * i + j] = (u.center_cov.m[3 * i + j] + b[i] * b[j]) * f;
            }
            r.center_radius_cov[i] = u.center_radius_cov[i];
        }
        if (!sfit_i_isfinite(cov[0] + cov[4] + cov[8])) {
            st = SFIT_E_RANGE;
        }
    }
    if (st == SFIT_OK) {
        /* the rest of the one flat record: the sandwich's radius terms, the
         * start and its verdict */
        r.radius_var = u.radius_var;
        r.cov_noise_var = u.noise_var;
        r.eigenvalues = s.fit.eigenvalues;
        r.axis = s.fit.axis;
        r.trust_ratio = s.fit.trust_ratio;
        r.leontief_ratio = s.fit.leontief_ratio;
        r.flags = s.fit.flags;
        *out = r;
    }
    return st;
}
