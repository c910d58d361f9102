/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_multi.c
 * @brief Planar multi-marker oracle (see sfit_ref_multi.h). Double with
 * long double sums; uses only ref_moments and ref_sym3_eig of sfit_ref.h.
 */
#include "sfit_ref_multi.h"

#include <math.h>
#include <string.h>

#include "sfit_ref.h"

/* Marker p as an array of points. C99 has no qualified array types, so a
 * cast from `const double *` to `const double (*)[3]` trips -Wcast-qual;
 * copying the pointer representation is the portable way round. */
static const double (*ref_m_pts(const double *const *xs, size_t p))[3]
{
    const double (*x)[3];
    const double *src = xs[p];
    memcpy(&x, &src, sizeof x);
    return x;
}

/* x = A^-1 b, or over A's two largest eigen-directions (planar); a = the
 * smallest eigen-direction, unit, largest component positive. 0, or -1
 * when a used eigenvalue is not positive. */
static int ref_solve_axis(double A[3][3], const long double b[3], int planar,
                          long double x[3], double a[3])
{
    double ev[3], V[3][3], nrm;
    int i, k, big = 0;
    ref_sym3_eig(REF_C3(A), ev, V); /* ascending */
    for (i = 0; i < 3; ++i) {
        x[i] = 0.0L;
    }
    for (k = planar ? 1 : 0; k < 3; ++k) {
        long double vb = 0.0L;
        if (!(ev[k] > 0.0)) {
            return -1;
        }
        for (i = 0; i < 3; ++i) {
            vb += (long double)V[i][k] * b[i];
        }
        for (i = 0; i < 3; ++i) {
            x[i] += (long double)V[i][k] * vb / (long double)ev[k];
        }
    }
    for (i = 1; i < 3; ++i) {
        if (fabs(V[i][0]) > fabs(V[big][0])) {
            big = i;
        }
    }
    nrm = sqrt(V[0][0] * V[0][0] + V[1][0] * V[1][0] + V[2][0] * V[2][0]);
    if (V[big][0] < 0.0) {
        nrm = -nrm;
    }
    for (i = 0; i < 3; ++i) {
        a[i] = V[i][0] / nrm;
    }
    return 0;
}

/* Per-marker radii about the centre o + x (r_p^2 = (n_p-1)/n_p tr C'_p +
 * |m_p - c|^2, C'_p = C_p - Sigma_p, Sigma_p at sig + stride p), or about
 * the axis a (planar: both parts projected normal to a). Checked for every
 * marker before any is written; 0, or -1 when some r_p^2 <= 0. */
static int ref_radii(const double *const *xs, const size_t *ns, size_t m, const double *sig,
                     size_t stride, const double o[3], const long double x[3], const double a[3],
                     int planar, double *radii)
{
    double mean[3], C[3][3], S[3];
    size_t p;
    int i, j, k;
    for (k = 0; k < 2; ++k) {
        for (p = 0; p < m; ++p) {
            const double *sg = &sig[stride * p];
            long double tr = 0.0L, e[3], ea = 0.0L, r2, np = (long double)ns[p];
            (void)ref_moments(ref_m_pts(xs, p), ns[p], mean, C, S);
            for (i = 0; i < 3; ++i) {
                long double ca = 0.0L;
                tr += (long double)C[i][i] - (long double)sg[4 * i];
                for (j = 0; j < 3; ++j) {
                    ca += ((long double)C[i][j] - (long double)sg[3 * i + j]) * (long double)a[j];
                }
                if (planar) {
                    tr -= (long double)a[i] * ca;
                }
                e[i] = ((long double)mean[i] - (long double)o[i]) - x[i];
                ea += e[i] * (long double)a[i];
            }
            r2 = (np - 1.0L) / np * tr;
            for (i = 0; i < 3; ++i) {
                long double q = planar ? e[i] - ea * (long double)a[i] : e[i];
                r2 += q * q;
            }
            if (!(r2 > 0.0L)) {
                return -1;
            }
            if (k == 1 && radii != NULL) {
                radii[p] = (double)sqrtl(r2);
            }
        }
    }
    return 0;
}

