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
    double h[36], rhs[6], kp[9], kc[9], pm[9], cm[9], xp[3], xc[3], mid[36], hi[36];
    size_t fi;
    int i, j, k;
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
        for (i = 0; i < 6; i++) {
            for (j = 0; j < 6; j++) {
                double s = 0.0;
                int p, q;
                for (p = 0; p < 3; p++) {
                    for (q = 0; q < 3; q++) {
                        s += jm[3 * i + p] * e[3 * p + q] * jm[3 * j + q];
                    }
                }
                mid[6 * i + j] += s;
            }
        }
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
    /* H^-1 column by column */
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
