/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_imu.c
 * @brief Double-precision oracle for sfit_imu.h: exact signals of two
 * segments joined at a point, Seel's batch Gauss-Newton (ball and hinge).
 * Independent of lib/ (no shared code, no float).
 */
#include "sfit_ref_imu.h"

#include <math.h>
#include <string.h>

#define RI_PI 3.14159265358979323846
#define RI_G 9.81

static void ri_cross(const double a[3], const double b[3], double c[3])
{
    double t[3];
    t[0] = a[1] * b[2] - a[2] * b[1];
    t[1] = a[2] * b[0] - a[0] * b[2];
    t[2] = a[0] * b[1] - a[1] * b[0];
    memcpy(c, t, sizeof t);
}

static double ri_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void ri_matvec(const double m[9], const double v[3], double o[3])
{
    double t[3];
    int i;
    for (i = 0; i < 3; i++) {
        t[i] = m[3 * i] * v[0] + m[3 * i + 1] * v[1] + m[3 * i + 2] * v[2];
    }
    memcpy(o, t, sizeof t);
}

static void ri_mattvec(const double m[9], const double v[3], double o[3])
{
    double t[3];
    int i;
    for (i = 0; i < 3; i++) {
        t[i] = m[i] * v[0] + m[3 + i] * v[1] + m[6 + i] * v[2];
    }
    memcpy(o, t, sizeof t);
}

static void ri_matmul(const double a[9], const double b[9], double c[9])
{
    double t[9];
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            t[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
        }
    }
    memcpy(c, t, sizeof t);
}

/* Rotation by angle th about the unit axis u (Rodrigues). */
static void ri_rot(const double u[3], double th, double r[9])
{
    const double c = cos(th), s = sin(th), k = 1.0 - c;
    r[0] = c + k * u[0] * u[0];
    r[1] = k * u[0] * u[1] - s * u[2];
    r[2] = k * u[0] * u[2] + s * u[1];
    r[3] = k * u[1] * u[0] + s * u[2];
    r[4] = c + k * u[1] * u[1];
    r[5] = k * u[1] * u[2] - s * u[0];
    r[6] = k * u[2] * u[0] - s * u[1];
    r[7] = k * u[2] * u[1] + s * u[0];
    r[8] = c + k * u[2] * u[2];
}

/* value, first and second derivative of off + sum amp sin(2 pi f t + ph) */
static void ri_wave(double off, const double amp[2], const double f[2], const double ph[2],
                    double t, double v[3])
{
    int k;
    v[0] = off;
    v[1] = 0.0;
    v[2] = 0.0;
    for (k = 0; k < 2; k++) {
        const double om = 2.0 * RI_PI * f[k], a = om * t + ph[k];
        v[0] += amp[k] * sin(a);
        v[1] += amp[k] * om * cos(a);
        v[2] -= amp[k] * om * om * sin(a);
    }
}

