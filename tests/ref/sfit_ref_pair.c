/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_pair.c
 * @brief Double-precision oracle for the pair of segments (sfit_ref_pair.h):
 * every frame kept, 6x6 systems, no shifted sums.
 */
#include "sfit_ref_pair.h"

#include <math.h>
#include <string.h>

/* y = a x (3x3) */
static void rp_mv(const double a[9], const double x[3], double y[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        y[i] = a[3 * i] * x[0] + a[3 * i + 1] * x[1] + a[3 * i + 2] * x[2];
    }
}

/* y = a^T x */
static void rp_mtv(const double a[9], const double x[3], double y[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        y[i] = a[i] * x[0] + a[3 + i] * x[1] + a[6 + i] * x[2];
    }
}

/* c = a^T b */
static void rp_mtm(const double a[9], const double b[9], double c[9])
{
    int i, j, k;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += a[3 * k + i] * b[3 * k + j];
            }
            c[3 * i + j] = s;
        }
    }
}

/* Solve the n x n system a x = b (a destroyed) by Gaussian elimination with
 * partial pivoting; nonzero when singular. */
static int rp_gauss(double *a, double *b, int n, double *x)
{
    int i, j, k;
    for (k = 0; k < n; k++) {
        int p = k;
        double amax = fabs(a[k * n + k]);
        for (i = k + 1; i < n; i++) {
            if (fabs(a[i * n + k]) > amax) {
                amax = fabs(a[i * n + k]);
                p = i;
            }
        }
        if (!(amax > 0.0)) {
            return 1;
        }
        if (p != k) {
            for (j = 0; j < n; j++) {
                const double t = a[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = t;
            }
            {
                const double t = b[k];
                b[k] = b[p];
                b[p] = t;
            }
        }
        for (i = k + 1; i < n; i++) {
            const double f = a[i * n + k] / a[k * n + k];
            for (j = k; j < n; j++) {
                a[i * n + j] -= f * a[k * n + j];
            }
            b[i] -= f * b[k];
        }
    }
    for (i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (j = i + 1; j < n; j++) {
            s -= a[i * n + j] * x[j];
        }
        x[i] = s / a[i * n + i];
    }
    return 0;
}

/* Cyclic Jacobi for a symmetric n x n (n <= 6): w unsorted, columns of v. */
static void rp_jacobi(const double *a_in, int n, double *w, double *v)
{
    double a[36];
    int i, j, k, sweep;
    memcpy(a, a_in, sizeof(double) * (size_t)(n * n));
    for (i = 0; i < n * n; i++) {
        v[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
    }
    for (sweep = 0; sweep < 100; sweep++) {
        double off = 0.0;
        for (i = 0; i < n; i++) {
            for (j = i + 1; j < n; j++) {
                off += a[i * n + j] * a[i * n + j];
            }
        }
        if (off < 1e-300) {
            break;
        }
        for (i = 0; i < n; i++) {
            for (j = i + 1; j < n; j++) {
                const double apq = a[i * n + j];
                double th, t, c, s;
                if (apq == 0.0) {
                    continue;
                }
                th = (a[j * n + j] - a[i * n + i]) / (2.0 * apq);
                t = (th >= 0.0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (k = 0; k < n; k++) {
                    const double aki = a[k * n + i], akj = a[k * n + j];
                    a[k * n + i] = c * aki - s * akj;
                    a[k * n + j] = s * aki + c * akj;
                }
                for (k = 0; k < n; k++) {
                    const double aik = a[i * n + k], ajk = a[j * n + k];
                    a[i * n + k] = c * aik - s * ajk;
                    a[j * n + k] = s * aik + c * ajk;
                }
                for (k = 0; k < n; k++) {
                    const double vki = v[k * n + i], vkj = v[k * n + j];
                    v[k * n + i] = c * vki - s * vkj;
                    v[k * n + j] = s * vki + c * vkj;
                }
            }
        }
    }
    for (i = 0; i < n; i++) {
        w[i] = a[i * n + i];
    }
}

/* mid += J E J^T (J 6x3, E 3x3, mid 6x6; row-major): one frame's term of
 * a sandwich's middle. */
static void rp_add_jej(const double jm[18], const double e[9], double mid[36])
{
    int i, j, p, q;
    for (i = 0; i < 6; i++) {
        for (j = 0; j < 6; j++) {
            double s = 0.0;
            for (p = 0; p < 3; p++) {
                for (q = 0; q < 3; q++) {
                    s += jm[3 * i + p] * e[3 * p + q] * jm[3 * j + q];
                }
            }
            mid[6 * i + j] += s;
        }
    }
}

/* cov := the parent block of H^-1 M H^-1 (H, M 6x6; H^-1 column by
 * column by Gaussian elimination). 1 when H is singular. */
static int rp_sandwich6(const double h[36], const double mid[36], double cov[9])
{
    double hi[36];
    int i, j, k;
    for (k = 0; k < 6; k++) {
        double hh[36], b[6] = {0, 0, 0, 0, 0, 0}, x[6];
        memcpy(hh, h, sizeof hh);
        b[k] = 1.0;
        if (rp_gauss(hh, b, 6, x) != 0) {
            return 1;
        }
        for (i = 0; i < 6; i++) {
            hi[6 * i + k] = x[i];
        }
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            int p, q;
            for (p = 0; p < 6; p++) {
                for (q = 0; q < 6; q++) {
                    s += hi[6 * i + p] * mid[6 * p + q] * hi[6 * j + q];
                }
            }
            cov[3 * i + j] = s;
        }
    }
    return 0;
}

static int rp_inv3(const double a[9], double inv[9])
{
    const double det = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6])
                       + a[2] * (a[3] * a[7] - a[4] * a[6]);
    if (!(fabs(det) > 0.0)) {
        return 1;
    }
    inv[0] = (a[4] * a[8] - a[5] * a[7]) / det;
    inv[1] = (a[2] * a[7] - a[1] * a[8]) / det;
    inv[2] = (a[1] * a[5] - a[2] * a[4]) / det;
    inv[3] = (a[5] * a[6] - a[3] * a[8]) / det;
    inv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
    inv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
    inv[6] = (a[3] * a[7] - a[4] * a[6]) / det;
    inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
    inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
    return 0;
}

