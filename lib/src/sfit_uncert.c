/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_uncert.c
 * @brief Centre covariance and radius variance of a sphere fit.
 *
 * Implementation notes
 * --------------------
 * From moments: with C' = C - sigma^2 I (the noise-free covariance estimate)
 * and K = C'^-1, M^-1 = K / (N-1), so
 *   Cov(c) = sigma^2 (r^2 + 7.5 sigma^2) K / (N-1)
 *          + N sigma^4 / (N-1)^2 (r^2 K K + s (K a)(K a)^T).
 * Working with C' (entries ~ the spread squared) instead of M keeps the
 * numbers in range for any N. K is formed column by column from the
 * Cholesky factor of C'.
 *
 * From samples: J^T J = [[sum u u^T, sum u], [sum u^T, N]]; its inverse's
 * centre block is A^-1 with A = sum (u - ubar)(u - ubar)^T (the Schur
 * complement, summed centred so nothing cancels), the radius entry is
 * 1/N + ubar^T A^-1 ubar and the coupling -A^-1 ubar. Two passes; sums are
 * two-level (blocks of SFIT_UNCERT_BLOCK) to bound float rounding.
 *
 * Geometric fit (sandwich): the estimating equation of the profiled
 * orthogonal-distance fit is sum f_i (u_i - ubar) = 0; its derivative is
 * A = Mu + sum f_i (I - u_i u_i^T)/d_i and the covariance of its terms is
 * s^2 Mu (the residual f and the direction u are uncorrelated to the order
 * that matters: f is radial, u moves with the tangential noise). The 4x4
 * (centre, radius) sandwich reduces to the 3x3 blocks in the header because
 * the radius row of A is exactly that of J^T J. Pass 1 shifts the distances
 * by the first one so the mean distance carries no cancellation.
 */
#include "sfit/sfit_uncert.h"

#include <string.h>

#include "sfit/sfit_mat3.h"
#include "sfit_internal.h"

#define SFIT_UNCERT_BLOCK 64u

static sfit_status_t prv_check_fit(const sfit_vec3_t *center, float radius, float noise_var)
{
    int i;
    if (!sfit_i_isfinite(radius) || !(radius > 0.0f) || !sfit_i_isfinite(noise_var)
        || noise_var < 0.0f) {
        return SFIT_E_ARG;
    }
    for (i = 0; i < 3; i++) {
        if (!sfit_i_isfinite(center->v[i])) {
            return SFIT_E_ARG;
        }
    }
    return SFIT_OK;
}

/* Average the off-diagonal pairs (rounding left them unequal). */
static void prv_symmetrise(sfit_mat3_t *a)
{
    a->m[1] = a->m[3] = 0.5f * (a->m[1] + a->m[3]);
    a->m[2] = a->m[6] = 0.5f * (a->m[2] + a->m[6]);
    a->m[5] = a->m[7] = 0.5f * (a->m[5] + a->m[7]);
}

/* Inverse of an SPD matrix from its Cholesky factor (full symmetric). */
static void prv_chol_inverse(const sfit_mat3_t *l, sfit_mat3_t *inv)
{
    int j;
    for (j = 0; j < 3; j++) {
        sfit_vec3_t e, x;
        e.v[0] = (j == 0) ? 1.0f : 0.0f;
        e.v[1] = (j == 1) ? 1.0f : 0.0f;
        e.v[2] = (j == 2) ? 1.0f : 0.0f;
        (void)sfit_mat3_chol_solve(l, &e, &x);
        inv->m[j] = x.v[0];
        inv->m[3 + j] = x.v[1];
        inv->m[6 + j] = x.v[2];
    }
    prv_symmetrise(inv);
}

static void prv_pack(const sfit_mat3_t *a, float p[6])
{
    p[0] = a->m[0];
    p[1] = a->m[4];
    p[2] = a->m[8];
    p[3] = a->m[1];
    p[4] = a->m[2];
    p[5] = a->m[5];
}

static sfit_status_t prv_finish(sfit_uncert_t *u, sfit_uncert_t *out)
{
    int i;
    for (i = 0; i < 6; i++) {
        if (!sfit_i_isfinite(u->center_cov[i])) {
            return SFIT_E_RANGE;
        }
    }
    for (i = 0; i < 3; i++) {
        if (!sfit_i_isfinite(u->center_radius_cov[i])) {
            return SFIT_E_RANGE;
        }
    }
    if (!sfit_i_isfinite(u->radius_var)) {
        return SFIT_E_RANGE;
    }
    *out = *u;
    return SFIT_OK;
}

