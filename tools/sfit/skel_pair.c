/* SPDX-License-Identifier: MIT */
/**
 * @file skel_pair.c
 * @brief The joint cost of a pair of segments from their poses (SCoRE /
 * SARA, DESIGN.md section 5), in double on the host.
 *
 * This is the host stand-in for the library's pair module (sfit_pair,
 * issue 28); skel_pair_solve() is the one place to switch over. The
 * accumulators are what a firmware would keep per pair and frame.
 *
 * Cost J(ca, cb) = sum_f |R_a ca + t_a - R_b cb - t_b|^2, d = t_b - t_a:
 *   J = n|ca|^2 + n|cb|^2 - 2 ca^T M cb - 2 ca^T u + 2 cb^T v + e,
 *   M = sum R_a^T R_b, u = sum R_a^T d, v = sum R_b^T d, e = sum |d|^2.
 * Minimum: cb = (M^T ca - v) / n and S ca = u - M v / n with the Schur
 * complement S = n I - M M^T / n. The eigenvalues of S / n lie in [0, 1]
 * and measure the spread of the relative rotation: about a hinge axis
 * w, S w = 0; with no relative motion S = 0.
 */
#include <math.h>
#include <string.h>

#include "skel.h"

/* Decision thresholds (docs/skeleton.md). */
#define SKEL_NO_MOTION_RAD 0.087  /* largest rotation spread below this (5 deg): no joint */
#define SKEL_SMALL_RANGE_RAD 0.17 /* largest rotation spread below this (10 deg): flagged */
#define SKEL_HINGE_RATIO 0.3      /* sqrt(s0 / s1) below this: a hinge */
#define SKEL_MIN_FRAMES 30

void skel_pair_reset(skel_pair_acc_t *a)
{
    memset(a, 0, sizeof *a);
}

void skel_pair_add(skel_pair_acc_t *a, const double ra[9], const double ta[3],
                   const double rb[9], const double tb[3])
{
    int i, j, k;
    double d[3];
    for (i = 0; i < 3; i++) {
        d[i] = tb[i] - ta[i];
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += ra[k * 3 + i] * rb[k * 3 + j];
            }
            a->m[i * 3 + j] += s;
        }
        a->u[i] += ra[0 * 3 + i] * d[0] + ra[1 * 3 + i] * d[1] + ra[2 * 3 + i] * d[2];
        a->v[i] += rb[0 * 3 + i] * d[0] + rb[1 * 3 + i] * d[1] + rb[2 * 3 + i] * d[2];
    }
    a->e += d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    a->n += 1.0;
}

/* Cyclic Jacobi for a symmetric 3x3 (double): a = v diag(w) v^T,
 * eigenvalues ascending, eigenvectors in the columns of v. 0, or -1. */
int skel_eig3(const double a_in[9], double w[3], double v[9])
{
    double a[9];
    int sweep, p, q, i;
    memcpy(a, a_in, sizeof a);
    memset(v, 0, 9u * sizeof *v);
    v[0] = v[4] = v[8] = 1.0;
    for (sweep = 0; sweep < 64; sweep++) {
        const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
        const double diag = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
        if (off <= 1e-30 * diag || off == 0.0) {
            break;
        }
        for (p = 0; p < 2; p++) {
            for (q = p + 1; q < 3; q++) {
                const double apq = a[p * 3 + q];
                double theta, t, c, s;
                if (apq == 0.0) {
                    continue;
                }
                theta = (a[q * 3 + q] - a[p * 3 + p]) / (2.0 * apq);
                t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (i = 0; i < 3; i++) { /* columns p, q of a */
                    const double aip = a[i * 3 + p], aiq = a[i * 3 + q];
                    a[i * 3 + p] = c * aip - s * aiq;
                    a[i * 3 + q] = s * aip + c * aiq;
                }
                for (i = 0; i < 3; i++) { /* rows p, q */
                    const double api = a[p * 3 + i], aqi = a[q * 3 + i];
                    a[p * 3 + i] = c * api - s * aqi;
                    a[q * 3 + i] = s * api + c * aqi;
                }
                for (i = 0; i < 3; i++) {
                    const double vip = v[i * 3 + p], viq = v[i * 3 + q];
                    v[i * 3 + p] = c * vip - s * viq;
                    v[i * 3 + q] = s * vip + c * viq;
                }
            }
        }
    }
    if (sweep == 64) {
        return -1;
    }
    for (i = 0; i < 3; i++) {
        w[i] = a[i * 4];
    }
    /* sort ascending */
    for (p = 0; p < 2; p++) {
        for (q = p + 1; q < 3; q++) {
            if (w[q] < w[p]) {
                const double tw = w[p];
                w[p] = w[q];
                w[q] = tw;
                for (i = 0; i < 3; i++) {
                    const double tv = v[i * 3 + p];
                    v[i * 3 + p] = v[i * 3 + q];
                    v[i * 3 + q] = tv;
                }
            }
        }
    }
    return 0;
}