int ref_pair_tpl(const double (*p)[3], size_t n, ref_pair_tpl_t *t)
{
    double j[9] = {0};
    size_t i;
    int a, b;
    for (a = 0; a < 3; a++) {
        double s = 0.0;
        for (i = 0; i < n; i++) {
            s += p[i][a];
        }
        t->cen[a] = s / (double)n;
    }
    for (i = 0; i < n; i++) {
        double q[3], q2;
        for (a = 0; a < 3; a++) {
            q[a] = p[i][a] - t->cen[a];
        }
        q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                j[3 * a + b] += (a == b ? q2 : 0.0) - q[a] * q[b];
            }
        }
    }
    t->m = (double)n;
    return rp_inv3(j, t->jinv);
}

/* var (tr J^-1 I - J^-1) */
static void rp_k(const ref_pair_tpl_t *t, double var, double k[9])
{
    const double tr = t->jinv[0] + t->jinv[4] + t->jinv[8];
    int i;
    for (i = 0; i < 9; i++) {
        k[i] = var * ((i % 4 == 0 ? tr : 0.0) - t->jinv[i]);
    }
}

/* The 6x6 matrix H and right-hand side of the (corrected) system in
 * centroid coordinates: frame by frame, A = R_p^T R_c,
 * d' = R_p^T (cg_c - cg_p), cg = t + R cen. */
static void rp_system(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                      const ref_pair_tpl_t *tc, double var_p, double var_c, double h[36],
                      double rhs[6], double kp[9], double kc[9])
{
    size_t fi;
    int i, j;
    double N = (double)n;
    memset(h, 0, sizeof(double) * 36);
    memset(rhs, 0, sizeof(double) * 6);
    rp_k(tp, var_p, kp);
    rp_k(tc, var_c, kc);
    for (fi = 0; fi < n; fi++) {
        double a[9], cgp[3], cgc[3], dt[3], d[3], g[3];
        rp_mtm(f[fi].rp, f[fi].rc, a);
        rp_mv(f[fi].rp, tp->cen, cgp);
        rp_mv(f[fi].rc, tc->cen, cgc);
        for (i = 0; i < 3; i++) {
            dt[i] = (f[fi].tc[i] + cgc[i]) - (f[fi].tp[i] + cgp[i]);
        }
        rp_mtv(f[fi].rp, dt, d);
        rp_mtv(a, d, g);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                h[6 * i + 3 + j] -= a[3 * i + j];
                h[6 * (3 + j) + i] -= a[3 * i + j];
            }
            rhs[i] += d[i];
            rhs[3 + i] -= g[i];
        }
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            h[6 * i + j] = (i == j ? N : 0.0) - N * kp[3 * i + j];
            h[6 * (3 + i) + 3 + j] = (i == j ? N : 0.0) - N * kc[3 * i + j];
        }
    }
}

int ref_pair_score(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                   const ref_pair_tpl_t *tc, double var_p, double var_c, double cp[3],
                   double cc[3])
{
    double h[36], rhs[6], x[6], kp[9], kc[9], t[3];
    int i;
    rp_system(f, n, tp, tc, var_p, var_c, h, rhs, kp, kc);
    if (rp_gauss(h, rhs, 6, x) != 0) {
        return 1;
    }
    rp_mv(kp, x, t);
    for (i = 0; i < 3; i++) {
        cp[i] = tp->cen[i] + x[i] - 0.5 * t[i];
    }
    rp_mv(kc, x + 3, t);
    for (i = 0; i < 3; i++) {
        cc[i] = tc->cen[i] + x[3 + i] - 0.5 * t[i];
    }
    return 0;
}