sfit_status_t sfit_uncert_moments(const sfit_moments_t *m, const sfit_vec3_t *center,
                                  float radius, float noise_var, sfit_uncert_noise_t kind,
                                  sfit_uncert_t *out)
{
    sfit_vec3_t mean, a, q;
    sfit_mat3_t c, l, k, cov;
    sfit_uncert_t u;
    float nf, n1, f1, f2, sgn, r2;
    int i, j;
    sfit_status_t st;

    if (m == NULL || center == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    if (kind != SFIT_UNCERT_NOISE_KNOWN && kind != SFIT_UNCERT_NOISE_ESTIMATED) {
        return SFIT_E_ARG;
    }
    st = prv_check_fit(center, radius, noise_var);
    if (st != SFIT_OK) {
        return st;
    }
    if (sfit_moments_count(m) < SFIT_MIN_SAMPLES) {
        return SFIT_E_TOO_FEW;
    }
    (void)sfit_moments_stats(m, &mean, &c, NULL);
    for (i = 0; i < 3; i++) {
        c.m[4 * i] -= noise_var;
        a.v[i] = mean.v[i] - center->v[i];
    }
    if (sfit_mat3_chol(&c, &l) != SFIT_OK) {
        return SFIT_E_NOT_POSDEF;
    }
    prv_chol_inverse(&l, &k);
    for (i = 0; i < 3; i++) {
        q.v[i] = k.m[3 * i] * a.v[0] + k.m[3 * i + 1] * a.v[1] + k.m[3 * i + 2] * a.v[2];
    }
    nf = (float)sfit_moments_count(m);
    n1 = nf - 1.0f;
    r2 = radius * radius;
    sgn = (kind == SFIT_UNCERT_NOISE_KNOWN) ? 1.0f : -1.0f;
    f1 = noise_var * (r2 + 7.5f * noise_var) / n1;
    f2 = (nf / n1) * (noise_var / n1) * noise_var;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            const float kk = k.m[3 * i] * k.m[j] + k.m[3 * i + 1] * k.m[3 + j]
                             + k.m[3 * i + 2] * k.m[6 + j];
            cov.m[3 * i + j] = f1 * k.m[3 * i + j] + f2 * (r2 * kk + sgn * q.v[i] * q.v[j]);
        }
    }
    memset(&u, 0, sizeof u);
    prv_pack(&cov, u.center_cov);
    u.radius_var = noise_var * (1.0f / nf + (a.v[0] * q.v[0] + a.v[1] * q.v[1] + a.v[2] * q.v[2]) / n1);
    for (i = 0; i < 3; i++) {
        u.center_radius_cov[i] = -noise_var * radius * q.v[i] / n1;
    }
    u.noise_var = noise_var;
    return prv_finish(&u, out);
}

/* Two-level accumulation of k floats: blk into tot every block. */
static void prv_flush(float *tot, float *blk, int k)
{
    int j;
    for (j = 0; j < k; j++) {
        tot[j] += blk[j];
        blk[j] = 0.0f;
    }
}

/* Distance and unit direction from the centre; 0 when the sample is at the
 * centre. */