int ref_fit_multi_planar(const double *const *xs, const size_t *ns, size_t m,
                         const double *cov, int weighted, double center[3],
                         double axis[3], double *radii)
{
    double sig[3][3], mean[3], C[3][3], S[3], o[3] = {0.0, 0.0, 0.0};
    double A[3][3], a[3], c[3], bar[3];
    long double Al[3][3], b[3], mb[3], sw = 0.0L, x[3];
    size_t p;
    int i, j;

    if (xs == NULL || ns == NULL || center == NULL || axis == NULL || m == 0) {
        return -1;
    }
    memset(sig, 0, sizeof sig);
    if (cov != NULL) {
        sig[0][0] = cov[0];
        sig[1][1] = cov[1];
        sig[2][2] = cov[2];
        sig[0][1] = sig[1][0] = cov[3];
        sig[0][2] = sig[2][0] = cov[4];
        sig[1][2] = sig[2][1] = cov[5];
    }
    memset(Al, 0, sizeof Al);
    memset(b, 0, sizeof b);
    memset(mb, 0, sizeof mb);
    for (p = 0; p < m; ++p) {
        long double w;
        if (xs[p] == NULL || ns[p] < 3 ||
            ref_moments(ref_m_pts(xs, p), ns[p], mean, C, S)) {
            return -1;
        }
        if (p == 0) {
            memcpy(o, mean, sizeof o);
        }
        w = weighted ? (long double)ns[p] - 1.0L : 1.0L;
        sw += w;
        for (i = 0; i < 3; ++i) {
            long double t = 0.5L * (long double)S[i];
            for (j = 0; j < 3; ++j) {
                long double cij = (long double)C[i][j] - (long double)sig[i][j];
                Al[i][j] += w * cij;
                t += cij * ((long double)mean[j] - (long double)o[j]);
            }
            b[i] += w * t;
            mb[i] += w * ((long double)mean[i] - (long double)o[i]);
        }
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            A[i][j] = (double)Al[i][j];
        }
    }
    /* x = sum_{k=1,2} v_k v_k^T b / lambda_k; then the axial position. */
    if (ref_solve_axis(A, b, 1, x, a) != 0) {
        return -1;
    }
    {
        long double ax = 0.0L, mx = 0.0L;
        for (i = 0; i < 3; ++i) {
            bar[i] = (double)(mb[i] / sw);
            ax += (long double)a[i] * x[i];
            mx += (long double)a[i] * (long double)bar[i];
        }
        for (i = 0; i < 3; ++i) {
            x[i] += (mx - ax) * (long double)a[i];
            c[i] = (double)((long double)o[i] + x[i]);
        }
    }
    if (ref_radii(xs, ns, m, &sig[0][0], 0, o, x, a, 1, radii) != 0) {
        return -1;
    }
    memcpy(center, c, sizeof c);
    memcpy(axis, a, sizeof a);
    return 0;
}

int ref_fit_multi_noise(const double *const *xs, const size_t *ns, size_t m,
                        const double *cov9, const double *skew, int planar,
                        double center[3], double axis[3], double *radii)
{
    double mean[3], C[3][3], S[3], o[3] = {0.0, 0.0, 0.0}, A[3][3];
    double a[3] = {0.0, 0.0, 0.0}, c[3];
    long double Al[3][3], b[3], mb[3], x[3];
    size_t p;
    int i, j;

    if (xs == NULL || ns == NULL || cov9 == NULL || skew == NULL || center == NULL || m == 0) {
        return -1;
    }
    memset(Al, 0, sizeof Al);
    memset(b, 0, sizeof b);
    memset(mb, 0, sizeof mb);
    for (p = 0; p < m; ++p) {
        const double *sg = &cov9[9 * p];
        if (xs[p] == NULL || ns[p] < 3 || ref_moments(ref_m_pts(xs, p), ns[p], mean, C, S)) {
            return -1;
        }
        if (p == 0) {
            memcpy(o, mean, sizeof o);
        }
        for (i = 0; i < 3; ++i) {
            long double t = 0.5L * ((long double)S[i] - (long double)skew[3 * p + (size_t)i]);
            for (j = 0; j < 3; ++j) {
                long double cij = (long double)C[i][j] - (long double)sg[3 * i + j];
                Al[i][j] += cij;
                t += cij * ((long double)mean[j] - (long double)o[j]);
            }
            b[i] += t;
            mb[i] += (long double)mean[i] - (long double)o[i];
        }
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            A[i][j] = (double)Al[i][j];
        }
    }
    if (ref_solve_axis(A, b, planar, x, a) != 0) {
        return -1;
    }
    if (planar) {
        long double ax = 0.0L, mx = 0.0L;
        for (i = 0; i < 3; ++i) {
            ax += (long double)a[i] * x[i];
            mx += (long double)a[i] * (mb[i] / (long double)m);
        }
        for (i = 0; i < 3; ++i) {
            x[i] += (mx - ax) * (long double)a[i];
        }
    }
    for (i = 0; i < 3; ++i) {
        c[i] = (double)((long double)o[i] + x[i]);
    }
    if (ref_radii(xs, ns, m, cov9, 9, o, x, a, planar, radii) != 0) {
        return -1;
    }
    memcpy(center, c, sizeof c);
    if (axis != NULL) {
        memcpy(axis, a, sizeof a);
    }
    return 0;
}