static void rp_sign(double v[3])
{
    int im = 0, i;
    for (i = 1; i < 3; i++) {
        if (fabs(v[i]) > fabs(v[im])) {
            im = i;
        }
    }
    if (v[im] < 0.0) {
        for (i = 0; i < 3; i++) {
            v[i] = -v[i];
        }
    }
}

int ref_pair_sara(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                  const ref_pair_tpl_t *tc, double var_p, double var_c, double axis[3],
                  double eig3[3])
{
    double h[36], rhs[6], kp[9], kc[9], w[6], v[36], nn;
    int i, j, k, imin = 0;
    rp_system(f, n, tp, tc, var_p, var_c, h, rhs, kp, kc);
    if (var_p == 0.0 && var_c == 0.0) {
        rp_jacobi(h, 6, w, v);
        for (i = 1; i < 6; i++) {
            if (w[i] < w[imin]) {
                imin = i;
            }
        }
        for (i = 0; i < 3; i++) {
            axis[i] = v[6 * i + imin];
        }
    } else {
        /* Schur complement H11 - H12 H22^-1 H21 in double. */
        double h22[9], h22i[9], s[9], w3[3], v3[9];
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                h22[3 * i + j] = h[6 * (3 + i) + 3 + j];
            }
        }
        if (rp_inv3(h22, h22i) != 0) {
            return 1;
        }
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                double acc = h[6 * i + j];
                int a, b;
                for (a = 0; a < 3; a++) {
                    for (b = 0; b < 3; b++) {
                        acc -= h[6 * i + 3 + a] * h22i[3 * a + b] * h[6 * (3 + b) + j];
                    }
                }
                s[3 * i + j] = acc;
            }
        }
        rp_jacobi(s, 3, w3, v3);
        for (i = 1; i < 3; i++) {
            if (w3[i] < w3[imin]) {
                imin = i;
            }
        }
        for (i = 0; i < 3; i++) {
            axis[i] = v3[3 * i + imin];
        }
        if (eig3 != NULL) {
            /* ascending */
            for (i = 0; i < 3; i++) {
                eig3[i] = w3[i] / (double)n;
            }
            for (i = 0; i < 3; i++) {
                for (k = i + 1; k < 3; k++) {
                    if (eig3[k] < eig3[i]) {
                        const double t = eig3[i];
                        eig3[i] = eig3[k];
                        eig3[k] = t;
                    }
                }
            }
        }
    }
    nn = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if (!(nn > 0.0)) {
        return 1;
    }
    for (i = 0; i < 3; i++) {
        axis[i] /= nn;
    }
    rp_sign(axis);
    return 0;
}

int ref_pair_hinge_point(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                         const ref_pair_tpl_t *tc, double var_p, double var_c,
                         const double axis[3], double cp[3])
{
    /* Least squares with the constraint axis . u = axis . mid (Lagrange,
     * 7x7), u the parent unknown in centroid coordinates. */
    double h[36], rhs[6], kp[9], kc[9], a7[49], b7[7], x7[7], mid[3] = {0, 0, 0}, t[3];
    size_t fi;
    int i, j;
    rp_system(f, n, tp, tc, var_p, var_c, h, rhs, kp, kc);
    for (fi = 0; fi < n; fi++) {
        double cgp[3], cgc[3], dt[3], d[3];
        rp_mv(f[fi].rp, tp->cen, cgp);
        rp_mv(f[fi].rc, tc->cen, cgc);
        for (i = 0; i < 3; i++) {
            dt[i] = (f[fi].tc[i] + cgc[i]) - (f[fi].tp[i] + cgp[i]);
        }
        rp_mtv(f[fi].rp, dt, d);
        for (i = 0; i < 3; i++) {
            mid[i] += 0.5 * d[i] / (double)n;
        }
    }
    memset(a7, 0, sizeof a7);
    for (i = 0; i < 6; i++) {
        for (j = 0; j < 6; j++) {
            a7[7 * i + j] = h[6 * i + j];
        }
        b7[i] = rhs[i];
    }
    for (i = 0; i < 3; i++) {
        a7[7 * i + 6] = axis[i];
        a7[7 * 6 + i] = axis[i];
    }
    b7[6] = axis[0] * mid[0] + axis[1] * mid[1] + axis[2] * mid[2];
    if (rp_gauss(a7, b7, 7, x7) != 0) {
        return 1;
    }
    rp_mv(kp, x7, t);
    for (i = 0; i < 3; i++) {
        cp[i] = tp->cen[i] + x7[i] - 0.5 * t[i];
    }
    return 0;
}

/* out = var ([x] J^-1 [x]^T + I / m) */
static void rp_point_noise(const ref_pair_tpl_t *t, double var, const double x[3], double out[9])
{
    const double cx[9] = {0.0, -x[2], x[1], x[2], 0.0, -x[0], -x[1], x[0], 0.0};
    int i, j, a, b;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (a = 0; a < 3; a++) {
                for (b = 0; b < 3; b++) {
                    s += cx[3 * i + a] * t->jinv[3 * a + b] * cx[3 * j + b];
                }
            }
            out[3 * i + j] = var * (s + (i == j ? 1.0 / t->m : 0.0));
        }
    }
}

