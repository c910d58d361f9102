/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_mat3.c
 * @brief Cholesky factor/solve and cyclic Jacobi for symmetric 3x3 matrices.
 */
#include "sfit/sfit_mat3.h"

#include <string.h>

#include "sfit_mat3_i.h"

sfit_status_t sfit_mat3_chol(const sfit_mat3_t *a, sfit_mat3_t *l)
{
    float a00, a10, a11, a20, a21, a22, dmax, tol;
    float l00, l10, l11, l20, l21, l22, p;

    if (a == NULL || l == NULL) {
        return SFIT_E_ARG;
    }
    a00 = a->m[0]; a10 = a->m[3]; a11 = a->m[4];
    a20 = a->m[6]; a21 = a->m[7]; a22 = a->m[8];
    dmax = a00;
    if (a11 > dmax) { dmax = a11; }
    if (a22 > dmax) { dmax = a22; }
    /* The negated comparisons also reject NaN (every comparison is false). */
    if (!(dmax > 0.0f) || !sfit_i_isfinite(dmax)) {
        return SFIT_E_NOT_POSDEF;
    }
    tol = SFIT_CHOL_PIVOT_EPS * dmax;
    if (!(a00 > tol)) {
        return SFIT_E_NOT_POSDEF;
    }
    l00 = SFIT_SQRTF(a00);
    l10 = a10 / l00;
    l20 = a20 / l00;
    p = a11 - l10 * l10;
    if (!(p > tol)) {
        return SFIT_E_NOT_POSDEF; /* also catches a NaN/Inf in a10 */
    }
    l11 = SFIT_SQRTF(p);
    l21 = (a21 - l20 * l10) / l11;
    p = a22 - l20 * l20 - l21 * l21;
    if (!(p > tol)) {
        return SFIT_E_NOT_POSDEF; /* also catches a NaN/Inf in a20 or a21 */
    }
    l22 = SFIT_SQRTF(p);

    l->m[0] = l00; l->m[1] = 0.0f; l->m[2] = 0.0f;
    l->m[3] = l10; l->m[4] = l11;  l->m[5] = 0.0f;
    l->m[6] = l20; l->m[7] = l21;  l->m[8] = l22;
    return SFIT_OK;
}

void sfit_i_chol_solve(const sfit_mat3_t *l, const float b[3], float x[3])
{
    const float *L = l->m;
    float x0, x1, x2;

    sfit_i_chol_forward(l, b, x); /* L y = b, y in x (it reads b[i] before writing y[i]) */
    /* Backward: L^T x = y. */
    x2 = x[2] / L[8];
    x1 = (x[1] - L[7] * x2) / L[4];
    x0 = (x[0] - L[3] * x1 - L[6] * x2) / L[0];
    x[0] = x0; x[1] = x1; x[2] = x2;
}

/* sfit_i_chol_solve() with the check: written only when x is finite. */
sfit_status_t sfit_mat3_chol_solve(const sfit_mat3_t *l, const sfit_vec3_t *b, sfit_vec3_t *x)
{
    float t[3];

    if (l == NULL || b == NULL || x == NULL) {
        return SFIT_E_ARG;
    }
    sfit_i_chol_solve(l, b->v, t);
    if (!sfit_i_isfinite(t[0]) || !sfit_i_isfinite(t[1]) || !sfit_i_isfinite(t[2])) {
        return SFIT_E_RANGE; /* a zero or non-finite factor, a non-finite b, or overflow */
    }
    x->v[0] = t[0]; x->v[1] = t[1]; x->v[2] = t[2];
    return SFIT_OK;
}

/* 1 when x is zero (either sign): its bits with the sign shifted out (a
 * NaN is not zero, as with the float comparison). */
SFIT_INLINE int prv_is_zero(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return (u << 1) == 0u;
}

/* (x, y) := (c x - s y, s x + c y): a plane rotation of one pair. */
static void prv_rot2(float *x, float *y, float c, float s)
{
    const float a = *x, b = *y;
    *x = c * a - s * b;
    *y = s * a + c * b;
}

/* One Jacobi rotation in plane j (0: (0,1), 1: (0,2), 2: (1,2)) zeroing
 * a[p][q] (full row-major working copy a, accumulated eigenvectors v or
 * NULL). */