static int prv_dist_dir(const sfit_vec3_t *x, const sfit_vec3_t *c, float *d, float u[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        u[i] = x->v[i] - c->v[i];
    }
    *d = SFIT_SQRTF(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (!(*d > 0.0f)) {
        return 0;
    }
    for (i = 0; i < 3; i++) {
        u[i] /= *d;
    }
    return 1;
}

sfit_status_t sfit_uncert_points(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                 float radius, float noise_var, sfit_uncert_t *out)
{
    float ub[3], tot[3] = {0.0f, 0.0f, 0.0f}, blk[3] = {0.0f, 0.0f, 0.0f};
    float at[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}, ab[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    sfit_mat3_t a, l, k;
    sfit_vec3_t q;
    sfit_uncert_t u;
    size_t i;
    uint32_t inblk = 0u;
    int j;
    float nf;
    sfit_status_t st;

    if (pts == NULL || center == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    st = prv_check_fit(center, radius, noise_var);
    if (st != SFIT_OK) {
        return st;
    }
    if (n < (size_t)SFIT_MIN_SAMPLES || n > (size_t)UINT32_MAX) {
        return (n < (size_t)SFIT_MIN_SAMPLES) ? SFIT_E_TOO_FEW : SFIT_E_RANGE;
    }
    for (i = 0; i < n; i++) {
        st = sfit_i_check_sample(pts[i].v);
        if (st != SFIT_OK) {
            return st;
        }
    }
    /* Pass 1: mean direction. */
    for (i = 0; i < n; i++) {
        float d[3], dist;
        if (!prv_dist_dir(&pts[i], center, &dist, d)) {
            return SFIT_E_DEGENERATE;
        }
        for (j = 0; j < 3; j++) {
            blk[j] += d[j];
        }
        if (++inblk == SFIT_UNCERT_BLOCK) {
            prv_flush(tot, blk, 3);
            inblk = 0u;
        }
    }
    nf = (float)n;
    for (j = 0; j < 3; j++) {
        ub[j] = (tot[j] + blk[j]) / nf;
    }
    /* Pass 2: A = sum (u - ubar)(u - ubar)^T. */
    inblk = 0u;
    for (i = 0; i < n; i++) {
        float d[3], dist;
        (void)prv_dist_dir(&pts[i], center, &dist, d);
        for (j = 0; j < 3; j++) {
            d[j] -= ub[j];
        }
        ab[0] += d[0] * d[0];
        ab[1] += d[1] * d[1];
        ab[2] += d[2] * d[2];
        ab[3] += d[0] * d[1];
        ab[4] += d[0] * d[2];
        ab[5] += d[1] * d[2];
        if (++inblk == SFIT_UNCERT_BLOCK) {
            prv_flush(at, ab, 6);
            inblk = 0u;
        }
    }
    prv_flush(at, ab, 6);
    sfit_i_sym_unpack(at, &a);
    if (sfit_mat3_chol(&a, &l) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    prv_chol_inverse(&l, &k);
    for (j = 0; j < 3; j++) {
        q.v[j] = k.m[3 * j] * ub[0] + k.m[3 * j + 1] * ub[1] + k.m[3 * j + 2] * ub[2];
    }
    memset(&u, 0, sizeof u);
    for (j = 0; j < 9; j++) {
        k.m[j] *= noise_var;
    }
    prv_pack(&k, u.center_cov);
    u.radius_var = noise_var * (1.0f / nf + ub[0] * q.v[0] + ub[1] * q.v[1] + ub[2] * q.v[2]);
    for (j = 0; j < 3; j++) {
        u.center_radius_cov[j] = -noise_var * q.v[j];
    }
    u.noise_var = noise_var;
    return prv_finish(&u, out);
}

/* p = a * b for full 3x3 matrices. */
static void prv_mul(const sfit_mat3_t *a, const sfit_mat3_t *b, sfit_mat3_t *p)
{
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            p->m[3 * i + j] = a->m[3 * i] * b->m[j] + a->m[3 * i + 1] * b->m[3 + j]
                              + a->m[3 * i + 2] * b->m[6 + j];
        }
    }
}

/* Fewest samples: 4 sphere parameters plus one residual degree of freedom. */
#define PRV_GEO_MIN_N ((SFIT_MIN_SAMPLES > 5u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)5u)

sfit_status_t sfit_uncert_geometric(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                    sfit_uncert_t *out)
{
    /* Row and column of the packed entries (XX, YY, ZZ, XY, XZ, YZ), the
     * order of sfit_i_sym_unpack. */
    static const uint8_t k_row[6] = {0u, 1u, 2u, 0u, 0u, 1u};
    static const uint8_t k_col[6] = {0u, 1u, 2u, 1u, 2u, 2u};
    /* sums: [0..2] u, [3] d - d0 (pass 1); [0..5] Mu, [6..11] H2, [12] f^2 (pass 2) */
    float tot[13], blk[13], ub[3], d0 = 0.0f, dbar, nf, s2;
    sfit_mat3_t mu, ap, l, k, w, cov;
    sfit_vec3_t q, wq;
    sfit_uncert_t u;
    size_t i;
    uint32_t inblk = 0u;
    int j;
    sfit_status_t st;

    if (pts == NULL || center == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    for (j = 0; j < 3; j++) {
        if (!sfit_i_isfinite(center->v[j])) {
            return SFIT_E_ARG;
        }
    }
    if (n < PRV_GEO_MIN_N) {
        return SFIT_E_TOO_FEW;
    }
    if (n > (size_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    for (i = 0; i < n; i++) {
        st = sfit_i_check_sample(pts[i].v);
        if (st != SFIT_OK) {
            return st;
        }
    }
    /* Pass 1: mean direction and mean distance (shifted by the first). */
    memset(tot, 0, sizeof tot);
    memset(blk, 0, sizeof blk);
    for (i = 0; i < n; i++) {
        float d, e[3];
        if (!prv_dist_dir(&pts[i], center, &d, e)) {
            return SFIT_E_DEGENERATE;
        }
        if (i == 0u) {
            d0 = d;
        }
        for (j = 0; j < 3; j++) {
            blk[j] += e[j];
        }
        blk[3] += d - d0;
        if (++inblk == SFIT_UNCERT_BLOCK) {
            prv_flush(tot, blk, 4);
            inblk = 0u;
        }
    }
    prv_flush(tot, blk, 4);
    nf = (float)n;
    for (j = 0; j < 3; j++) {
        ub[j] = tot[j] / nf;
    }
    dbar = d0 + tot[3] / nf;
    /* Pass 2: Mu = sum (u - ubar)(u - ubar)^T, H2 = sum f (I - u u^T) / d,
     * sum f^2 with f = d - dbar. */
    memset(tot, 0, sizeof tot);
    inblk = 0u;
    for (i = 0; i < n; i++) {
        float d, e[3], t[13], f, g;
        (void)prv_dist_dir(&pts[i], center, &d, e);
        f = d - dbar;
        g = f / d;
        for (j = 0; j < 6; j++) {
            const int r = k_row[j], c2 = k_col[j];
            t[j] = (e[r] - ub[r]) * (e[c2] - ub[c2]);
            t[6 + j] = g * (((j < 3) ? 1.0f : 0.0f) - e[r] * e[c2]);
        }
        t[12] = f * f;
        for (j = 0; j < 13; j++) {
            blk[j] += t[j];
        }
        if (++inblk == SFIT_UNCERT_BLOCK) {
            prv_flush(tot, blk, 13);
            inblk = 0u;
        }
    }
    prv_flush(tot, blk, 13);
    s2 = tot[12] / (nf - 4.0f);
    if (!sfit_i_isfinite(s2)) {
        return SFIT_E_RANGE;
    }
    sfit_i_sym_unpack(&tot[0], &mu);
    if (sfit_mat3_chol(&mu, &l) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    for (j = 0; j < 6; j++) {
        tot[6 + j] += tot[j];
    }
    sfit_i_sym_unpack(&tot[6], &ap);
    if (sfit_mat3_chol(&ap, &l) != SFIT_OK) {
        /* The cost is not convex at this centre: not a minimum of the
         * geometric fit, or the noise swamps the curvature of the data. */
        return SFIT_E_NOT_POSDEF;
    }
    prv_chol_inverse(&l, &k);
    prv_mul(&k, &mu, &w); /* W = K Mu */
    prv_mul(&w, &k, &cov); /* Cov / s^2 = K Mu K */
    for (j = 0; j < 9; j++) {
        cov.m[j] *= s2;
    }
    prv_symmetrise(&cov);
    for (j = 0; j < 3; j++) {
        q.v[j] = k.m[3 * j] * ub[0] + k.m[3 * j + 1] * ub[1] + k.m[3 * j + 2] * ub[2];
    }
    for (j = 0; j < 3; j++) {
        wq.v[j] = w.m[3 * j] * q.v[0] + w.m[3 * j + 1] * q.v[1] + w.m[3 * j + 2] * q.v[2];
    }
    memset(&u, 0, sizeof u);
    prv_pack(&cov, u.center_cov);
    /* Var(r) = s^2 (1/N + ubar^T K Mu K ubar), K Mu K ubar = W q. */
    u.radius_var = s2 * (1.0f / nf + ub[0] * wq.v[0] + ub[1] * wq.v[1] + ub[2] * wq.v[2]);
    for (j = 0; j < 3; j++) {
        u.center_radius_cov[j] = -s2 * wq.v[j];
    }
    u.noise_var = s2;
    return prv_finish(&u, out);
}