int ref_pair_cov(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                 const ref_pair_tpl_t *tc, double var_p, double var_c, const double cp[3],
                 const double cc[3], double cov[9], double *cost, double *expect)
{
    double h[36], rhs[6], kp[9], kc[9], pm[9], cm[9], xp[3], xc[3], mid[36];
    size_t fi;
    int i, j;
    rp_system(f, n, tp, tc, var_p, var_c, h, rhs, kp, kc);
    for (i = 0; i < 3; i++) {
        xp[i] = cp[i] - tp->cen[i];
        xc[i] = cc[i] - tc->cen[i];
    }
    rp_point_noise(tp, var_p, xp, pm);
    rp_point_noise(tc, var_c, xc, cm);
    memset(mid, 0, sizeof mid);
    *cost = 0.0;
    for (fi = 0; fi < n; fi++) {
        double a[9], e[9], jm[18], cgp[3], cgc[3], dt[3], d[3], ac[3], eps[3];
        rp_mtm(f[fi].rp, f[fi].rc, a);
        /* Cov(eps) = P + A C A^T */
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                double s = pm[3 * i + j];
                int p, q;
                for (p = 0; p < 3; p++) {
                    for (q = 0; q < 3; q++) {
                        s += a[3 * i + p] * cm[3 * p + q] * a[3 * j + q];
                    }
                }
                e[3 * i + j] = s;
            }
        }
        /* J = [I; -A^T] (6x3) */
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                jm[3 * i + j] = (i == j) ? 1.0 : 0.0;
                jm[3 * (3 + i) + j] = -a[3 * j + i];
            }
        }
        rp_add_jej(jm, e, mid);
        /* eps at (cp, cc), original coordinates */
        (void)cgp;
        (void)cgc;
        for (i = 0; i < 3; i++) {
            dt[i] = f[fi].tc[i] - f[fi].tp[i];
        }
        rp_mtv(f[fi].rp, dt, d);
        rp_mv(a, cc, ac);
        for (i = 0; i < 3; i++) {
            eps[i] = cp[i] - ac[i] - d[i];
        }
        *cost += eps[0] * eps[0] + eps[1] * eps[1] + eps[2] * eps[2];
    }
    *expect = ((double)n - 2.0) * (pm[0] + pm[4] + pm[8] + cm[0] + cm[4] + cm[8]);
    return rp_sandwich6(h, mid, cov);
}

/* ---------------------------------------------------------------------------
 * The weighted default (docs/pair.md#weighting), independently: per-frame
 * 6x6 normal equations with a constant child-frame weight, the noise maps
 * D(Z) = Z - (K Z + Z K) / 2 + sum_pq Sigma_pq [e_p] Z [e_q]^T inverted
 * exactly as 9x9 linear operators. */

/* [e_p] Z [e_q]^T accumulated with weight c into o. */
static void rp_skew_acc(int p, int q, const double z[9], double c, double o[9])
{
    double ep[9] = {0}, eq[9] = {0}, t[9];
    int i, j, k;
    static const int a1[3] = {7, 2, 3}, a2[3] = {5, 6, 1}; /* +1 and -1 entries of [e_p] */
    ep[a1[p]] = 1.0;
    ep[a2[p]] = -1.0;
    eq[a1[q]] = 1.0;
    eq[a2[q]] = -1.0;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += ep[3 * i + k] * z[3 * k + j];
            }
            t[3 * i + j] = s;
        }
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += t[3 * i + k] * eq[3 * j + k];
            }
            o[3 * i + j] += c * s;
        }
    }
}

/* D(Z) for the rotation noise Sigma = var J^-1 of a template. */
static void rp_dmap(const ref_pair_tpl_t *t, double var, const double z[9], double o[9])
{
    double k[9], sig[9];
    int i, j, l, p, q;
    for (i = 0; i < 9; i++) {
        sig[i] = var * t->jinv[i];
    }
    rp_k(t, var, k);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (l = 0; l < 3; l++) {
                s += k[3 * i + l] * z[3 * l + j] + z[3 * i + l] * k[3 * l + j];
            }
            o[3 * i + j] = z[3 * i + j] - 0.5 * s;
        }
    }
    for (p = 0; p < 3; p++) {
        for (q = 0; q < 3; q++) {
            rp_skew_acc(p, q, z, sig[3 * p + q], o);
        }
    }
}