static void prv_rotate(float a[9], float v[9], int j)
{
    const int p = j / 2, q = 1 + (j + 1) / 2, r = 3 - p - q; /* r: the third index */
    float *const apq = &a[3 * p + q], *const aqp = &a[3 * q + p];
    float *const app = &a[4 * p], *const aqq = &a[4 * q];
    const float g = 100.0f * SFIT_FABSF(*apq);
    float theta, t, c, s;
    int k;

    if (prv_is_zero(*apq)) {
        return;
    }
    /* Negligible against both diagonal entries: drop it (keeps the small
     * eigenvalue accurate to its own relative precision). */
    if (SFIT_FABSF(*app) + g != SFIT_FABSF(*app) || SFIT_FABSF(*aqq) + g != SFIT_FABSF(*aqq)) {
        theta = (*aqq - *app) / (2.0f * *apq);
        if (SFIT_FABSF(theta) > 1.0e18f) {
            t = 0.5f / theta; /* theta^2 would overflow; t ~ 1/(2 theta) */
        } else {
            t = 1.0f / (SFIT_FABSF(theta) + SFIT_SQRTF(theta * theta + 1.0f));
            if (theta < 0.0f) {
                t = -t;
            }
        }
        c = 1.0f / SFIT_SQRTF(t * t + 1.0f);
        s = t * c;
        theta = t * *apq; /* one product for both (the stores may alias) */
        *app -= theta;
        *aqq += theta;
        prv_rot2(&a[3 * r + p], &a[3 * r + q], c, s);
        a[3 * p + r] = a[3 * r + p];
        a[3 * q + r] = a[3 * r + q];
        for (k = 0; (v != NULL) && k < 9; k += 3) {
            prv_rot2(&v[k + p], &v[k + q], c, s);
        }
    }
    *apq = 0.0f;
    *aqp = 0.0f;
}

sfit_status_t sfit_i_eig_sym(float A[9], sfit_vec3_t *w, float *V)
{
    int k, converged = 0;

    for (k = 0; k < 9; k++) {
        if (!sfit_i_isfinite(A[k])) {
            return SFIT_E_NONFINITE;
        }
        if (V != NULL) {
            V[k] = (k % 4 == 0) ? 1.0f : 0.0f;
        }
    }
    /* Cyclic sweeps over the planes (0,1), (0,2), (1,2); converged when
     * every off-diagonal entry is zero at a sweep's start (or at the end);
     * each tested on its bits, one at a time (prv_is_zero: no FP compare,
     * one M4F instruction less per test than the float comparison). */
    for (k = 0; k <= SFIT_JACOBI_MAX_SWEEPS; k++) {
        int j;
        if (prv_is_zero(A[1]) && prv_is_zero(A[2]) && prv_is_zero(A[5])) {
            converged = 1;
            break;
        }
        for (j = 0; j < 3 && k < SFIT_JACOBI_MAX_SWEEPS; j++) {
            prv_rotate(A, V, j);
        }
    }
    /* Entries near FLT_MAX can overflow inside a rotation. */
    for (k = 0; k < 9; k++) {
        if (!sfit_i_isfinite(A[k]) || (V != NULL && !sfit_i_isfinite(V[k]))) {
            return SFIT_E_RANGE;
        }
    }
    if (!converged) {
        return SFIT_E_NO_CONVERGENCE;
    }
    /* The diagonal, sorted ascending (3-element network: pairs (0,1),
     * (1,2), (0,1)) in place, with V's columns. */
    A[1] = A[4];
    A[2] = A[8];
    for (k = 0; k < 3; k++) {
        const int i = k % 2;
        if (A[i] > A[i + 1]) {
            int m;
            for (m = (V != NULL) ? 0 : 9; m < 12; m += 3) { /* V's rows, then A's diagonal */
                float *const x = (m < 9) ? &V[m + i] : &A[i];
                const float tmp = x[0];
                x[0] = x[1];
                x[1] = tmp;
            }
        }
    }
    w->v[0] = A[0]; w->v[1] = A[1]; w->v[2] = A[2];
    return SFIT_OK;
}

sfit_status_t sfit_mat3_eig_sym(const sfit_mat3_t *a, sfit_vec3_t *w, sfit_mat3_t *v)
{
    float A[9], V[9];
    sfit_status_t st;

    if (a == NULL || w == NULL) {
        return SFIT_E_ARG;
    }
    sfit_i_sym_full(a, A);
    st = sfit_i_eig_sym(A, w, (v != NULL) ? V : NULL);
    if (st == SFIT_OK && v != NULL) {
        memcpy(v->m, V, sizeof V);
    }
    return st;
}
