/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_lean.c
 * @brief The screened sphere solve: Cholesky of C' = C - sigma^2 I and a
 * lower bound of lambda_min(C') instead of the Jacobi eigen-decomposition,
 * used when the bound proves the answer of the full solver.
 *
 * Implementation notes (derivation: docs/api.md#lean)
 * ---------------------------------------------------
 * For a symmetric positive definite 3x3 A with eigenvalues l1 <= l2 <= l3,
 * det A = l1 l2 l3 and e2 = l1 l2 + l1 l3 + l2 l3 (the sum of the 2x2
 * principal minors) >= l2 l3, so l1 >= det A / e2 (within a factor 3, tight
 * when l1 << l2). det C' = (l00 l11 l22)^2 comes from the Cholesky factor
 * that the solve needs anyway. With a relative margin of 2^-6 and an
 * absolute one of 2^-12 tr(C) (each far above the rounding of the bound and
 * of the Jacobi eigenvalues, a few tens of eps tr(C)) the screen passes only
 * when the full solver would find: not coincident, not collinear, not
 * near-planar (neither on C nor on C': lambda_min(C') <= lambda_min(C) and
 * tr(C') <= tr(C)), not below SFIT_MIN_SPREAD and trusted, and inside the
 * coverage limit (the caller proves the rounding flag clear on the same
 * bounds, sfit_i_rounding_test, once the centre is known); it then
 * returns the same centre and radius (the same Cholesky solve) and the same
 * status and flags. Every doubt
 * returns SFIT_I_SCREEN_TRIPPED and the caller runs the full solver.
 */
#include "sfit_solve.h"

#include <float.h>
#include <string.h>

/* Relative and absolute safety margins of the screen. */
#define PRV_REL 0.015625f     /* 2^-6 */
#define PRV_ABS 2.44140625e-4f /* 2^-12, times tr(C) */
/* lambda_min(C') >= PRV_COND tr(C): bounds cond(C') so that the rounding
 * of the full solver's trust ratio stays far below PRV_REL. */
#define PRV_COND 9.765625e-4f /* 2^-10 */
/* The screen promises that the full solver converges. A symmetric 3x3
 * needs 4-6 Jacobi sweeps (SFIT_JACOBI_MAX_SWEEPS); with a bound below 8
 * the full solver may stop with SFIT_E_NO_CONVERGENCE, so the screen is off
 * (unless there is no full solver: SFIT_FULL_SOLVER 0). */
#define PRV_SWEEPS_OK (!SFIT_FULL_SOLVER || SFIT_JACOBI_MAX_SWEEPS >= 8)

int sfit_i_rounding_test(uint32_t n, float lmax, float lmin, float r, const float c[3])
{
    const uint32_t b = SFIT_SUM_BLOCK;
    const uint32_t merges = n / b; /* block merges (integer count) */
    uint32_t g = n; /* the first block's term: N, or ceil(B^3 / N^2) past it */
    uint32_t u, umax = 0u;
    float k, cinf;
    int i;
    /* max |c_i| by the bits (no FP operation: non-negative floats are
     * ordered as their bit patterns). */
    for (i = 0; i < 3; i++) {
        memcpy(&u, &c[i], sizeof u);
        u &= 0x7FFFFFFFu;
        umax = (u > umax) ? u : umax;
    }
    memcpy(&cinf, &umax, sizeof cinf);
    if (n > b) {
        /* ceil(B^2 / N) <= B, then ceil(that B / N): integer steps (no
         * FLOPs), B^2 in 32 bits up to B = 46340, in 64 above. */
#if SFIT_SUM_BLOCK <= 46340
        g = (b * b + n - 1u) / n;
        g = (g * b + n - 1u) / n;
#else
        g = (uint32_t)(((uint64_t)b * b + n - 1u) / n);
        g = (uint32_t)(((uint64_t)g * b + n - 1u) / n);
#endif
    }
    k = SFIT_SQRTF(SFIT_ROUNDING_K2 * (float)(merges + 1u) + SFIT_ROUNDING_KB2 * (float)g);
    /* eps (lmax/lmin k + cinf/r) <= tol  <=>  lmax k r <= lmin (tol/eps r - cinf) */
    return !(lmax * k * r <= lmin * ((SFIT_ROUNDING_TOL / FLT_EPSILON) * r - cinf));
}

int sfit_i_solve_lean(const sfit_i_system_t *sys, uint32_t n, float ratio,
                      sfit_i_solution_t *out)
{
    sfit_mat3_t l;
    sfit_i_solution_t *const r = out; /* scratch until the screen passes */
    const sfit_mat3_t *const c = &sys->ms.c;
    const float *a = l.m;
    const float var = sys->sigma.var, scale = sys->scale; /* SFIT_NOISE_NONE or _ISO */
    float tr, s, e2, det, lo;

    tr = c->m[0] + c->m[4] + c->m[8];
    /* Below SFIT_COV_MIN_SAMPLES the coverage limit flags (sfit_i_cov_limit,
     * decided by the count alone): the full solver runs, so that a screened
     * result is never UNTRUSTED; a build without it (SFIT_FULL_SOLVER 0)
     * screens these too (same centre, radius and flags). */
    if (!PRV_SWEEPS_OK || (SFIT_FULL_SOLVER && n < SFIT_COV_MIN_SAMPLES) || !(tr > 0.0f)
        || !sfit_i_isfinite(tr)) {
        return SFIT_I_SCREEN_TRIPPED;
    }
    /* C' = C - var I: its lower triangle, what the Cholesky reads (and
     * all that the system holds of C). */
    l.m[0] = c->m[0] - var;
    l.m[3] = c->m[3];
    l.m[4] = c->m[4] - var;
    l.m[6] = c->m[6];
    l.m[7] = c->m[7];
    l.m[8] = c->m[8] - var;
    /* Everything relative to tr(C) (no overflow of the products; an
     * underflow only weakens the bound): e2 / tr^2 and det C' / tr^3. */
    s = 1.0f / tr;
    {
        const float b0 = a[0] * s, b4 = a[4] * s, b8 = a[8] * s;
        const float b3 = a[3] * s, b6 = a[6] * s, b7 = a[7] * s;
        e2 = (b0 * b4 - b3 * b3) + (b0 * b8 - b6 * b6) + (b4 * b8 - b7 * b7);
    }
    /* every member the caller reads (w: the solve below; the bounds in
     * eigenvalues v[0] and v[2] at the end; v[1] is not read: the caller
     * clears the three) */
    r->axis.v[0] = 0.0f;
    r->axis.v[1] = 0.0f;
    r->axis.v[2] = 0.0f;
    r->rho = 0.0f;
    r->flags = 0u;
    r->trace = a[0] + a[4] + a[8];
    if (!(e2 > 0.0f) || sfit_mat3_chol(&l, &l) != SFIT_OK) {
        return SFIT_I_SCREEN_TRIPPED;
    }
    det = ((a[0] * a[0]) * s) * ((a[4] * a[4]) * s) * ((a[8] * a[8]) * s); /* det C' / tr^3 */
    lo = (det / e2) * (1.0f - PRV_REL) - PRV_ABS; /* <= lambda_min(C') / tr */
    if (ratio < SFIT_COLLINEAR_RATIO) {
        ratio = SFIT_COLLINEAR_RATIO;
    }
    if (ratio < PRV_COND) {
        ratio = PRV_COND;
    }
    /* lambda_max(C) <= tr: lo >= ratio (1 + margin) proves lambda_min >= ratio lambda_max. */
    if (!(lo >= ratio * (1.0f + PRV_REL))) {
        return SFIT_I_SCREEN_TRIPPED; /* near-planar, collinear or ill-conditioned */
    }
    lo *= tr; /* <= lambda_min(C') */
    if (!(0.3f * tr > scale * scale)
        || !(0.3f * tr > (SFIT_I_SPREAD2_NORMAL ? SFIT_MIN_SPREAD * SFIT_MIN_SPREAD : FLT_MIN))) {
        return SFIT_I_SCREEN_TRIPPED; /* lambda_max(C) >= tr/3: not provably spread */
    }
    if (var > 0.0f) {
        /* rho(C'^-1 sigma^2 I) = var / lambda_min(C') <= var / lo. */
        if (!(var <= (1.0f - PRV_REL) * lo)) {
            return SFIT_I_SCREEN_TRIPPED;
        }
        r->rho = var / lo;
    }
    sfit_i_chol_solve(&l, sys->ms.rhs.v, r->w.v);
    if (sfit_i_solution_finite(r) != SFIT_OK) {
        return SFIT_I_SCREEN_TRIPPED;
    }
    /* The bounds must also prove that the fit is inside the coverage limit
     * (the bound of rho is an upper bound, the full solver decides above
     * it; so a screened result is never UNTRUSTED). The rounding flag:
     * the caller, on these bounds, once the centre is known. */
    if (r->rho > SFIT_COV_MAX_TRUST / (1.0f - SFIT_COV_MAX_TRUST)) {
        return SFIT_I_SCREEN_TRIPPED;
    }
    r->eigenvalues.v[0] = lo;
    r->eigenvalues.v[2] = (1.0f + PRV_REL) * tr;
    r->mode = SFIT_MODE_SPHERE;
    return SFIT_OK;
}

#if !SFIT_FULL_SOLVER
float sfit_i_lmin_lower(const sfit_mat3_t *c)
{
    sfit_mat3_t l;
    const float tr = c->m[0] + c->m[4] + c->m[8];
    float s, prod = 1.0f, minors = 0.0f, lo;
    int i;
    l = *c;
    if (!(tr > 0.0f) || !sfit_i_isfinite(tr)) {
        return 0.0f;
    }
    s = 1.0f / tr;
    /* e2 / tr^2: the three 2x2 principal minors of C / tr (i < j: rows
     * (0,1), (0,2), (1,2) with off-diagonal entries m[3], m[6], m[7]). */
    for (i = 0; i < 3; i++) {
        const int p = (i == 2) ? 1 : 0, q = (i == 0) ? 1 : 2;
        const float off = c->m[3 * q + p] * s;
        minors += (c->m[4 * p] * s) * (c->m[4 * q] * s) - off * off;
    }
    if (!(minors > 0.0f) || sfit_mat3_chol(&l, &l) != SFIT_OK) {
        return 0.0f;
    }
    for (i = 0; i < 3; i++) { /* det C / tr^3 = prod (l_ii^2 / tr) */
        prod *= (l.m[4 * i] * l.m[4 * i]) * s;
    }
    lo = ((prod / minors) * (1.0f - PRV_REL) - PRV_ABS) * tr;
    return (lo > 0.0f && sfit_i_isfinite(lo)) ? lo : 0.0f;
}
#endif /* !SFIT_FULL_SOLVER */