/* o = D^-1(y), the 9x9 operator built column by column and solved. */
static int rp_dinv(const ref_pair_tpl_t *t, double var, const double y[9], double o[9])
{
    double a[81], b[9];
    int i, c;
    for (c = 0; c < 9; c++) {
        double z[9] = {0}, d[9];
        z[c] = 1.0;
        rp_dmap(t, var, z, d);
        for (i = 0; i < 9; i++) {
            a[9 * i + c] = d[i];
        }
    }
    memcpy(b, y, sizeof b);
    return rp_gauss(a, b, 9, o);
}

/* c = a b (3x3) */
static void rp_mm(const double a[9], const double b[9], double c[9])
{
    int i, j, k;
    double t[9];
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += a[3 * i + k] * b[3 * k + j];
            }
            t[3 * i + j] = s;
        }
    }
    memcpy(c, t, sizeof t);
}

/* Frame quantities in centroid coordinates: A, g' = R_c^T (cg_c - cg_p). */
static void rp_frame(const ref_pair_frame_t *fr, const ref_pair_tpl_t *tp,
                     const ref_pair_tpl_t *tc, double a[9], double g[3])
{
    double cgp[3], cgc[3], dt[3];
    int i;
    rp_mtm(fr->rp, fr->rc, a);
    rp_mv(fr->rp, tp->cen, cgp);
    rp_mv(fr->rc, tc->cen, cgc);
    for (i = 0; i < 3; i++) {
        dt[i] = (fr->tc[i] + cgc[i]) - (fr->tp[i] + cgp[i]);
    }
    rp_mtv(fr->rc, dt, g);
}

int ref_pair_score_wls(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                       const ref_pair_tpl_t *tc, double var_p, double var_c, const double cp0[3],
                       const double cc0[3], double cp[3], double cc[3], double cov[9])
{
    double pm[9], cm[9], xp[3], xc[3], sig[9], w[9], v[9], pinv[9], cinv[9], t[9];
    double sav[9] = {0}, sa[9] = {0}, sg[3] = {0}, savg[3] = {0}, h[36], rhs[6], x[6];
    double mid[36];
    const double N = (double)n;
    size_t fi;
    int i, j;
    for (i = 0; i < 3; i++) {
        xp[i] = cp0[i] - tp->cen[i];
        xc[i] = cc0[i] - tc->cen[i];
    }
    rp_point_noise(tp, var_p, xp, pm);
    rp_point_noise(tc, var_c, xc, cm);
    /* Sigma = mean A^T P A + C, W = Sigma^-1 */
    memcpy(sig, cm, sizeof sig);
    for (fi = 0; fi < n; fi++) {
        double a[9], g[3], at[9];
        rp_frame(&f[fi], tp, tc, a, g);
        for (i = 0; i < 9; i++) {
            at[i] = a[3 * (i % 3) + i / 3];
        }
        rp_mm(at, pm, t);
        rp_mm(t, a, t);
        for (i = 0; i < 9; i++) {
            sig[i] += t[i] / N;
        }
    }
    if (rp_inv3(sig, w) != 0 || rp_dinv(tc, var_c, w, v) != 0) {
        return 1;
    }
    /* P^-1, C^-1 (P = I - K_p / 2) */
    rp_k(tp, var_p, t);
    for (i = 0; i < 9; i++) {
        t[i] = (i % 4 == 0 ? 1.0 : 0.0) - 0.5 * t[i];
    }
    if (rp_inv3(t, pinv) != 0) {
        return 1;
    }
    rp_k(tc, var_c, t);
    for (i = 0; i < 9; i++) {
        t[i] = (i % 4 == 0 ? 1.0 : 0.0) - 0.5 * t[i];
    }
    if (rp_inv3(t, cinv) != 0) {
        return 1;
    }
    for (fi = 0; fi < n; fi++) {
        double a[9], g[3], at[9], vg[3], avg[3], av[9];
        rp_frame(&f[fi], tp, tc, a, g);
        for (i = 0; i < 9; i++) {
            at[i] = a[3 * (i % 3) + i / 3];
        }
        rp_mm(a, v, av);
        rp_mm(av, at, t);
        rp_mv(v, g, vg);
        rp_mv(a, vg, avg);
        for (i = 0; i < 9; i++) {
            sav[i] += t[i];
            sa[i] += a[i];
        }
        for (i = 0; i < 3; i++) {
            sg[i] += g[i];
            savg[i] += avg[i];
        }
    }
    /* H = [[D_p^-1(sum A V A^T), -P^-1 (sum A) C^-1 W], [., N W]],
     * rhs = (P^-1 sum A V g', -W C^-1 sum g'). */
    {
        double hpp[9], hpc[9], bp[3], bc[3];
        if (rp_dinv(tp, var_p, sav, hpp) != 0) {
            return 1;
        }
        rp_mm(pinv, sa, hpc);
        rp_mm(hpc, cinv, hpc);
        rp_mm(hpc, w, hpc);
        rp_mv(pinv, savg, bp);
        rp_mv(cinv, sg, t);
        rp_mv(w, t, bc);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                h[6 * i + j] = hpp[3 * i + j];
                h[6 * i + 3 + j] = -hpc[3 * i + j];
                h[6 * (3 + j) + i] = -hpc[3 * i + j];
                h[6 * (3 + i) + 3 + j] = N * w[3 * i + j];
            }
            rhs[i] = bp[i];
            rhs[3 + i] = -bc[i];
        }
    }
    {
        double hh[36], bb[6];
        memcpy(hh, h, sizeof hh);
        memcpy(bb, rhs, sizeof bb);
        if (rp_gauss(hh, bb, 6, x) != 0) {
            return 1;
        }
    }
    for (i = 0; i < 3; i++) {
        cp[i] = tp->cen[i] + x[i];
        cc[i] = tc->cen[i] + x[3 + i];
    }
    if (cov == NULL) {
        return 0;
    }
    /* First-order sandwich at the solution: psi_f = [A; -I] W eps_f, eps_f
     * = A^T u - v - g' (child frame), Cov(eps_f) = A^T P A + C. */
    for (i = 0; i < 3; i++) {
        xp[i] = x[i];
        xc[i] = x[3 + i];
    }
    rp_point_noise(tp, var_p, xp, pm);
    rp_point_noise(tc, var_c, xc, cm);
    memset(mid, 0, sizeof mid);
    for (fi = 0; fi < n; fi++) {
        double a[9], g[3], at[9], e[9], jw[18];
        rp_frame(&f[fi], tp, tc, a, g);
        for (i = 0; i < 9; i++) {
            at[i] = a[3 * (i % 3) + i / 3];
        }
        rp_mm(at, pm, e);
        rp_mm(e, a, e);
        for (i = 0; i < 9; i++) {
            e[i] += cm[i];
        }
        /* jw = [A W; -W] (6x3) */
        rp_mm(a, w, t);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                jw[3 * i + j] = t[3 * i + j];
                jw[3 * (3 + i) + j] = -w[3 * i + j];
            }
        }
        rp_add_jej(jw, e, mid);
    }
    return rp_sandwich6(h, mid, cov);
}