/* One sensor: orientation R, world angular velocity W and its derivative WD. */
static void ri_chain(const ref_imu_motion_t *m, int nfac, const double c[9], double t, double r[9],
                     double w[3], double wd[3])
{
    double q[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, rot[9], v[3], x[3], th[3];
    int i, k;
    memset(w, 0, 3 * sizeof(double));
    memset(wd, 0, 3 * sizeof(double));
    for (i = 0; i < nfac; i++) {
        ri_wave(m->off[i], m->amp[i], m->freq[i], m->ph[i], t, th);
        ri_matvec(q, m->axis[i], v);
        ri_cross(w, v, x);
        for (k = 0; k < 3; k++) {
            wd[k] += x[k] * th[1] + v[k] * th[2];
            w[k] += v[k] * th[1];
        }
        ri_rot(m->axis[i], th[0], rot);
        ri_matmul(q, rot, q);
    }
    ri_matmul(q, c, r);
}

void ref_imu_synth(const ref_imu_motion_t *m, double t, double acc[2][3], double gyr[2][3],
                   double dgyr[2][3])
{
    double pdd[3], r[9], w[3], wd[3], rr[3], x[3], y[3], sdd[3], p[3];
    int s, k;
    for (k = 0; k < 3; k++) {
        ri_wave(m->pos0[k] + m->vel[k] * t, m->pamp[k], m->pfreq[k], m->pph[k], t, p);
        pdd[k] = p[2];
    }
    for (s = 0; s < 2; s++) {
        const int nfac = (s == 0) ? m->nf1 : m->nf1 + m->nf2;
        ri_chain(m, nfac, s == 0 ? m->c1 : m->c2, t, r, w, wd);
        ri_matvec(r, s == 0 ? m->r1 : m->r2, rr); /* sensor -> joint, world */
        ri_cross(w, rr, x);
        ri_cross(w, x, y);
        ri_cross(wd, rr, x);
        for (k = 0; k < 3; k++) {
            sdd[k] = pdd[k] - x[k] - y[k]; /* the sensor is at P - R r */
        }
        sdd[2] += RI_G;
        ri_mattvec(r, sdd, acc[s]);
        ri_mattvec(r, w, gyr[s]);
        ri_mattvec(r, wd, dgyr[s]);
    }
}

/* G(w, w') r */
static void ri_g(const double w[3], const double dw[3], const double r[3], double o[3])
{
    double x[3], y[3], z[3];
    int k;
    ri_cross(w, r, x);
    ri_cross(w, x, y);
    ri_cross(dw, r, z);
    for (k = 0; k < 3; k++) {
        o[k] = y[k] + z[k];
    }
}

double ref_imu_gap(const double a1[3], const double w1[3], const double dw1[3],
                   const double r1[3], const double a2[3], const double w2[3],
                   const double dw2[3], const double r2[3])
{
    double g1[3], g2[3];
    int k;
    ri_g(w1, dw1, r1, g1);
    ri_g(w2, dw2, r2, g2);
    for (k = 0; k < 3; k++) {
        g1[k] += a1[k];
        g2[k] += a2[k];
    }
    return sqrt(ri_dot(g1, g1)) - sqrt(ri_dot(g2, g2));
}

/* Solve the n x n system a x = b (a destroyed) by Gaussian elimination with
 * partial pivoting; optionally the inverse of the original a into inv. */
static int ri_solve(int n, double *a, double *b, double *inv)
{
    double m[12 * 24];
    int i, j, k, c = n + 1 + (inv ? n : 0);
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            m[i * c + j] = a[i * n + j];
        }
        m[i * c + n] = b[i];
        if (inv) {
            for (j = 0; j < n; j++) {
                m[i * c + n + 1 + j] = (i == j) ? 1.0 : 0.0;
            }
        }
    }
    for (k = 0; k < n; k++) {
        int p = k;
        double piv;
        for (i = k + 1; i < n; i++) {
            if (fabs(m[i * c + k]) > fabs(m[p * c + k])) {
                p = i;
            }
        }
        if (!(fabs(m[p * c + k]) > 1e-300)) {
            return 1;
        }
        for (j = 0; j < c; j++) {
            double t = m[k * c + j];
            m[k * c + j] = m[p * c + j];
            m[p * c + j] = t;
        }
        piv = m[k * c + k];
        for (j = 0; j < c; j++) {
            m[k * c + j] /= piv;
        }
        for (i = 0; i < n; i++) {
            if (i != k) {
                const double f = m[i * c + k];
                for (j = 0; j < c; j++) {
                    m[i * c + j] -= f * m[k * c + j];
                }
            }
        }
    }
    for (i = 0; i < n; i++) {
        b[i] = m[i * c + n];
        if (inv) {
            for (j = 0; j < n; j++) {
                inv[i * n + j] = m[i * c + n + 1 + j];
            }
        }
    }
    return 0;
}

/* Derivative weights over k = -m..m: the slope at 0 of the least-squares
 * polynomial of the given degree (Vandermonde normal equations in double). */
static int ri_deriv_weights(int m, int degree, double *wk)
{
    double vtv[16], inv[16], rhs[4] = {0, 0, 0, 0};
    int k, a, b, d = degree + 1;
    for (a = 0; a < d; a++) {
        for (b = 0; b < d; b++) {
            double t = 0.0;
            for (k = -m; k <= m; k++) {
                t += pow((double)k, a) * pow((double)k, b);
            }
            vtv[a * d + b] = t;
        }
    }
    if (ri_solve(d, vtv, rhs, inv)) {
        return 1;
    }
    for (k = -m; k <= m; k++) {
        double t = 0.0;
        for (a = 0; a < d; a++) {
            t += inv[1 * d + a] * pow((double)k, a); /* row of the linear coefficient */
        }
        wk[k + m] = t;
    }
    return 0;
}

