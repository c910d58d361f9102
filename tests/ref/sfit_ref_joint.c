/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_joint.c
 * @brief Horn's quaternion registration in double (see sfit_ref_joint.h).
 */
#include "sfit_ref_joint.h"

#include <math.h>
#include <string.h>

void ref_jacobi_n(const double *a_in, int n, double *w, double *v)
{
    double a[16];
    int i, j, p, q, sweep;
    memcpy(a, a_in, sizeof(double) * (size_t)(n * n));
    for (i = 0; i < n; i++) {
        for (j = 0; j < n; j++) {
            v[i * n + j] = (i == j) ? 1.0 : 0.0;
        }
    }
    for (sweep = 0; sweep < 100; sweep++) {
        double off = 0.0, diag = 0.0;
        for (p = 0; p < n; p++) {
            diag += a[p * n + p] * a[p * n + p];
            for (q = p + 1; q < n; q++) {
                off += a[p * n + q] * a[p * n + q];
            }
        }
        if (off <= 1e-32 * diag || off == 0.0) {
            break;
        }
        for (p = 0; p < n - 1; p++) {
            for (q = p + 1; q < n; q++) {
                double apq = a[p * n + q], theta, t, c, s;
                int k;
                if (apq == 0.0) {
                    continue;
                }
                theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (k = 0; k < n; k++) { /* A := A J (columns p, q) */
                    double akp = a[k * n + p], akq = a[k * n + q];
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for (k = 0; k < n; k++) { /* A := J^T A (rows p, q) */
                    double apk = a[p * n + k], aqk = a[q * n + k];
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for (k = 0; k < n; k++) {
                    double vkp = v[k * n + p], vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    for (i = 0; i < n; i++) {
        w[i] = a[i * n + i];
    }
}

int ref_horn_pose(const double (*tpl)[3], const double (*x)[3], const int *seen, size_t n,
                  double r[9], double t[3], double *rms)
{
    double cp[3] = {0, 0, 0}, cx[3] = {0, 0, 0}, s[3][3], nm[16], w[4], v[16], qw, qx, qy, qz;
    double e2 = 0.0;
    size_t i, used = 0;
    int a, b, best;

    for (i = 0; i < n; i++) {
        if (seen != NULL && !seen[i]) {
            continue;
        }
        for (a = 0; a < 3; a++) {
            cp[a] += tpl[i][a];
            cx[a] += x[i][a];
        }
        used++;
    }
    if (used < 3) {
        return 1;
    }
    for (a = 0; a < 3; a++) {
        cp[a] /= (double)used;
        cx[a] /= (double)used;
    }
    memset(s, 0, sizeof s);
    for (i = 0; i < n; i++) {
        if (seen != NULL && !seen[i]) {
            continue;
        }
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                s[a][b] += (tpl[i][a] - cp[a]) * (x[i][b] - cx[b]); /* S_ab = sum p_a q_b */
            }
        }
    }
    /* Horn's symmetric 4x4 N. */
    nm[0] = s[0][0] + s[1][1] + s[2][2];
    nm[1] = s[1][2] - s[2][1];
    nm[2] = s[2][0] - s[0][2];
    nm[3] = s[0][1] - s[1][0];
    nm[5] = s[0][0] - s[1][1] - s[2][2];
    nm[6] = s[0][1] + s[1][0];
    nm[7] = s[2][0] + s[0][2];
    nm[10] = -s[0][0] + s[1][1] - s[2][2];
    nm[11] = s[1][2] + s[2][1];
    nm[15] = -s[0][0] - s[1][1] + s[2][2];
    nm[4] = nm[1]; nm[8] = nm[2]; nm[12] = nm[3];
    nm[9] = nm[6]; nm[13] = nm[7]; nm[14] = nm[11];
    ref_jacobi_n(nm, 4, w, v);
    best = 0;
    for (a = 1; a < 4; a++) {
        if (w[a] > w[best]) {
            best = a;
        }
    }
    qw = v[0 * 4 + best]; qx = v[1 * 4 + best]; qy = v[2 * 4 + best]; qz = v[3 * 4 + best];
    {
        double nq = sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
        qw /= nq; qx /= nq; qy /= nq; qz /= nq;
    }
    r[0] = qw * qw + qx * qx - qy * qy - qz * qz;
    r[1] = 2.0 * (qx * qy - qw * qz);
    r[2] = 2.0 * (qx * qz + qw * qy);
    r[3] = 2.0 * (qy * qx + qw * qz);
    r[4] = qw * qw - qx * qx + qy * qy - qz * qz;
    r[5] = 2.0 * (qy * qz - qw * qx);
    r[6] = 2.0 * (qz * qx - qw * qy);
    r[7] = 2.0 * (qz * qy + qw * qx);
    r[8] = qw * qw - qx * qx - qy * qy + qz * qz;
    for (a = 0; a < 3; a++) {
        t[a] = cx[a] - (r[3 * a] * cp[0] + r[3 * a + 1] * cp[1] + r[3 * a + 2] * cp[2]);
    }
    for (i = 0; i < n; i++) {
        double g[3];
        if (seen != NULL && !seen[i]) {
            continue;
        }
        ref_pose_to_global(r, t, tpl[i], g);
        for (a = 0; a < 3; a++) {
            e2 += (g[a] - x[i][a]) * (g[a] - x[i][a]);
        }
    }
    if (rms != NULL) {
        *rms = sqrt(e2 / (double)used);
    }
    return 0;
}

void ref_pose_to_segment(const double r[9], const double t[3], const double x[3], double out[3])
{
    double d[3];
    int a;
    for (a = 0; a < 3; a++) {
        d[a] = x[a] - t[a];
    }
    for (a = 0; a < 3; a++) {
        out[a] = r[a] * d[0] + r[3 + a] * d[1] + r[6 + a] * d[2];
    }
}

void ref_pose_to_global(const double r[9], const double t[3], const double x[3], double out[3])
{
    double y[3];
    int a;
    for (a = 0; a < 3; a++) {
        y[a] = r[3 * a] * x[0] + r[3 * a + 1] * x[1] + r[3 * a + 2] * x[2] + t[a];
    }
    memcpy(out, y, sizeof y);
}

/* Inverse of a symmetric 3x3 by cofactors; 0 when singular. */
static int ref_inv3(const double a[9], double inv[9])
{
    double det;
    int i;
    inv[0] = a[4] * a[8] - a[5] * a[7];
    inv[1] = a[2] * a[7] - a[1] * a[8];
    inv[2] = a[1] * a[5] - a[2] * a[4];
    inv[3] = a[5] * a[6] - a[3] * a[8];
    inv[4] = a[0] * a[8] - a[2] * a[6];
    inv[5] = a[2] * a[3] - a[0] * a[5];
    inv[6] = a[3] * a[7] - a[4] * a[6];
    inv[7] = a[1] * a[6] - a[0] * a[7];
    inv[8] = a[0] * a[4] - a[1] * a[3];
    det = a[0] * inv[0] + a[1] * inv[3] + a[2] * inv[6];
    if (!(fabs(det) > 0.0)) {
        return 0;
    }
    for (i = 0; i < 9; i++) {
        inv[i] /= det;
    }
    return 1;
}

/* [e]x K [e]x^T */
static void ref_cross_sandwich(const double e[3], const double k[9], double out[9])
{
    double x[9], xk[9];
    int a, b, c;
    x[0] = 0.0; x[1] = -e[2]; x[2] = e[1];
    x[3] = e[2]; x[4] = 0.0; x[5] = -e[0];
    x[6] = -e[1]; x[7] = e[0]; x[8] = 0.0;
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            xk[3 * a + b] = 0.0;
            for (c = 0; c < 3; c++) {
                xk[3 * a + b] += x[3 * a + c] * k[3 * c + b];
            }
        }
    }
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            out[3 * a + b] = 0.0;
            for (c = 0; c < 3; c++) {
                out[3 * a + b] += xk[3 * a + c] * x[3 * b + c];
            }
        }
    }
}

