/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_incr.c
 * @brief Double-precision references for the incremental estimator.
 *
 * Derivation (n samples -> n+1 with x = x_{n+1}; m_n the mean,
 * M2_n = sum y y^T, M3_n = sum |y|^2 y about m_n, C_n = M2_n/(n-1),
 * S_n = M3_n/(n-1)):
 *
 *  e = x - m_n;  m_{n+1} = m_n + e/(n+1)                       (eq. 224)
 *  delta = x - m_{n+1} = n/(n+1) e = n (m_{n+1} - m_n)        (eq. 225/226)
 *  M2_{n+1} = M2_n + n/(n+1) e e^T = M2_n + (n+1)/n delta delta^T,
 *  so C_{n+1} = (n-1)/n C_n + (n+1)/n^2 delta delta^T        (eq. 227: OK)
 *  C'_{n+1} = C_{n+1} - Sigma = (n-1)/n C'_n - Sigma/n
 *             + (n+1)/n^2 delta delta^T                      (eq. 228: OK)
 *  Sherman-Morrison on C_{n+1} = (n-1)/n (C_n + k^-1 delta delta^T),
 *  k = n(n-1)/(n+1):
 *  C_{n+1}^-1 = n/(n-1) C_n^-1 (I - delta delta^T C_n^-1 / (k + delta^T C_n^-1 delta))
 *                                      (eq. 229 is printed with '+': WRONG)
 *  With u = m_{n+1} - m_n = delta/n and sum y = 0,
 *  sum_{i<=n} |y_i - u|^2 (y_i - u) = M3_n - (2 M2_n + tr M2_n) u - n |u|^2 u,
 *  plus the new point's |delta|^2 delta. Rewriting M2_n with M2_{n+1}:
 *  M3_{n+1} = M3_n - (2 M2_{n+1} + tr M2_{n+1}) delta/n
 *             + (n+1)(n+2)/n^2 |delta|^2 delta, i.e.
 *  S_{n+1} = (n-1)/n S_n + (1/n)(-2 C_{n+1} - tr C_{n+1}
 *            + (n+1)(n+2)/n^2 delta delta^T) delta            (eq. 230: OK)
 *  c = m + C^-1 S/2 (eq. 231: OK); with N = n+1 samples the radius is
 *  r^2 = (N-1)/N tr C + |m - c|^2 = n/(n+1) tr C_{n+1} + ... (eq. 232: OK).
 *
 * The library form: see lib/src/sfit_incr.c (written separately; this file
 * only re-implements its mathematics in double).
 */
#include "sfit_ref_incr.h"

#include <math.h>
#include <string.h>

#include "sfit_ref.h"

typedef double rl_t; /* double is ample here: see the tolerances in test_incr.c */

static void rl_cov(const double *cov, double s[3][3])
{
    memset(s, 0, 9 * sizeof(double));
    if (cov != NULL) {
        s[0][0] = cov[0];
        s[1][1] = cov[1];
        s[2][2] = cov[2];
        s[0][1] = s[1][0] = cov[3];
        s[0][2] = s[2][0] = cov[4];
        s[1][2] = s[2][1] = cov[5];
    }
}

/* Inverse of a 3x3 by cofactors; nonzero if singular. */
static int rl_inv3(const double a[3][3], double out[3][3])
{
    rl_t c[3][3], det;
    int i, j;
    c[0][0] = (rl_t)a[1][1] * a[2][2] - (rl_t)a[1][2] * a[2][1];
    c[0][1] = (rl_t)a[1][2] * a[2][0] - (rl_t)a[1][0] * a[2][2];
    c[0][2] = (rl_t)a[1][0] * a[2][1] - (rl_t)a[1][1] * a[2][0];
    c[1][0] = (rl_t)a[0][2] * a[2][1] - (rl_t)a[0][1] * a[2][2];
    c[1][1] = (rl_t)a[0][0] * a[2][2] - (rl_t)a[0][2] * a[2][0];
    c[1][2] = (rl_t)a[0][1] * a[2][0] - (rl_t)a[0][0] * a[2][1];
    c[2][0] = (rl_t)a[0][1] * a[1][2] - (rl_t)a[0][2] * a[1][1];
    c[2][1] = (rl_t)a[0][2] * a[1][0] - (rl_t)a[0][0] * a[1][2];
    c[2][2] = (rl_t)a[0][0] * a[1][1] - (rl_t)a[0][1] * a[1][0];
    det = (rl_t)a[0][0] * c[0][0] + (rl_t)a[0][1] * c[0][1] + (rl_t)a[0][2] * c[0][2];
    if (!(fabs(det) > 0.0) || !isfinite((double)det)) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            out[i][j] = (double)(c[j][i] / det); /* adjugate = cofactor^T */
        }
    }
    return 0;
}