int ref_imu_ball_gn(const double (*acc1)[3], const double (*gyr1)[3], const double (*acc2)[3],
                    const double (*gyr2)[3], size_t n, double rate, int h, double r1[3],
                    double r2[3], double cov[36], double *rms)
{
    double x[6] = {0, 0, 0, 0, 0, 0}, ssr = 0.0, wk[2 * 32 + 1];
    size_t k, m = 0;
    int it, i, j;
    const int hw = (h < 0) ? -h : h;
    if (h == 0 || hw > 32 || n < (size_t)(2 * hw + 7)) {
        return 1;
    }
    if (h > 0) {
        memset(wk, 0, sizeof wk);
        wk[0] = -0.5 / (double)h;
        wk[2 * h] = 0.5 / (double)h;
    } else if (ri_deriv_weights(hw, 3, wk)) {
        return 1;
    }
    for (it = 0; it < 100; it++) {
        double a[36], b[6], inv[36], step = 0.0;
        memset(a, 0, sizeof a);
        memset(b, 0, sizeof b);
        ssr = 0.0;
        m = 0;
        const size_t hh = (size_t)hw;
        for (k = hh; k + hh < n; k++) {
            double dw1[3], dw2[3], v1[3], v2[3], n1, n2, u1[3], u2[3], jr[6], e, gu[3];
            int s, q;
            for (s = 0; s < 3; s++) {
                dw1[s] = 0.0;
                dw2[s] = 0.0;
                for (q = 0; q <= 2 * hw; q++) {
                    dw1[s] += wk[q] * gyr1[k - hh + (size_t)q][s] * rate;
                    dw2[s] += wk[q] * gyr2[k - hh + (size_t)q][s] * rate;
                }
            }
            ri_g(gyr1[k], dw1, x, v1);
            ri_g(gyr2[k], dw2, x + 3, v2);
            for (s = 0; s < 3; s++) {
                v1[s] += acc1[k][s];
                v2[s] += acc2[k][s];
            }
            n1 = sqrt(ri_dot(v1, v1));
            n2 = sqrt(ri_dot(v2, v2));
            if (!(n1 > 0.0) || !(n2 > 0.0)) {
                continue;
            }
            for (s = 0; s < 3; s++) {
                u1[s] = v1[s] / n1;
                u2[s] = v2[s] / n2;
            }
            e = n1 - n2;
            /* d|a + G r|/dr = G^T u; G^T u = (w x u) x w ... computed column by column */
            for (s = 0; s < 3; s++) {
                double ev[3] = {0, 0, 0}, g[3];
                ev[s] = 1.0;
                ri_g(gyr1[k], dw1, ev, g);
                gu[s] = ri_dot(g, u1);
            }
            for (s = 0; s < 3; s++) {
                jr[s] = gu[s];
            }
            for (s = 0; s < 3; s++) {
                double ev[3] = {0, 0, 0}, g[3];
                ev[s] = 1.0;
                ri_g(gyr2[k], dw2, ev, g);
                jr[3 + s] = -ri_dot(g, u2);
            }
            for (i = 0; i < 6; i++) {
                b[i] -= jr[i] * e;
                for (j = 0; j < 6; j++) {
                    a[6 * i + j] += jr[i] * jr[j];
                }
            }
            ssr += e * e;
            m++;
        }
        if (m < 7 || ri_solve(6, a, b, inv)) {
            return 1;
        }
        for (i = 0; i < 6; i++) {
            x[i] += b[i];
            step += b[i] * b[i];
        }
        if (cov) {
            /* the covariance at this iterate (the last one is kept) */
            for (i = 0; i < 36; i++) {
                cov[i] = inv[i] * ssr / (double)(m - 6);
            }
        }
        if (sqrt(step) < 1e-10) {
            break;
        }
    }
    if (it == 100) {
        return 2;
    }
    memcpy(r1, x, 3 * sizeof(double));
    memcpy(r2, x + 3, 3 * sizeof(double));
    if (rms) {
        *rms = sqrt(ssr / (double)m);
    }
    return 0;
}