/* ---------------------------------------------------------------------------
 * Skin motion linear in the joint angle (docs/pair.md#model-error), frame by
 * frame: theta_f = vee(skew(Abar^T (A_f - Abar))), the residual
 * r_f = A_f^T c_p - g_f (child frame), their centred cross and second
 * sums; the regression of r on theta restricted to the directions theta
 * excites, less the part a centre shift absorbs; the noise's share from
 * the mean residual covariance; the offset's prior and the absorbed shift. */

/* E[beta beta^T] for E[X_pq X_p'q'] = C_pp' S_qq' (beta_a = X_bd - X_db). */
static void rp_bcov(const double c[9], const double s[9], double o[9])
{
    int a, i;
    for (a = 0; a < 3; a++) {
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        for (i = 0; i < 3; i++) {
            const int b2 = (i + 1) % 3, d2 = (i + 2) % 3;
            o[3 * a + i] = c[3 * b + b2] * s[3 * d + d2] - c[3 * b + d2] * s[3 * d + b2]
                           - c[3 * d + b2] * s[3 * b + d2] + c[3 * d + d2] * s[3 * b + b2];
        }
    }
}

#define RP_PI 3.14159265358979323846

/* chi^2(3)'s distribution function, chi^2(nu)'s upper tail, and the
 * density of t = sqrt(X), X ~ chi^2(nu) (smooth at 0 for nu >= 1). */
static double rp_chi3_cdf(double x)
{
    return x <= 0.0 ? 0.0 : erf(sqrt(0.5 * x)) - sqrt(2.0 * x / RP_PI) * exp(-0.5 * x);
}

static double rp_chi_sf(int nu, double x)
{
    if (nu == 1) {
        return erfc(sqrt(0.5 * x));
    }
    if (nu == 3) {
        return 1.0 - rp_chi3_cdf(x);
    }
    return exp(-0.5 * x) * (1.0 + 0.5 * x + 0.125 * x * x); /* nu = 6 */
}

static double rp_t_pdf(int nu, double t)
{
    const double x = t * t;
    double px;
    if (nu == 1) {
        return 2.0 * exp(-0.5 * x) / sqrt(2.0 * RP_PI); /* pdf(x) 2t */
    }
    if (nu == 3) {
        px = sqrt(x) * exp(-0.5 * x) / (sqrt(2.0) * sqrt(RP_PI)); /* 2^1.5 Gamma(1.5) */
    } else {
        px = x * x * exp(-0.5 * x) / 16.0; /* 2^3 Gamma(3) */
    }
    return px * 2.0 * t;
}

