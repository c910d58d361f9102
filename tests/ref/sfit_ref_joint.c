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