static void ri_sph(double th, double ph, double j[3], double jt[3], double jp[3])
{
    j[0] = cos(ph) * cos(th);
    j[1] = cos(ph) * sin(th);
    j[2] = sin(ph);
    jt[0] = -cos(ph) * sin(th);
    jt[1] = cos(ph) * cos(th);
    jt[2] = 0.0;
    jp[0] = -sin(ph) * cos(th);
    jp[1] = -sin(ph) * sin(th);
    jp[2] = cos(ph);
}

/* |w x j| and its gradient in j (j unit) */
static double ri_wxj(const double w[3], const double j[3], double gr[3])
{
    double c[3], nn, wj = ri_dot(w, j), ww = ri_dot(w, w);
    int s;
    ri_cross(w, j, c);
    nn = sqrt(ri_dot(c, c));
    for (s = 0; s < 3; s++) {
        gr[s] = (nn > 1e-12) ? (ww * j[s] - wj * w[s]) / nn : 0.0;
    }
    return nn;
}

static double ri_hinge_run(const double (*gyr1)[3], const double (*gyr2)[3], size_t n,
                           double p[4])
{
    double ssr = 0.0;
    int it;
    for (it = 0; it < 200; it++) {
        double a[16], b[4], step = 0.0, j1[3], j1t[3], j1p[3], j2[3], j2t[3], j2p[3];
        size_t k;
        int i, l;
        memset(a, 0, sizeof a);
        memset(b, 0, sizeof b);
        ssr = 0.0;
        ri_sph(p[0], p[1], j1, j1t, j1p);
        ri_sph(p[2], p[3], j2, j2t, j2p);
        for (k = 0; k < n; k++) {
            double g1[3], g2[3], jr[4], e;
            e = ri_wxj(gyr1[k], j1, g1) - ri_wxj(gyr2[k], j2, g2);
            jr[0] = ri_dot(g1, j1t);
            jr[1] = ri_dot(g1, j1p);
            jr[2] = -ri_dot(g2, j2t);
            jr[3] = -ri_dot(g2, j2p);
            for (i = 0; i < 4; i++) {
                b[i] -= jr[i] * e;
                for (l = 0; l < 4; l++) {
                    a[4 * i + l] += jr[i] * jr[l];
                }
            }
            ssr += e * e;
        }
        for (i = 0; i < 4; i++) {
            a[5 * i] *= 1.0 + 1e-9; /* a touch of Levenberg at the poles */
        }
        if (ri_solve(4, a, b, NULL)) {
            return -1.0;
        }
        for (i = 0; i < 4; i++) {
            p[i] += b[i];
            step += b[i] * b[i];
        }
        if (sqrt(step) < 1e-12) {
            break;
        }
    }
    return ssr;
}

int ref_imu_hinge_gn(const double (*gyr1)[3], const double (*gyr2)[3], size_t n, double j1[3],
                     double j2[3], double *rms)
{
    static const double starts[5][2] = {{0.3, 0.2}, {1.8, 0.3}, {0.9, 1.2}, {-1.2, -0.4},
                                        {2.6, -1.0}};
    double best = -1.0, bp[4] = {0, 0, 0, 0}, t1[3], t2[3], cs = 0.0;
    int a, b;
    size_t k;
    if (n < 8) {
        return 1;
    }
    for (a = 0; a < 5; a++) {
        for (b = 0; b < 5; b++) {
            double p[4] = {starts[a][0], starts[a][1], starts[b][0], starts[b][1]};
            const double s = ri_hinge_run(gyr1, gyr2, n, p);
            if (s >= 0.0 && (best < 0.0 || s < best)) {
                best = s;
                memcpy(bp, p, sizeof p);
            }
        }
    }
    if (best < 0.0) {
        return 1;
    }
    ri_sph(bp[0], bp[1], j1, t1, t2);
    ri_sph(bp[2], bp[3], j2, t1, t2);
    for (k = 0; k < n; k++) {
        cs += ri_dot(gyr1[k], j1) * ri_dot(gyr2[k], j2);
    }
    if (cs < 0.0) {
        for (a = 0; a < 3; a++) {
            j2[a] = -j2[a];
        }
    }
    if (rms) {
        *rms = sqrt(best / (double)n);
    }
    return 0;
}