/* Template centroid pb and K = J^-1, J = sum (|p - pb|^2 I - (p - pb)(p - pb)^T);
 * 0 when J is singular. */
static int ref_pose_noise(const double (*tpl)[3], size_t np, double pb[3], double k[9])
{
    double jm[9];
    size_t i;
    int a, b;
    for (a = 0; a < 3; a++) {
        pb[a] = 0.0;
    }
    for (i = 0; i < np; i++) {
        for (a = 0; a < 3; a++) {
            pb[a] += tpl[i][a] / (double)np;
        }
    }
    memset(jm, 0, sizeof jm);
    for (i = 0; i < np; i++) {
        double p[3], p2 = 0.0;
        for (a = 0; a < 3; a++) {
            p[a] = tpl[i][a] - pb[a];
            p2 += p[a] * p[a];
        }
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                jm[3 * a + b] += (a == b ? p2 : 0.0) - p[a] * p[b];
            }
        }
    }
    return ref_inv3(jm, k);
}

int ref_joint_marker_noise(const double (*tpl)[3], size_t np, const double *xs, size_t n,
                           double var, double cov9[9], double skew[3])
{
    double pb[3], k[9], mean[3] = {0.0, 0.0, 0.0};
    long double cv[9], sk[3];
    size_t i;
    int a, b;
    if (tpl == NULL || xs == NULL || np < 3 || n < 2 || !ref_pose_noise(tpl, np, pb, k)) {
        return -1;
    }
    for (i = 0; i < n; i++) {
        for (a = 0; a < 3; a++) {
            mean[a] += xs[3 * i + (size_t)a] / (double)n;
        }
    }
    memset(cv, 0, sizeof cv);
    memset(sk, 0, sizeof sk);
    for (i = 0; i < n; i++) {
        double u[3], q[9], sg[9], tr;
        for (a = 0; a < 3; a++) {
            u[a] = xs[3 * i + (size_t)a] - pb[a];
        }
        ref_cross_sandwich(u, k, q); /* [u]x K [u]x^T */
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                sg[3 * a + b] = var * (((a == b) ? 1.0 + 1.0 / (double)np : 0.0) + q[3 * a + b]);
                cv[3 * a + b] += (long double)sg[3 * a + b] / (long double)n;
            }
        }
        tr = sg[0] + sg[4] + sg[8];
        for (a = 0; a < 3; a++) {
            long double t = 0.0L;
            for (b = 0; b < 3; b++) {
                const double m = 2.0 * sg[3 * a + b] + (a == b ? tr : 0.0);
                t += (long double)m * (long double)(xs[3 * i + (size_t)b] - mean[b]);
            }
            sk[a] += t / (long double)n;
        }
    }
    for (a = 0; a < 9; a++) {
        cov9[a] = (double)cv[a];
    }
    for (a = 0; a < 3; a++) {
        skew[a] = (double)sk[a];
    }
    return 0;
}