int ref_multi_center_cov(const double *const *xs, const size_t *ns, size_t m,
                         const double *cov, int weighted, const double c[3],
                         const double *axis, double var, int order2, double out[9])
{
    double A[3][3], Ai[3][3], M[3][3], T[3][3], sg[3][3], ev[3], V[3][3];
    long double sum_n1 = 0.0L;
    size_t p, i;
    int r, q, l;
    if (xs == NULL || ns == NULL || c == NULL || out == NULL || m == 0 || !(var >= 0.0)) {
        return -1;
    }
    memset(sg, 0, sizeof sg);
    if (cov != NULL) {
        static const int ix[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
        for (l = 0; l < 6; l++) {
            sg[ix[l][0]][ix[l][1]] = sg[ix[l][1]][ix[l][0]] = cov[l];
        }
    }
    for (p = 0; p < m; p++) {
        if (ns[p] < 2) {
            return -1;
        }
        sum_n1 += (long double)(ns[p] - 1);
    }
    memset(A, 0, sizeof A);
    memset(M, 0, sizeof M);
    for (p = 0; p < m; p++) {
        const double (*x)[3] = ref_m_pts(xs, p);
        const long double n = (long double)ns[p], n1 = n - 1.0L;
        const long double w = weighted ? n1 * (long double)m / sum_n1 : 1.0L;
        long double mean[3] = {0.0L, 0.0L, 0.0L}, cp[3][3], a[3], r2 = 0.0L, f, g;
        for (i = 0; i < ns[p]; i++) {
            for (r = 0; r < 3; r++) {
                mean[r] += (long double)x[i][r];
            }
        }
        for (r = 0; r < 3; r++) {
            mean[r] /= n;
            a[r] = mean[r] - (long double)c[r];
        }
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++) {
                long double s = 0.0L;
                for (i = 0; i < ns[p]; i++) {
                    s += ((long double)x[i][r] - mean[r]) * ((long double)x[i][q] - mean[q]);
                }
                cp[r][q] = s / n1 - (long double)sg[r][q];
            }
        }
        for (r = 0; r < 3; r++) {
            r2 += n1 / n * cp[r][r] + a[r] * a[r];
        }
        f = w * w / n1 * (r2 + (order2 ? 7.5L * (long double)var : 0.0L));
        g = order2 ? w * w * n / (n1 * n1) * (long double)var : 0.0L;
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++) {
                A[r][q] += (double)(w * cp[r][q]);
                M[r][q] += (double)(f * cp[r][q] + g * (a[r] * a[q] + (r == q ? r2 : 0.0L)));
            }
        }
    }
    if (axis != NULL) { /* A + (tr A) a a^T on the plane's complement: P A P + a a^T */
        double aa[3], qa = 0.0;
        for (r = 0; r < 3; r++) {
            aa[r] = A[r][0] * axis[0] + A[r][1] * axis[1] + A[r][2] * axis[2];
            qa += axis[r] * aa[r];
        }
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++) {
                A[r][q] += -axis[r] * aa[q] - aa[r] * axis[q] + (qa + 1.0) * axis[r] * axis[q];
            }
        }
    }
    ref_sym3_eig(REF_C3(A), ev, V);
    if (!(ev[0] > 0.0)) {
        return -1;
    }
    for (r = 0; r < 3; r++) {
        for (q = 0; q < 3; q++) {
            long double s = 0.0L;
            for (l = 0; l < 3; l++) {
                s += (long double)V[r][l] * (long double)V[q][l] / (long double)ev[l];
            }
            Ai[r][q] = (double)s - ((axis != NULL) ? axis[r] * axis[q] : 0.0);
        }
    }
    for (r = 0; r < 3; r++) {
        for (q = 0; q < 3; q++) {
            long double s = 0.0L;
            for (l = 0; l < 3; l++) {
                s += (long double)Ai[r][l] * (long double)M[l][q];
            }
            T[r][q] = (double)s;
        }
    }
    for (r = 0; r < 3; r++) {
        for (q = 0; q < 3; q++) {
            long double s = 0.0L;
            for (l = 0; l < 3; l++) {
                s += (long double)T[r][l] * (long double)Ai[l][q];
            }
            out[3 * r + q] = var * (double)s;
        }
    }
    return 0;
}