double ref_pair_sta_coverage(int nu, double rho, double kfq, double knc)
{
    const double q = 7.814727903251178; /* chi^2(3) 95 % */
    /* t = sqrt(X) to sqrt(rho nu), or to 12 where chi^2(nu <= 6)'s tail
     * (below 1e-26) is covered anyway (s^2 small there: the integrand is its
     * density); fine steps near 0, where the heavy tail of s^2 lives */
    const double top = (rho * (double)nu < 144.0) ? sqrt(rho * (double)nu) : 12.0;
    const int m = 40000; /* Simpson, even */
    double sum = 0.0;
    int i;
    /* covered when s^2_true <= 0 (X >= rho nu) or Z <= q kfq (rho - knc) / (rho nu / X - 1) */
    for (i = 0; i <= m; i++) {
        const double t = top * (double)i / (double)m;
        const double w = (i == 0 || i == m) ? 1.0 : ((i % 2) ? 4.0 : 2.0);
        double f = 0.0;
        if (t > 0.0) {
            const double st = rho * (double)nu / (t * t) - 1.0;
            f = rp_t_pdf(nu, t) * (st > 0.0 ? rp_chi3_cdf(q * kfq * (rho - knc) / st) : 1.0);
        }
        sum += w * f;
    }
    return sum * top / (3.0 * (double)m) + rp_chi_sf(nu, top * top);
}