static double pair_cost(const skel_pair_acc_t *a, const double ca[3], const double cb[3])
{
    double j = a->e;
    int i, k;
    for (i = 0; i < 3; i++) {
        double mcb = 0.0;
        for (k = 0; k < 3; k++) {
            mcb += a->m[i * 3 + k] * cb[k];
        }
        j += a->n * (ca[i] * ca[i] + cb[i] * cb[i]) - 2.0 * ca[i] * mcb - 2.0 * ca[i] * a->u[i]
             + 2.0 * cb[i] * a->v[i];
    }
    return j > 0.0 ? j : 0.0;
}

int skel_pair_solve(const skel_pair_acc_t *a, skel_jtype_t force, skel_pair_res_t *res)
{
    double s[9], w[3], vec[9], rhs[3], y[3], ca[3], cb[3];
    const double n = a->n;
    int i, j, k, nfree;
    skel_pair_res_t r;
    memset(&r, 0, sizeof r);
    if (!(n >= 3.0)) {
        return -1;
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double mm = 0.0;
            for (k = 0; k < 3; k++) {
                mm += a->m[i * 3 + k] * a->m[j * 3 + k];
            }
            s[i * 3 + j] = (i == j ? n : 0.0) - mm / n;
        }
        rhs[i] = a->u[i];
        for (k = 0; k < 3; k++) {
            rhs[i] -= a->m[i * 3 + k] * a->v[k] / n;
        }
    }
    if (skel_eig3(s, w, vec) != 0) {
        return -1;
    }
    for (i = 0; i < 3; i++) {
        r.s[i] = w[i] / n > 0.0 ? w[i] / n : 0.0;
    }
    r.n = n;
    if (n < SKEL_MIN_FRAMES) {
        r.flags |= SKEL_F_FEW_FRAMES;
    }
    if (sqrt(r.s[2]) < SKEL_SMALL_RANGE_RAD) {
        r.flags |= SKEL_F_SMALL_RANGE;
    }
    {
        const double ratio = sqrt(r.s[0] / (r.s[1] > 0.0 ? r.s[1] : 1e-300));
        if (force == SKEL_NONE) {
            if (sqrt(r.s[2]) < SKEL_NO_MOTION_RAD) {
                r.type = SKEL_NONE;
                r.flags |= SKEL_F_NO_MOTION;
            } else {
                r.type = ratio < SKEL_HINGE_RATIO ? SKEL_HINGE : SKEL_BALL;
                if (ratio > SKEL_HINGE_RATIO / 1.5 && ratio < SKEL_HINGE_RATIO * 1.5) {
                    r.flags |= SKEL_F_BORDERLINE;
                }
            }
        } else {
            r.type = force;
            r.flags |= SKEL_F_FORCED;
            if (sqrt(r.s[2]) < SKEL_NO_MOTION_RAD) {
                r.flags |= SKEL_F_NO_MOTION;
            }
        }
    }
    /* y = V^T rhs, solved over the eigen-directions kept */
    nfree = (r.type == SKEL_HINGE) ? 1 : (r.type == SKEL_NONE ? 3 : 0);
    for (i = 0; i < 3; i++) {
        y[i] = 0.0;
        for (k = 0; k < 3; k++) {
            y[i] += vec[k * 3 + i] * rhs[k];
        }
        y[i] = (i < nfree || !(w[i] > 0.0)) ? 0.0 : y[i] / w[i];
    }
    for (i = 0; i < 3; i++) {
        ca[i] = vec[i * 3 + 0] * y[0] + vec[i * 3 + 1] * y[1] + vec[i * 3 + 2] * y[2];
    }
    if (r.type == SKEL_HINGE) {
        /* along the axis: the point nearest the midpoint of the two template
         * origins (0 and the mean of b's origin in a's frame, u / n) */
        double along = 0.0;
        for (i = 0; i < 3; i++) {
            r.axis_a[i] = vec[i * 3 + 0];
            along += (0.5 * a->u[i] / n - ca[i]) * r.axis_a[i];
        }
        for (i = 0; i < 3; i++) {
            ca[i] += along * r.axis_a[i];
        }
    }
    for (i = 0; i < 3; i++) {
        cb[i] = -a->v[i];
        for (k = 0; k < 3; k++) {
            cb[i] += a->m[k * 3 + i] * ca[k];
        }
        cb[i] /= n;
    }
    r.rms = sqrt(pair_cost(a, ca, cb) / n);
    /* covariance of ca: sigma^2 S^-1 over the kept directions,
     * sigma^2 = J / (3n - unknowns) per coordinate */
    {
        const double dof = 3.0 * n - (r.type == SKEL_HINGE ? 4.0 : 6.0);
        const double sig2 = dof > 0.0 ? r.rms * r.rms * n / dof : 0.0;
        double big = 0.0;
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                double c = 0.0;
                for (k = nfree; k < 3; k++) {
                    if (w[k] > 0.0) {
                        c += vec[i * 3 + k] * vec[j * 3 + k] / w[k];
                    }
                }
                r.cov_a[i * 3 + j] = sig2 * c;
            }
        }
        for (k = nfree; k < 3; k++) {
            if (w[k] > 0.0 && sig2 / w[k] > big) {
                big = sig2 / w[k];
            }
        }
        r.sigma = sqrt(big);
    }
    memcpy(r.ca, ca, sizeof ca);
    memcpy(r.cb, cb, sizeof cb);
    *res = r;
    return 0;
}