/* ---------------------------------------------------------------------- */
/* The chapter's recursion                                                 */

int ref_incr_chapter_start(ref_incr_chapter_t *s, const double (*x)[3], size_t n0,
                           const double *cov, int printed_229)
{
    ref_incr_chapter_t t;
    int i, j;
    if (s == NULL || x == NULL || n0 < 4) {
        return -1;
    }
    memset(&t, 0, sizeof t);
    if (ref_moments(x, n0, t.m, t.C, t.S) || rl_inv3(REF_C3(t.C), t.Ci)) {
        return -1;
    }
    rl_cov(cov, t.sig);
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            t.Cp[i][j] = t.C[i][j] - t.sig[i][j];
        }
    }
    t.n = n0;
    t.ugdk = (cov != NULL);
    t.printed_229 = printed_229;
    *s = t;
    return 0;
}

void ref_incr_chapter_add(ref_incr_chapter_t *s, const double x[3])
{
    const rl_t n = (rl_t)s->n;
    rl_t dl[3], u[3], k, a, b, tr, g, v[3];
    double Ci[3][3];
    int i, j;

    for (i = 0; i < 3; ++i) {
        const rl_t e = (rl_t)x[i] - s->m[i];
        dl[i] = n / (n + 1.0) * e;                   /* eq. 225/226 */
        s->m[i] = (double)(s->m[i] + e / (n + 1.0)); /* eq. 224 */
    }
    /* eq. 229 (derived sign), with the C_n^-1 of before the update */
    for (i = 0; i < 3; ++i) {
        u[i] = s->Ci[i][0] * dl[0] + s->Ci[i][1] * dl[1] + s->Ci[i][2] * dl[2];
    }
    k = n * (n - 1.0) / (n + 1.0) + (dl[0] * u[0] + dl[1] * u[1] + dl[2] * u[2]);
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            /* C^-1 (I -/+ d d^T C^-1 / k) = C^-1 -/+ (C^-1 d)(C^-1 d)^T / k */
            const rl_t corr = u[i] * u[j] / k;
            Ci[i][j] = (double)(n / (n - 1.0)
                                * (s->Ci[i][j] + (s->printed_229 ? corr : -corr)));
        }
    }
    memcpy(s->Ci, Ci, sizeof Ci);
    /* eq. 227, 228 */
    a = (n - 1.0) / n;
    b = (n + 1.0) / (n * n);
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            s->C[i][j] = (double)(a * s->C[i][j] + b * dl[i] * dl[j]);
            s->Cp[i][j] = (double)(a * s->Cp[i][j] - s->sig[i][j] / n + b * dl[i] * dl[j]);
        }
    }
    /* eq. 230 with C_{n+1} */
    tr = (rl_t)s->C[0][0] + s->C[1][1] + s->C[2][2];
    g = (n + 1.0) * (n + 2.0) / (n * n) * (dl[0] * dl[0] + dl[1] * dl[1] + dl[2] * dl[2]);
    for (i = 0; i < 3; ++i) {
        v[i] = -2.0 * (s->C[i][0] * dl[0] + s->C[i][1] * dl[1] + s->C[i][2] * dl[2])
               + (g - tr) * dl[i];
    }
    for (i = 0; i < 3; ++i) {
        s->S[i] = (double)(a * s->S[i] + v[i] / n);
    }
    s->n++;
}

int ref_incr_chapter_estimate(const ref_incr_chapter_t *s, double c[3], double *r)
{
    double inv[3][3];
    rl_t w[3], r2, tr;
    const rl_t n = (rl_t)s->n;
    int i;

    if (s->ugdk) {
        if (rl_inv3(s->Cp, inv)) {
            return -1;
        }
        tr = (rl_t)s->Cp[0][0] + s->Cp[1][1] + s->Cp[2][2];
    } else {
        memcpy(inv, s->Ci, sizeof inv);
        tr = (rl_t)s->C[0][0] + s->C[1][1] + s->C[2][2];
    }
    for (i = 0; i < 3; ++i) {
        w[i] = 0.5 * ((rl_t)inv[i][0] * s->S[0] + (rl_t)inv[i][1] * s->S[1]
                       + (rl_t)inv[i][2] * s->S[2]);
    }
    r2 = (n - 1.0) / n * tr + w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    if (!(r2 > 0.0)) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        c[i] = (double)(s->m[i] + w[i]);
    }
    *r = (double)sqrt(r2);
    return 0;
}