int ref_pair_sta_quantiles(int nu, double *kfq, double *knc)
{
    static double cache[7][2]; /* by nu; computed once */
    double lo = 0.1, hi = 1e4;
    int it;
    if (nu != 1 && nu != 3 && nu != 6) {
        return 1;
    }
    if (cache[nu][0] > 0.0) {
        *kfq = cache[nu][0];
        *knc = cache[nu][1];
        return 0;
    }
    /* kfq: much skin (rho large, the noise's share negligible) */
    for (it = 0; it < 200; it++) {
        const double mid = sqrt(lo * hi);
        if (ref_pair_sta_coverage(nu, 1e6, mid, 0.0) < 0.95) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    *kfq = sqrt(lo * hi);
    lo = -1.0;
    hi = 1.0;
    for (it = 0; it < 100; it++) {
        const double mid = 0.5 * (lo + hi);
        if (ref_pair_sta_coverage(nu, 20.0, *kfq, mid) > 0.95) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    *knc = 0.5 * (lo + hi);
    cache[nu][0] = *kfq;
    cache[nu][1] = *knc;
    return 0;
}

int ref_pair_sta(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                 const ref_pair_tpl_t *tc, double var_p, double var_c, const double cp[3],
                 const double cc[3], double model[9], double *ratio, double *excess)
{
    static const double k_chi[3] = {3.841, 2.605, 2.099};
    static const int k_nu[3] = {1, 3, 6};
    double abar[9] = {0}, sig[9] = {0}, pm[9], cm[9], xp[3], xc[3];
    double st[3] = {0}, sr[3] = {0}, stt[9] = {0}, str[9] = {0};
    double cmat[9], xm[9], w[3], v[9], cinv[9] = {0}, proj[9] = {0}, t[9], mm[9], minv[9];
    double beta[3], ess = 0.0, vis, noise, trc, trs, nk = 0.0, pr[9], g2[9], h[9], den;
    double wmax;
    size_t fi;
    int i, j, k;
    memset(model, 0, 9 * sizeof model[0]);
    *ratio = 0.0;
    *excess = 0.0;
    if (n < 3) {
        return 1;
    }
    for (fi = 0; fi < n; fi++) {
        double a[9];
        rp_mtm(f[fi].rp, f[fi].rc, a);
        for (k = 0; k < 9; k++) {
            abar[k] += a[k] / (double)n;
        }
    }
    for (i = 0; i < 3; i++) {
        xp[i] = cp[i] - tp->cen[i];
        xc[i] = cc[i] - tc->cen[i];
    }
    rp_point_noise(tp, var_p, xp, pm);
    rp_point_noise(tc, var_c, xc, cm);
    for (fi = 0; fi < n; fi++) {
        double a[9], b[9], m[9], th[3], r[3], dt[3], g[3], atp[9], ap[9];
        rp_mtm(f[fi].rp, f[fi].rc, a);
        for (k = 0; k < 9; k++) {
            b[k] = a[k] - abar[k];
        }
        rp_mtm(abar, b, m);
        th[0] = 0.5 * (m[7] - m[5]);
        th[1] = 0.5 * (m[2] - m[6]);
        th[2] = 0.5 * (m[3] - m[1]);
        for (i = 0; i < 3; i++) {
            dt[i] = f[fi].tc[i] - f[fi].tp[i];
        }
        rp_mtv(f[fi].rc, dt, g);
        rp_mtv(a, cp, r);
        for (i = 0; i < 3; i++) {
            r[i] -= g[i];
            st[i] += th[i];
            sr[i] += r[i];
        }
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                stt[3 * i + j] += th[i] * th[j];
                str[3 * i + j] += th[i] * r[j];
            }
        }
        /* A^T P A */
        rp_mtm(a, pm, atp);
        rp_mm(atp, a, ap);
        for (k = 0; k < 9; k++) {
            sig[k] += ap[k] / (double)n;
        }
    }
    for (k = 0; k < 9; k++) {
        sig[k] += cm[k];
        cmat[k] = stt[k] - st[k / 3] * st[k % 3] / (double)n;
        xm[k] = str[k] - st[k / 3] * sr[k % 3] / (double)n;
    }
    /* less the rotation noise shared by theta and r: per frame
     * E[dr dtheta^T] = [xc]x Sc + A^T [xp]x Sp A, Sc = var_c J_c^-1 */
    for (fi = 0; fi < n; fi++) {
        double a[9], cxm[9], pxm[9], sc[9], sp[9], t1[9], t2[9], t3[9];
        const double *xx[2] = {xc, xp};
        double *cm2[2] = {cxm, pxm};
        int q;
        rp_mtm(f[fi].rp, f[fi].rc, a);
        for (q = 0; q < 2; q++) {
            const double *z = xx[q];
            double *o = cm2[q];
            o[0] = 0.0; o[1] = -z[2]; o[2] = z[1];
            o[3] = z[2]; o[4] = 0.0; o[5] = -z[0];
            o[6] = -z[1]; o[7] = z[0]; o[8] = 0.0;
        }
        for (k = 0; k < 9; k++) {
            sc[k] = var_c * tc->jinv[k];
            sp[k] = var_p * tp->jinv[k];
        }
        rp_mm(cxm, sc, t1);
        rp_mm(pxm, sp, t2);
        rp_mm(t2, a, t3);
        rp_mtm(a, t3, t2);
        for (k = 0; k < 9; k++) {
            /* xm(a, k): theta_a r_k; the expectation's (k, a) entry */
            xm[3 * (k % 3) + k / 3] -= (t1[k] + t2[k]) * (double)(n - 1) / (double)n;
        }
    }
    rp_jacobi(cmat, 3, w, v);
    wmax = fmax(w[0], fmax(w[1], w[2]));
    if (!(wmax > 0.0)) {
        return 1;
    }
    for (k = 0; k < 3; k++) {
        if (w[k] >= 0.03 * wmax) {
            nk += 1.0;
            for (i = 0; i < 9; i++) {
                const double p = v[3 * (i / 3) + k] * v[3 * (i % 3) + k];
                cinv[i] += p / w[k];
                proj[i] += p;
            }
        }
    }
    rp_mm(cmat, proj, t);
    rp_mm(proj, t, cmat);
    rp_mm(proj, xm, t);
    memcpy(xm, t, sizeof t);
    for (k = 0; k < 3; k++) { /* columns of X: the cross sum of theta with r_k */
        double col[3], u[3];
        for (i = 0; i < 3; i++) {
            col[i] = xm[3 * i + k];
        }
        rp_mv(cinv, col, u);
        ess += col[0] * u[0] + col[1] * u[1] + col[2] * u[2];
    }
    for (i = 0; i < 3; i++) {
        const int b = (i + 1) % 3, d = (i + 2) % 3;
        beta[i] = xm[3 * b + d] - xm[3 * d + b];
    }
    trc = cmat[0] + cmat[4] + cmat[8];
    for (k = 0; k < 9; k++) {
        mm[k] = ((k % 4 == 0) ? trc : 0.0) - cmat[k];
    }
    if (rp_inv3(mm, minv) != 0) {
        return 1;
    }
    {
        double u[3];
        rp_mv(minv, beta, u);
        vis = ess - (beta[0] * u[0] + beta[1] * u[1] + beta[2] * u[2]);
    }
    trs = sig[0] + sig[4] + sig[8];
    rp_bcov(cmat, sig, t);
    rp_mm(minv, t, h);
    noise = nk * trs - (h[0] + h[4] + h[8]);
    /* the offset's prior: independent per-marker slides of the child
     * cluster, seen at the joint point: [xc] J_c^-1 [xc]^T + I / M_c */
    rp_point_noise(tc, 1.0, xc, pr);
    rp_mm(cmat, cmat, g2);
    rp_bcov(g2, pr, t);
    rp_mm(minv, t, h);
    den = (pr[0] + pr[4] + pr[8]) * trc - (h[0] + h[4] + h[8]);
    if (noise > 0.0) {
        *ratio = vis / noise;
    }
    if (noise > 0.0 && den > 0.0 && vis > k_chi[(int)nk - 1] * noise) {
        double kfq = 0.0, knc = 0.0, s2;
        if (ref_pair_sta_quantiles(k_nu[(int)nk - 1], &kfq, &knc) != 0) {
            return 1;
        }
        s2 = kfq * (vis - knc * noise) / den;
        double hm[9], ah[9];
        rp_mm(h, minv, hm); /* M^-1 G M^-1 */
        rp_mm(abar, hm, ah);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                model[3 * i + j] = s2 * (ah[3 * i] * abar[3 * j] + ah[3 * i + 1] * abar[3 * j + 1]
                                         + ah[3 * i + 2] * abar[3 * j + 2]);
            }
        }
        *excess = vis - noise;
    }
    return 0;
}