int ref_joint_center_cov(const double (*tpl)[3], size_t np, const double *const *xs, size_t m,
                         size_t n, const double *cov9, const double c[3], const double *axis,
                         double var, double cov[9])
{
    double pb[3], k[9], e[3], sg[9], a[9], ai[9], mm[9], t[9];
    double mean[8][3];
    const double v = 1.0 / ((double)n - 1.0);
    size_t p, f;
    int r, q, l;
    if (xs == NULL || c == NULL || cov == NULL || m == 0 || m > 8 || n < 2
        || (tpl != NULL && (np < 3 || !ref_pose_noise(tpl, np, pb, k)))) {
        return -1;
    }
    memset(sg, 0, sizeof sg); /* no parent: independent markers, E = 0 */
    if (tpl != NULL) {
        for (r = 0; r < 3; r++) {
            e[r] = c[r] - pb[r];
        }
        ref_cross_sandwich(e, k, sg);
        for (r = 0; r < 3; r++) {
            sg[4 * r] += 1.0 / (double)np;
        }
    }
    /* A = sum (C_p - Sigma_p) */
    memset(a, 0, sizeof a);
    for (p = 0; p < m; p++) {
        for (r = 0; r < 3; r++) {
            mean[p][r] = 0.0;
            for (f = 0; f < n; f++) {
                mean[p][r] += xs[p][3 * f + (size_t)r] / (double)n;
            }
        }
        for (f = 0; f < n; f++) {
            for (r = 0; r < 3; r++) {
                for (q = 0; q < 3; q++) {
                    a[3 * r + q] += v * (xs[p][3 * f + (size_t)r] - mean[p][r])
                                    * (xs[p][3 * f + (size_t)q] - mean[p][q]);
                }
            }
        }
        if (cov9 != NULL) {
            for (r = 0; r < 9; r++) {
                a[r] -= cov9[9 * p + (size_t)r];
            }
        }
    }
    if (axis != NULL) { /* pseudo-inverse normal to the axis */
        double aa[3], qa = 0.0;
        for (r = 0; r < 3; r++) {
            aa[r] = a[3 * r] * axis[0] + a[3 * r + 1] * axis[1] + a[3 * r + 2] * axis[2];
            qa += axis[r] * aa[r];
        }
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++) {
                a[3 * r + q] += -axis[r] * aa[q] - aa[r] * axis[q] + (qa + 1.0) * axis[r] * axis[q];
            }
        }
    }
    if (!ref_inv3(a, ai)) {
        return -1;
    }
    if (axis != NULL) {
        for (r = 0; r < 9; r++) {
            ai[r] -= axis[r / 3] * axis[r % 3];
        }
    }
    memset(mm, 0, sizeof mm);
    for (f = 0; f < n; f++) {
        double w[9], ws[9];
        memset(w, 0, sizeof w);
        for (p = 0; p < m; p++) {
            double b[3], d[3], d2 = 0.0;
            for (r = 0; r < 3; r++) {
                b[r] = xs[p][3 * f + (size_t)r] - mean[p][r];
                d[r] = xs[p][3 * f + (size_t)r] - c[r];
                d2 += d[r] * d[r];
            }
            for (r = 0; r < 9; r++) {
                w[r] += v * b[r / 3] * d[r % 3];
                mm[r] += v * v * d2 * b[r / 3] * b[r % 3];
            }
        }
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++) {
                ws[3 * r + q] = 0.0;
                for (l = 0; l < 3; l++) {
                    ws[3 * r + q] += w[3 * r + l] * sg[3 * l + q];
                }
            }
        }
        for (r = 0; r < 3; r++) {
            for (q = 0; q < 3; q++) {
                for (l = 0; l < 3; l++) {
                    mm[3 * r + q] += ws[3 * r + l] * w[3 * q + l];
                }
            }
        }
    }
    for (r = 0; r < 3; r++) {
        for (q = 0; q < 3; q++) {
            t[3 * r + q] = 0.0;
            for (l = 0; l < 3; l++) {
                t[3 * r + q] += ai[3 * r + l] * mm[3 * l + q];
            }
        }
    }
    for (r = 0; r < 3; r++) {
        for (q = 0; q < 3; q++) {
            cov[3 * r + q] = 0.0;
            for (l = 0; l < 3; l++) {
                cov[3 * r + q] += var * t[3 * r + l] * ai[3 * l + q];
            }
        }
    }
    return 0;
}
