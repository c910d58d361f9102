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

int ref_fit_multi_planar(const double *const *xs, const size_t *ns, size_t m,
                         const double *cov, int weighted, double center[3],
                         double axis[3], double *radii)
{
    double sig[3][3], mean[3], C[3][3], S[3], o[3] = {0.0, 0.0, 0.0};
    double A[3][3], ev[3], V[3][3], a[3], c[3], bar[3];
    long double Al[3][3], b[3], mb[3], sw = 0.0L, x[3];
    size_t p;
    int i, j, k, big;

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
    ref_sym3_eig(REF_C3(A), ev, V);
    if (!(ev[1] > 0.0) || !(ev[2] > 0.0)) {
        return -1;
    }
    /* x = sum_{k=1,2} v_k v_k^T b / lambda_k; then the axial position. */
    for (i = 0; i < 3; ++i) {
        x[i] = 0.0L;
    }
    for (k = 1; k < 3; ++k) {
        long double vb = 0.0L;
        for (i = 0; i < 3; ++i) {
            vb += (long double)V[i][k] * b[i];
        }
        for (i = 0; i < 3; ++i) {
            x[i] += (long double)V[i][k] * vb / (long double)ev[k];
        }
    }
    big = 0;
    for (i = 1; i < 3; ++i) {
        if (fabs(V[i][0]) > fabs(V[big][0])) {
            big = i;
        }
    }
    {
        double nrm = sqrt(V[0][0] * V[0][0] + V[1][0] * V[1][0] + V[2][0] * V[2][0]);
        if (V[big][0] < 0.0) {
            nrm = -nrm;
        }
        for (i = 0; i < 3; ++i) {
            a[i] = V[i][0] / nrm;
        }
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
    /* radii: checked in pass 0, written in pass 1 */
    for (k = 0; k < 2; ++k) {
        for (p = 0; p < m; ++p) {
            long double tr = 0.0L, e[3], ea = 0.0L, r2, np = (long double)ns[p];
            (void)ref_moments(ref_m_pts(xs, p), ns[p], mean, C, S);
            for (i = 0; i < 3; ++i) {
                long double ca = 0.0L;
                tr += (long double)C[i][i] - (long double)sig[i][i];
                for (j = 0; j < 3; ++j) {
                    ca += ((long double)C[i][j] - (long double)sig[i][j]) * (long double)a[j];
                }
                tr -= (long double)a[i] * ca;
                e[i] = ((long double)mean[i] - (long double)o[i]) - x[i];
                ea += e[i] * (long double)a[i];
            }
            r2 = (np - 1.0L) / np * tr;
            for (i = 0; i < 3; ++i) {
                long double q = e[i] - ea * (long double)a[i];
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
    memcpy(center, c, sizeof c);
    memcpy(axis, a, sizeof a);
    return 0;
}

int ref_fit_multi_noise(const double *const *xs, const size_t *ns, size_t m,
                        const double *cov9, const double *skew, int planar,
                        double center[3], double axis[3], double *radii)
{
    double mean[3], C[3][3], S[3], o[3] = {0.0, 0.0, 0.0}, A[3][3], ev[3], V[3][3];
    double a[3] = {0.0, 0.0, 0.0}, c[3];
    long double Al[3][3], b[3], mb[3], x[3];
    size_t p;
    int i, j, k, big, kmin;

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
    ref_sym3_eig(REF_C3(A), ev, V);
    /* ascending order is not promised: find the smallest */
    kmin = 0;
    for (k = 1; k < 3; ++k) {
        if (ev[k] < ev[kmin]) {
            kmin = k;
        }
    }
    for (i = 0; i < 3; ++i) {
        x[i] = 0.0L;
    }
    for (k = 0; k < 3; ++k) {
        long double vb = 0.0L;
        if (planar && k == kmin) {
            continue;
        }
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
    big = 0;
    for (i = 1; i < 3; ++i) {
        if (fabs(V[i][kmin]) > fabs(V[big][kmin])) {
            big = i;
        }
    }
    {
        double nrm = sqrt(V[0][kmin] * V[0][kmin] + V[1][kmin] * V[1][kmin]
                          + V[2][kmin] * V[2][kmin]);
        if (V[big][kmin] < 0.0) {
            nrm = -nrm;
        }
        for (i = 0; i < 3; ++i) {
            a[i] = V[i][kmin] / nrm;
        }
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
    for (k = 0; k < 2; ++k) {
        for (p = 0; p < m; ++p) {
            const double *sg = &cov9[9 * p];
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
    memcpy(center, c, sizeof c);
    if (axis != NULL) {
        memcpy(axis, a, sizeof a);
    }
    return 0;
}