/* ---------------------------------------------------------------------- */
/* The library's formulation                                               */

void ref_incr_lib_init(ref_incr_lib_t *s, const double *cov, size_t block)
{
    memset(s, 0, sizeof *s);
    s->block = block < 2 ? 2 : block;
    rl_cov(cov, s->sig);
}

/* Move p to the mean; re-express T and Q about it. */
static void rl_lib_rebase(ref_incr_lib_t *s)
{
    rl_t pn[3], dn[3], m3[3], md[3], mdn[3], tr, dd;
    int i;
    for (i = 0; i < 3; ++i) {
        pn[i] = (rl_t)s->p[i] + s->d[i];
        dn[i] = ((rl_t)s->p[i] + s->d[i]) - (rl_t)(double)pn[i]; /* residue of rounding p */
    }
    tr = (rl_t)s->M2[0][0] + s->M2[1][1] + s->M2[2][2];
    for (i = 0; i < 3; ++i) {
        md[i] = (rl_t)s->M2[i][0] * s->d[0] + (rl_t)s->M2[i][1] * s->d[1]
                + (rl_t)s->M2[i][2] * s->d[2];
    }
    for (i = 0; i < 3; ++i) {
        m3[i] = s->T[i] - (rl_t)s->Q * s->d[i] - 2.0 * md[i]; /* centred third moment */
    }
    for (i = 0; i < 3; ++i) {
        mdn[i] = s->M2[i][0] * dn[0] + s->M2[i][1] * dn[1] + s->M2[i][2] * dn[2];
    }
    dd = dn[0] * dn[0] + dn[1] * dn[1] + dn[2] * dn[2];
    for (i = 0; i < 3; ++i) {
        s->T[i] = (double)(m3[i] + 2.0 * mdn[i] + (tr + (rl_t)s->n * dd) * dn[i]);
        s->p[i] = (double)pn[i];
        s->d[i] = (double)dn[i];
    }
    s->Q = (double)(tr + (rl_t)s->n * dd);
    s->nb = 0;
}

void ref_incr_lib_add(ref_incr_lib_t *s, const double x[3])
{
    rl_t z[3], e[3], q;
    int i, j;
    if (s->n == 0) {
        memcpy(s->p, x, sizeof s->p);
    }
    s->n++;
    for (i = 0; i < 3; ++i) {
        z[i] = (rl_t)x[i] - s->p[i];
        e[i] = z[i] - s->d[i];
        s->d[i] = (double)(s->d[i] + e[i] / (rl_t)s->n);
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            s->M2[i][j] = (double)(s->M2[i][j]
                                   + ((rl_t)s->n - 1.0) / (rl_t)s->n * e[i] * e[j]);
        }
    }
    q = z[0] * z[0] + z[1] * z[1] + z[2] * z[2];
    for (i = 0; i < 3; ++i) {
        s->T[i] = (double)(s->T[i] + q * z[i]);
    }
    s->Q = (double)(s->Q + q);
    s->nb++;
    if (s->nb >= s->block || 8 * s->nb >= s->n) {
        rl_lib_rebase(s);
    }
}

int ref_incr_lib_estimate(const ref_incr_lib_t *s, double c[3], double *r)
{
    double A[3][3], inv[3][3];
    rl_t b[3], a[3], w[3], k = (rl_t)s->n - 1.0, tr = 0.0, r2;
    int i, j;
    if (s->n < 4) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            A[i][j] = (double)((rl_t)s->M2[i][j] - k * s->sig[i][j]);
        }
        tr += A[i][i];
    }
    for (i = 0; i < 3; ++i) {
        b[i] = 0.5 * ((rl_t)s->T[i] - (rl_t)s->Q * s->d[i])
               - k * ((rl_t)s->sig[i][0] * s->d[0] + (rl_t)s->sig[i][1] * s->d[1]
                      + (rl_t)s->sig[i][2] * s->d[2]);
    }
    if (rl_inv3(REF_C3(A), inv)) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        a[i] = inv[i][0] * b[0] + inv[i][1] * b[1] + inv[i][2] * b[2];
        w[i] = a[i] - s->d[i];
    }
    r2 = tr / (rl_t)s->n + w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    if (!(r2 > 0.0)) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        c[i] = (double)((rl_t)s->p[i] + a[i]);
    }
    *r = (double)sqrt(r2);
    return 0;
}