void ref_imu_relative(const ref_imu_motion_t *m, double t, double rel[9], double w[3])
{
    double q[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, rot[9], v[3], th[3], x[9];
    int i, k;
    memset(w, 0, 3 * sizeof(double));
    for (i = m->nf1; i < m->nf1 + m->nf2; i++) {
        ri_wave(m->off[i], m->amp[i], m->freq[i], m->ph[i], t, th);
        ri_matvec(q, m->axis[i], v);
        for (k = 0; k < 3; k++) {
            w[k] += v[k] * th[1];
        }
        ri_rot(m->axis[i], th[0], rot);
        ri_matmul(q, rot, q);
    }
    /* sensor 2 -> sensor 1: c1^T q c2 ; the rate in sensor 1's frame: c1^T w */
    ri_matmul(q, m->c2, x);
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 3; k++) {
            rel[3 * i + k] = m->c1[i] * x[k] + m->c1[3 + i] * x[3 + k] + m->c1[6 + i] * x[6 + k];
        }
    }
    ri_mattvec(m->c1, w, v);
    memcpy(w, v, sizeof v);
}

/* Top eigenvector of the symmetric 3x3 s (power iteration from the largest column). */
static void ri_top_eig(const double s[9], double v[3])
{
    double n;
    int it, i, c = 0;
    for (i = 1; i < 3; i++) {
        c = (s[4 * i] > s[4 * c]) ? i : c;
    }
    for (i = 0; i < 3; i++) {
        v[i] = s[3 * i + c];
    }
    for (it = 0; it < 2000; it++) {
        double x[3];
        ri_matvec(s, v, x);
        n = sqrt(ri_dot(x, x));
        if (!(n > 0.0)) {
            break;
        }
        for (i = 0; i < 3; i++) {
            v[i] = x[i] / n;
        }
    }
}

void ref_imu_fixed_axis(const ref_imu_motion_t *m, size_t n, double rate, double j1[3],
                        double j2[3], double *wander, double f1[3], double f2[3])
{
    double mean[9], s[9], x[9], nn;
    double q[9] = {0}, q2[9] = {0};
    size_t k;
    int i, l;
    memset(mean, 0, sizeof mean);
    for (k = 0; k < n; k++) {
        double rel[9], w[3], w2[3];
        ref_imu_relative(m, (double)k / rate, rel, w);
        ri_mattvec(rel, w, w2);
        for (i = 0; i < 9; i++) {
            mean[i] += rel[i] / (double)n;
        }
        for (i = 0; i < 3; i++) {
            for (l = 0; l < 3; l++) {
                q[3 * i + l] += w[i] * w[l];
                q2[3 * i + l] += w2[i] * w2[l];
            }
        }
    }
    /* j2: top eigenvector of mean^T mean; j1 = mean j2 normalised */
    for (i = 0; i < 3; i++) {
        for (l = 0; l < 3; l++) {
            s[3 * i + l] = mean[i] * mean[l] + mean[3 + i] * mean[3 + l] + mean[6 + i] * mean[6 + l];
        }
    }
    ri_top_eig(s, j2);
    ri_matvec(mean, j2, j1);
    nn = sqrt(ri_dot(j1, j1));
    for (i = 0; i < 3; i++) {
        j1[i] /= nn;
    }
    if (wander) {
        double worst = 0.0;
        for (k = 0; k < n; k++) {
            double rel[9], w[3], v[3];
            ref_imu_relative(m, (double)k / rate, rel, w);
            ri_matvec(rel, j2, v);
            ri_cross(v, j1, w);
            worst = fmax(worst, asin(fmin(1.0, sqrt(ri_dot(w, w)))));
        }
        *wander = worst;
    }
    ri_top_eig(q, f1);
    ri_top_eig(q2, f2);
    (void)x;
}
