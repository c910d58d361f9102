/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref.c
 * @brief Independent double-precision reference for sfit (test oracle).
 *
 * Everything is re-derived here from first principles; the chapter (typeset
 * from a scan) was only used to know what to derive. Findings about the
 * printed equations (also checked numerically by test_ref_selfcheck.c):
 *
 * - eq. 177/189/190 (noise calibration): CORRECT. Derivation above
 *   ref_noise_trace_var(); Var(sigma_hat^2) = 2 s2 (D s2 + 2 r0^2)/(N D^2).
 * - eq. 203/204 (arc) and 210/211 (cap) with theta the HALF-angle: CORRECT
 *   (derivations above ref_arc_eigs_numeric / ref_cap_eigs_numeric; the
 *   numeric quadrature agrees to ~1e-13).
 * - eq. 217/218 (planar solution): 218 agrees with the derivation when the
 *   sum runs over BOTH terms, r^2 = sum_kept [(v_i^T S)^2/(4 l_i^2)
 *   + (N-1)/N l_i] = |c - m|^2 + (N-1)/N (sum of kept l_i). See
 *   ref_fit_circle() for what the solution is exactly.
 * - eq. 219-222 (multi-marker): the gradient of the joint Kasa cost is
 *   sum_p 4 (n_p - 1) (2 C_p (c - m_p) - S_p); eq. 219 drops the factor
 *   (n_p - 1) (exact only when every marker has the same n_p, or if C_p,
 *   S_p denote un-normalised sums). Eq. 220/222 must be read with the
 *   bracket around the whole summand:
 *   c = (sum C_p)^-1 sum (C_p m_p + S_p/2). Both forms are implemented.
 */
#include "sfit_ref.h"

#include <float.h>
#include <math.h>
#include <string.h>

typedef long double ref_ld;
#define LD(v) ((ref_ld)(v)) /* explicit widening (clang -Wdouble-promotion) */

#define REF_GE_MAX 8        /* largest system solved by ref_i_solve */
#define REF_JACOBI_SWEEPS 100
#define REF_LM_MAX_ITERS 500

/* ---------------------------------------------------------------------- */
/* Small helpers                                                           */

/* Gaussian elimination with partial pivoting (row-major a, n <= REF_GE_MAX),
 * b overwritten by the solution. Nonzero on a zero pivot or non-finite x. */
static int ref_i_solve(size_t n, ref_ld *a, ref_ld *b)
{
    size_t i, j, k;
    if (n == 0 || n > REF_GE_MAX) {
        return -1;
    }
    for (k = 0; k < n; ++k) {
        size_t piv = k;
        for (i = k + 1; i < n; ++i) {
            if (fabsl(a[i * n + k]) > fabsl(a[piv * n + k])) {
                piv = i;
            }
        }
        if (!(fabsl(a[piv * n + k]) > 0.0L)) {
            return -1;
        }
        if (piv != k) {
            ref_ld t;
            for (j = 0; j < n; ++j) {
                t = a[k * n + j];
                a[k * n + j] = a[piv * n + j];
                a[piv * n + j] = t;
            }
            t = b[k];
            b[k] = b[piv];
            b[piv] = t;
        }
        for (i = k + 1; i < n; ++i) {
            ref_ld f = a[i * n + k] / a[k * n + k];
            for (j = k; j < n; ++j) {
                a[i * n + j] -= f * a[k * n + j];
            }
            b[i] -= f * b[k];
        }
    }
    for (k = n; k-- > 0;) {
        ref_ld s = b[k];
        for (j = k + 1; j < n; ++j) {
            s -= a[k * n + j] * b[j];
        }
        b[k] = s / a[k * n + k];
        if (!isfinite(b[k])) {
            return -1;
        }
    }
    return 0;
}

/* cov[6] = XX, YY, ZZ, XY, XZ, YZ -> full symmetric matrix (zero if NULL). */
static void ref_i_cov(const double *cov, double s[3][3])
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

/* Ascending eigenvalues w: positive definite within REF_PD_RTOL? */
static int ref_i_pd(const double w[3])
{
    return w[2] > 0.0 && w[0] > REF_PD_RTOL * w[2];
}

/* Column k of v, normalised, sign such that the largest |component| > 0. */
static void ref_i_axis(const double v[3][3], int k, double axis[3])
{
    int i, big = 0;
    double nrm = sqrt(v[0][k] * v[0][k] + v[1][k] * v[1][k] +
                      v[2][k] * v[2][k]);
    for (i = 1; i < 3; ++i) {
        if (fabs(v[i][k]) > fabs(v[big][k])) {
            big = i;
        }
    }
    if (v[big][k] < 0.0) {
        nrm = -nrm;
    }
    for (i = 0; i < 3; ++i) {
        axis[i] = v[i][k] / nrm;
    }
}

/* Spectral radius of A^-1 Sigma restricted to the eigen-directions
 * first..2 of A = V diag(w) V^T: A^-1 Sigma is similar to the symmetric
 * M = W^-1/2 V^T Sigma V W^-1/2, so rho = max |eig(M)| (padding unused rows
 * with zeros only adds the eigenvalue 0). */
static double ref_i_trust(const double w[3], const double v[3][3],
                          const double sig[3][3], int first)
{
    double mm[3][3], e[3], ev[3][3];
    int i, j, k, l;
    memset(mm, 0, sizeof mm);
    for (i = first; i < 3; ++i) {
        for (j = first; j < 3; ++j) {
            ref_ld t = 0.0L;
            for (k = 0; k < 3; ++k) {
                for (l = 0; l < 3; ++l) {
                    t += LD(v[k][i]) * LD(sig[k][l]) * LD(v[l][j]);
                }
            }
            mm[i][j] = (double)t / sqrt(w[i] * w[j]);
        }
    }
    ref_sym3_eig(REF_C3(mm), e, ev);
    return fabs(e[0]) > fabs(e[2]) ? fabs(e[0]) : fabs(e[2]);
}

/* ---------------------------------------------------------------------- */
/* Eigen-decomposition: cyclic Jacobi (Numerical Recipes rotation form).   */

void ref_sym3_eig(const double a_in[3][3], double w[3], double v[3][3])
{
    double a[3][3];
    int i, j, p, q, sweep;

    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            a[i][j] = (i <= j) ? a_in[i][j] : a_in[j][i];
            v[i][j] = (i == j) ? 1.0 : 0.0;
        }
    }
    for (sweep = 0; sweep < REF_JACOBI_SWEEPS; ++sweep) {
        int rotated = 0;
        for (p = 0; p < 2; ++p) {
            for (q = p + 1; q < 3; ++q) {
                double apq = a[p][q], theta, t, c, s, tau, arp, arq;
                int r = 3 - p - q, k;
                if (apq == 0.0) {
                    continue;
                }
                /* Negligible against both diagonal entries: drop it. */
                if (fabs(a[p][p]) + 1e3 * fabs(apq) == fabs(a[p][p]) &&
                    fabs(a[q][q]) + 1e3 * fabs(apq) == fabs(a[q][q])) {
                    a[p][q] = a[q][p] = 0.0;
                    continue;
                }
                /* Rotation angle zeroing a_pq: t = tan, smaller root. */
                theta = 0.5 * (a[q][q] - a[p][p]) / apq;
                if (fabs(theta) > 1e150) {
                    t = 0.5 / theta;
                } else {
                    t = 1.0 / (fabs(theta) + sqrt(1.0 + theta * theta));
                    if (theta < 0.0) {
                        t = -t;
                    }
                }
                c = 1.0 / sqrt(1.0 + t * t);
                s = t * c;
                tau = s / (1.0 + c);
                a[p][p] -= t * apq;
                a[q][q] += t * apq;
                a[p][q] = a[q][p] = 0.0;
                arp = a[r][p];
                arq = a[r][q];
                a[r][p] = a[p][r] = arp - s * (arq + tau * arp);
                a[r][q] = a[q][r] = arq + s * (arp - tau * arq);
                for (k = 0; k < 3; ++k) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = vkp - s * (vkq + tau * vkp);
                    v[k][q] = vkq + s * (vkp - tau * vkq);
                }
                rotated = 1;
            }
        }
        if (!rotated) {
            break;
        }
    }
    for (i = 0; i < 3; ++i) {
        w[i] = a[i][i];
    }
    /* Selection sort, ascending, moving eigenvector columns along. */
    for (i = 0; i < 2; ++i) {
        int mi = i;
        for (j = i + 1; j < 3; ++j) {
            if (w[j] < w[mi]) {
                mi = j;
            }
        }
        if (mi != i) {
            double t = w[i];
            w[i] = w[mi];
            w[mi] = t;
            for (j = 0; j < 3; ++j) {
                t = v[j][i];
                v[j][i] = v[j][mi];
                v[j][mi] = t;
            }
        }
    }
}

/* ---------------------------------------------------------------------- */
/* Moments                                                                 */

/* Points as a flat array x[3 i + j] (shared with the multi-marker code). */
static int ref_i_moments(const double *x, size_t n, double mean[3],
                         double C[3][3], double S[3])
{
    ref_ld m[3] = {0.0L, 0.0L, 0.0L}, d[3] = {0.0L, 0.0L, 0.0L};
    ref_ld c[3][3], s[3] = {0.0L, 0.0L, 0.0L};
    ref_ld nn = (ref_ld)n;
    size_t i;
    int j, k;

    if (x == NULL || n < 2) {
        return -1;
    }
    /* Pass 1: mean; pass 1b: add the mean of the residuals (removes the
     * rounding error of the first sum); pass 2: centred moments. */
    for (i = 0; i < n; ++i) {
        for (j = 0; j < 3; ++j) {
            m[j] += LD(x[3 * i + (size_t)j]);
        }
    }
    for (j = 0; j < 3; ++j) {
        m[j] /= nn;
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < 3; ++j) {
            d[j] += (ref_ld)x[3 * i + (size_t)j] - m[j];
        }
    }
    for (j = 0; j < 3; ++j) {
        m[j] += d[j] / nn;
    }
    memset(c, 0, sizeof c);
    for (i = 0; i < n; ++i) {
        ref_ld y[3], q;
        for (j = 0; j < 3; ++j) {
            y[j] = (ref_ld)x[3 * i + (size_t)j] - m[j];
        }
        q = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
        for (j = 0; j < 3; ++j) {
            s[j] += q * y[j];
            for (k = j; k < 3; ++k) {
                c[j][k] += y[j] * y[k];
            }
        }
    }
    for (j = 0; j < 3; ++j) {
        mean[j] = (double)m[j];
        S[j] = (double)(s[j] / (nn - 1.0L));
        for (k = j; k < 3; ++k) {
            C[j][k] = C[k][j] = (double)(c[j][k] / (nn - 1.0L));
        }
    }
    return 0;
}

int ref_moments(const double (*x)[3], size_t n, double mean[3], double C[3][3],
                double S[3])
{
    return x == NULL ? -1 : ref_i_moments(x[0], n, mean, C, S);
}

/* ---------------------------------------------------------------------- */
/* Sphere: GDKE / UGDK                                                     */
/*
 * Kasa: minimise sum (|x_i - c|^2 - rho)^2 over c, rho. With y = x - m and
 * d = c - m the residual is |y|^2 - 2 d.y - k, k = rho - |d|^2. d/dk = 0
 * gives k = mean |y|^2 = (n-1)/n tr C (sum y = 0); d/dd = 0 then gives
 * sum (|y|^2 - k) y = 2 sum y y^T d, i.e. S = 2 C d: c = m + C^-1 S / 2
 * and r^2 = rho = (n-1)/n tr C + |m - c|^2. UGDK replaces C by
 * C' = C - Sigma (E C = C0 + Sigma, eq. 171-176).
 */
int ref_fit_sphere(const double (*x)[3], size_t n, const double *cov,
                   ref_fit_t *out)
{
    double m[3], C[3][3], S[3], sig[3][3], Cp[3][3];
    double w[3], v[3][3], wp[3], vp[3][3];
    ref_ld a[9], b[3], r2;
    int i, j;

    if (x == NULL || out == NULL || n < 4 || ref_moments(x, n, m, C, S)) {
        return -1;
    }
    ref_i_cov(cov, sig);
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            Cp[i][j] = C[i][j] - sig[i][j];
        }
    }
    ref_sym3_eig(REF_C3(C), w, v);
    ref_sym3_eig(REF_C3(Cp), wp, vp);
    if (!ref_i_pd(w) || !ref_i_pd(wp)) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        b[i] = 0.5L * LD(S[i]);
        for (j = 0; j < 3; ++j) {
            a[3 * i + j] = LD(Cp[i][j]);
        }
    }
    if (ref_i_solve(3, a, b)) {
        return -1;
    }
    r2 = ((ref_ld)n - 1.0L) / (ref_ld)n * (LD(Cp[0][0]) + LD(Cp[1][1]) +
                                            LD(Cp[2][2])) +
         b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
    if (!(r2 > 0.0L)) {
        return -1;
    }
    for (i = 0; i < 3; ++i) {
        out->center[i] = (double)((ref_ld)m[i] + b[i]);
        out->eig[i] = w[i];
    }
    out->radius = (double)sqrtl(r2);
    ref_i_axis(REF_C3(v), 0, out->axis);
    out->planar = 0;
    out->trust_ratio = cov ? ref_i_trust(wp, REF_C3(vp), REF_C3(sig), 0) : 0.0;
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Circle: planar / cylindrical joint                                      */
/*
 * Constrain the Kasa centre to the best-fit plane through m, d = c - m =
 * a1 v1 + a2 v2 (v1, v2 eigenvectors of the two largest eigenvalues). The
 * derivation above restricted to that plane gives v_i^T S = 2 l_i a_i:
 *   c = m + 1/2 sum_kept (v_i^T S / l_i) v_i        (eq. 217).
 * The radius is the in-plane one: r^2 = (n-1)/n (l1 + l2) + |c - m|^2,
 * i.e. the mean squared in-plane distance to c (the out-of-plane variance
 * l3 is wobble, not radius). Eq. 218 as printed is the same expression
 * written per eigen-direction (|c - m|^2 = sum (v_i^T S)^2 / (4 l_i^2));
 * it agrees provided the sum covers both terms.
 * For exactly planar data this is the 2-D Kasa circle in that plane. With
 * out-of-plane scatter h_i the centre still uses |y|^2 including h_i^2 (it
 * is the 3-D Kasa fit with the centre constrained to the plane), which
 * differs from the 2-D Kasa fit of the projected points by the term
 * sum h_i^2 (v_j^T y_i) / (2 (n-1) l_j): small for a hinge.
 */
int ref_fit_circle(const double (*x)[3], size_t n, const double *cov,
                   ref_fit_t *out)
{
    double m[3], C[3][3], S[3], sig[3][3], Cp[3][3];
    double w[3], v[3][3], wp[3], vp[3][3], d[3] = {0.0, 0.0, 0.0};
    ref_ld r2;
    int i, j, k;

    if (x == NULL || out == NULL || n < 3 || ref_moments(x, n, m, C, S)) {
        return -1;
    }
    ref_i_cov(cov, sig);
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            Cp[i][j] = C[i][j] - sig[i][j];
        }
    }
    ref_sym3_eig(REF_C3(C), w, v);
    ref_sym3_eig(REF_C3(Cp), wp, vp);
    if (!(wp[2] > 0.0 && wp[1] > REF_PD_RTOL * wp[2])) {
        return -1;
    }
    for (k = 1; k < 3; ++k) {
        double vs = vp[0][k] * S[0] + vp[1][k] * S[1] + vp[2][k] * S[2];
        for (i = 0; i < 3; ++i) {
            d[i] += 0.5 * vs / wp[k] * vp[i][k];
        }
    }
    r2 = ((ref_ld)n - 1.0L) / (ref_ld)n * (LD(wp[1]) + LD(wp[2])) +
         LD(d[0]) * LD(d[0]) + LD(d[1]) * LD(d[1]) + LD(d[2]) * LD(d[2]);
    for (i = 0; i < 3; ++i) {
        out->center[i] = m[i] + d[i];
        out->eig[i] = w[i];
    }
    out->radius = (double)sqrtl(r2);
    ref_i_axis(REF_C3(vp), 0, out->axis);
    out->planar = 1;
    /* In-plane trust ratio: rho((P^T C' P)^-1 P^T Sigma P), P = [v2 v3];
     * isotropic: sigma^2 / l2' (the circle condition of eq. 213). */
    out->trust_ratio = cov ? ref_i_trust(wp, REF_C3(vp), REF_C3(sig), 1) : 0.0;
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Direct algebraic fits (independent of the moment formulation)           */
/*
 * Circle: minimise sum (u^2 + v^2 + D u + E v + F)^2 (linear in D, E, F)
 * through its normal equations; centre (-D/2, -E/2), r^2 = (D^2+E^2)/4 - F.
 * Data are shifted by their mean first (the fit is translation-equivariant)
 * only for conditioning; the 3x3 system is solved in full.
 */
int ref_kasa_circle_2d(const double (*p)[2], size_t n, double c[2], double *r)
{
    ref_ld sh[2] = {0.0L, 0.0L}, a[9], b[3], r2;
    size_t i;
    int j, k;

    if (p == NULL || c == NULL || r == NULL || n < 3) {
        return -1;
    }
    for (i = 0; i < n; ++i) {
        sh[0] += LD(p[i][0]);
        sh[1] += LD(p[i][1]);
    }
    sh[0] /= (ref_ld)n;
    sh[1] /= (ref_ld)n;
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    for (i = 0; i < n; ++i) {
        ref_ld row[3];
        ref_ld z;
        row[0] = (ref_ld)p[i][0] - sh[0];
        row[1] = (ref_ld)p[i][1] - sh[1];
        row[2] = 1.0L;
        z = row[0] * row[0] + row[1] * row[1];
        for (j = 0; j < 3; ++j) {
            b[j] -= row[j] * z;
            for (k = 0; k < 3; ++k) {
                a[3 * j + k] += row[j] * row[k];
            }
        }
    }
    if (ref_i_solve(3, a, b)) {
        return -1;
    }
    r2 = 0.25L * (b[0] * b[0] + b[1] * b[1]) - b[2];
    if (!(r2 > 0.0L)) {
        return -1;
    }
    c[0] = (double)(sh[0] - 0.5L * b[0]);
    c[1] = (double)(sh[1] - 0.5L * b[1]);
    *r = (double)sqrtl(r2);
    return 0;
}

/* Sphere: minimise sum (|x|^2 + a.x + b)^2, 4x4 normal equations. */
int ref_kasa_sphere_direct(const double (*x)[3], size_t n, double c[3],
                           double *r)
{
    ref_ld sh[3] = {0.0L, 0.0L, 0.0L}, a[16], b[4], r2;
    size_t i;
    int j, k;

    if (x == NULL || c == NULL || r == NULL || n < 4) {
        return -1;
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < 3; ++j) {
            sh[j] += LD(x[i][j]);
        }
    }
    for (j = 0; j < 3; ++j) {
        sh[j] /= (ref_ld)n;
    }
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    for (i = 0; i < n; ++i) {
        ref_ld row[4], z = 0.0L;
        for (j = 0; j < 3; ++j) {
            row[j] = (ref_ld)x[i][j] - sh[j];
            z += row[j] * row[j];
        }
        row[3] = 1.0L;
        for (j = 0; j < 4; ++j) {
            b[j] -= row[j] * z;
            for (k = 0; k < 4; ++k) {
                a[4 * j + k] += row[j] * row[k];
            }
        }
    }
    if (ref_i_solve(4, a, b)) {
        return -1;
    }
    r2 = 0.25L * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]) - b[3];
    if (!(r2 > 0.0L)) {
        return -1;
    }
    for (j = 0; j < 3; ++j) {
        c[j] = (double)(sh[j] - 0.5L * b[j]);
    }
    *r = (double)sqrtl(r2);
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Noise calibration (eq. 177, 189, 190)                                   */

double ref_noise_trace(const double (*x)[3], size_t n, const double c0[3],
                       double r0)
{
    ref_ld s = 0.0L;
    size_t i;
    int j;
    if (x == NULL || c0 == NULL || n == 0) {
        return (double)NAN;
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < 3; ++j) {
            ref_ld d = LD(x[i][j]) - LD(c0[j]);
            s += d * d;
        }
    }
    return (double)(s / (ref_ld)n - LD(r0) * LD(r0));
}

/*
 * Derivation. x_i = mu_i + e_i, |mu_i - c0| = r0, e_i ~ N(0, Sigma),
 * u_i = mu_i - c0. Then |x_i - c0|^2 - r0^2 = 2 u_i.e_i + |e_i|^2, so
 *   T = Tr(Sigma_hat) = 1/N sum (2 u_i.e_i + |e_i|^2),  E T = Tr Sigma.
 * For a Gaussian, Var(|e|^2) = 2 Tr(Sigma^2), Var(2 u.e) = 4 u^T Sigma u,
 * and Cov(u.e, |e|^2) = 0 (odd moment). Samples are independent, so
 *   Var T = 2/N (Tr(Sigma^2) + 2/N sum u_i^T Sigma u_i)        (= eq. 189).
 * Isotropic Sigma = s2 I in D dimensions: Tr(Sigma^2) = D s2^2,
 * u^T Sigma u = s2 r0^2, and sigma_hat^2 = T / D:
 *   Var(sigma_hat^2) = 2 s2 (D s2 + 2 r0^2) / (N D^2)           (= eq. 190).
 * Exact for any N (c0, r0 known, no O(1/N^2) term). Eq. 190 is correct.
 */
double ref_noise_trace_var(double sigma2, double r0, size_t n, int dim)
{
    double dd = (double)dim;
    if (n == 0 || dim < 1) {
        return (double)NAN;
    }
    return 2.0 * sigma2 * (dd * sigma2 + 2.0 * r0 * r0) /
           ((double)n * dd * dd);
}

/* ---------------------------------------------------------------------- */
/* Multi-marker (eq. 219-223)                                              */
/*
 * Joint Kasa cost: sum_p sum_i (|x_pi - c|^2 - rho_p)^2, one radius per
 * marker and a common centre. Per marker (derivation of ref_fit_sphere with
 * d_p = c - m_p) the gradient in c is 4 (n_p - 1) (2 C_p (c - m_p) - S_p).
 * Zero total gradient: c = (sum w_p C_p)^-1 sum w_p (C_p m_p + S_p / 2)
 * with w_p = n_p - 1 (exact joint least squares, ref_fit_multi_weighted);
 * eq. 220 as printed uses w_p = 1 (ref_fit_multi). Radii: eq. 221
 * (rho_p = mean_i |x_pi - c|^2 = (n_p-1)/n_p tr C_p + |m_p - c|^2). The
 * unbiased form (eq. 222/223) uses C'_p = C_p - Sigma everywhere. Sums are
 * taken relative to the first marker's mean (conditioning only).
 */
static int ref_i_multi(const double *const *xs, const size_t *ns, size_t m,
                       const double *cov, double center[3], double *radii,
                       int weighted)
{
    double sig[3][3], mp[3], C[3][3], S[3], o[3] = {0.0, 0.0, 0.0};
    double aw[3][3], w[3], v[3][3];
    ref_ld a[9], b[3] = {0.0L, 0.0L, 0.0L};
    size_t p;
    int i, j, pass;

    if (xs == NULL || ns == NULL || center == NULL || radii == NULL ||
        m == 0) {
        return -1;
    }
    ref_i_cov(cov, sig);
    memset(a, 0, sizeof a);
    for (p = 0; p < m; ++p) {
        ref_ld wp;
        if (ref_i_moments(xs[p], ns[p], mp, C, S)) {
            return -1;
        }
        if (p == 0) {
            memcpy(o, mp, sizeof o);
        }
        wp = weighted ? (ref_ld)ns[p] - 1.0L : 1.0L;
        for (i = 0; i < 3; ++i) {
            ref_ld t = 0.5L * LD(S[i]);
            for (j = 0; j < 3; ++j) {
                ref_ld cij = LD(C[i][j]) - LD(sig[i][j]);
                a[3 * i + j] += wp * cij;
                t += cij * (LD(mp[j]) - LD(o[j]));
            }
            b[i] += wp * t;
        }
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            aw[i][j] = (double)a[3 * i + j];
        }
    }
    ref_sym3_eig(REF_C3(aw), w, v);
    if (!ref_i_pd(w) || ref_i_solve(3, a, b)) {
        return -1;
    }
    /* Pass 0 checks every radius, pass 1 writes (outputs untouched on
     * failure). */
    for (pass = 0; pass < 2; ++pass) {
        for (p = 0; p < m; ++p) {
            ref_ld r2, np = (ref_ld)ns[p];
            (void)ref_i_moments(xs[p], ns[p], mp, C, S);
            r2 = (np - 1.0L) / np *
                 (LD(C[0][0]) + LD(C[1][1]) + LD(C[2][2]) - LD(sig[0][0]) -
                  LD(sig[1][1]) - LD(sig[2][2]));
            for (i = 0; i < 3; ++i) {
                ref_ld d = LD(mp[i]) - LD(o[i]) - b[i];
                r2 += d * d;
            }
            if (!(r2 > 0.0L)) {
                return -1;
            }
            if (pass == 1) {
                radii[p] = (double)sqrtl(r2);
            }
        }
    }
    for (i = 0; i < 3; ++i) {
        center[i] = (double)(LD(o[i]) + b[i]);
    }
    return 0;
}

int ref_fit_multi(const double *const *xs, const size_t *ns, size_t m,
                  const double *cov, double center[3], double *radii)
{
    return ref_i_multi(xs, ns, m, cov, center, radii, 0);
}

int ref_fit_multi_weighted(const double *const *xs, const size_t *ns, size_t m,
                           const double *cov, double center[3], double *radii)
{
    return ref_i_multi(xs, ns, m, cov, center, radii, 1);
}

/* ---------------------------------------------------------------------- */
/* Geometric (orthogonal-distance) fit: Levenberg-Marquardt                */
/*
 * Residuals e_i = |x_i - c| - r, Jacobian rows [-(x_i - c)^T / |x_i - c|, -1].
 * Marquardt damping (J^T J + lambda diag(J^T J)) d = -J^T e; a step is kept
 * only if the cost does not increase (beyond its own rounding). Converged
 * when the step is below 1e-14 of the problem scale, or when no damped step
 * can lower the cost (minimum reached to rounding).
 */
static ref_ld ref_i_geo_cost(const double (*x)[3], size_t n, const double p[4])
{
    ref_ld s = 0.0L;
    size_t i;
    for (i = 0; i < n; ++i) {
        ref_ld dx = LD(x[i][0]) - LD(p[0]), dy = LD(x[i][1]) - LD(p[1]);
        ref_ld dz = LD(x[i][2]) - LD(p[2]);
        ref_ld e = sqrtl(dx * dx + dy * dy + dz * dz) - LD(p[3]);
        s += e * e;
    }
    return s;
}

int ref_fit_geometric(const double (*x)[3], size_t n, const double c_init[3],
                      double r_init, double c[3], double *r, int *iters)
{
    double p[4], pn[4];
    ref_ld cost, lambda = 1e-3L;
    int it, j, k;

    if (x == NULL || c_init == NULL || c == NULL || r == NULL || n < 4) {
        return -1;
    }
    p[0] = c_init[0];
    p[1] = c_init[1];
    p[2] = c_init[2];
    p[3] = r_init;
    cost = ref_i_geo_cost(x, n, p);
    for (it = 1; it <= REF_LM_MAX_ITERS; ++it) {
        ref_ld jtj[16], g[4], a[16], d[4], cn = cost, step = 0.0L, scale, dmax;
        size_t i;
        int stalled = 0;
        memset(jtj, 0, sizeof jtj);
        memset(g, 0, sizeof g);
        for (i = 0; i < n; ++i) {
            ref_ld u[4], dist;
            for (j = 0; j < 3; ++j) {
                u[j] = LD(x[i][j]) - LD(p[j]);
            }
            dist = sqrtl(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            if (!(dist > 0.0L)) {
                return -1;
            }
            for (j = 0; j < 3; ++j) {
                u[j] = -u[j] / dist;
            }
            u[3] = -1.0L;
            for (j = 0; j < 4; ++j) {
                g[j] += u[j] * (dist - LD(p[3]));
                for (k = 0; k < 4; ++k) {
                    jtj[4 * j + k] += u[j] * u[k];
                }
            }
        }
        dmax = 0.0L;
        for (j = 0; j < 4; ++j) {
            dmax = jtj[5 * j] > dmax ? jtj[5 * j] : dmax;
        }
        for (;;) {
            memcpy(a, jtj, sizeof a);
            for (j = 0; j < 4; ++j) {
                /* the 1e-9 dmax floor damps directions that carry no
                 * information (e.g. off-plane for planar data) */
                a[5 * j] += lambda * (jtj[5 * j] + 1e-9L * dmax);
                d[j] = -g[j];
            }
            if (ref_i_solve(4, a, d)) {
                return -1;
            }
            for (j = 0; j < 4; ++j) {
                pn[j] = (double)((ref_ld)p[j] + d[j]);
            }
            cn = ref_i_geo_cost(x, n, pn);
            /* accept within the rounding of the cost itself, else the
             * minimum is only resolved to sqrt(eps) when long double is
             * double */
            if (cn <= cost * (1.0L + 8.0L * (ref_ld)n * LDBL_EPSILON)) {
                break;
            }
            lambda *= 10.0L;
            if (lambda > 1e20L) {
                stalled = 1;
                break;
            }
        }
        if (stalled) {
            break;
        }
        scale = fabsl((ref_ld)p[0]) + fabsl((ref_ld)p[1]) +
                fabsl((ref_ld)p[2]) + fabsl((ref_ld)p[3]);
        for (j = 0; j < 4; ++j) {
            step += fabsl(d[j]);
            p[j] = pn[j];
        }
        cost = cn;
        lambda = lambda * 0.1L > 1e-12L ? lambda * 0.1L : 1e-12L;
        if (step <= 1e-14L * scale) {
            break;
        }
    }
    if (it > REF_LM_MAX_ITERS) {
        return -1;
    }
    c[0] = p[0];
    c[1] = p[1];
    c[2] = p[2];
    *r = p[3];
    if (iters != NULL) {
        *iters = it;
    }
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Cramer-Rao bound                                                        */
/*
 * x_i = c + r u_i + e_i, e_i ~ N(0, s2 I), u_i unit (the angles of u_i are
 * nuisance parameters). The derivatives of the mean of x_i are I (centre),
 * u_i (radius) and tangential vectors (angles); eliminating the tangential
 * nuisance leaves the radial projection, so the Fisher information of
 * (c, r) is sum J_i^T J_i / s2 with J_i = [-u_i^T, -1] (sign irrelevant).
 */
void ref_crlb_sphere(const double (*x_true)[3], size_t n, const double c[3],
                     double r, double sigma2, double crlb[4][4])
{
    ref_ld f[16], a[16], col[4];
    size_t i;
    int j, k;

    (void)r; /* the samples carry the radius; r is for documentation */
    memset(f, 0, sizeof f);
    memset(crlb, 0, 16 * sizeof(double));
    if (x_true == NULL || c == NULL || !(sigma2 > 0.0)) {
        return;
    }
    for (i = 0; i < n; ++i) {
        ref_ld u[4], dist;
        for (j = 0; j < 3; ++j) {
            u[j] = LD(x_true[i][j]) - LD(c[j]);
        }
        dist = sqrtl(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        if (!(dist > 0.0L)) {
            return;
        }
        for (j = 0; j < 3; ++j) {
            u[j] = -u[j] / dist;
        }
        u[3] = -1.0L;
        for (j = 0; j < 4; ++j) {
            for (k = 0; k < 4; ++k) {
                f[4 * j + k] += u[j] * u[k] / (ref_ld)sigma2;
            }
        }
    }
    for (k = 0; k < 4; ++k) {
        memcpy(a, f, sizeof a);
        for (j = 0; j < 4; ++j) {
            col[j] = (j == k) ? 1.0L : 0.0L;
        }
        if (ref_i_solve(4, a, col)) {
            memset(crlb, 0, 16 * sizeof(double));
            return;
        }
        for (j = 0; j < 4; ++j) {
            crlb[j][k] = (double)col[j];
        }
    }
}

int ref_sandwich_geometric(const double (*x)[3], size_t n, const double c[3],
                           double cov[4][4])
{
    ref_ld jtj[16], a[16], ainv[16], col[4], rbar = 0.0L, s2 = 0.0L;
    size_t i;
    int j, k, l;

    memset(jtj, 0, sizeof jtj);
    memset(a, 0, sizeof a);
    for (i = 0; i < n; ++i) {
        ref_ld v[3];
        for (j = 0; j < 3; ++j) {
            v[j] = LD(x[i][j]) - LD(c[j]);
        }
        rbar += sqrtl(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    rbar /= (ref_ld)n;
    for (i = 0; i < n; ++i) {
        ref_ld u[4], v[3], d, f;
        for (j = 0; j < 3; ++j) {
            v[j] = LD(x[i][j]) - LD(c[j]);
        }
        d = sqrtl(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(d > 0.0L)) {
            return -1;
        }
        f = d - rbar;
        s2 += f * f;
        for (j = 0; j < 3; ++j) {
            u[j] = -v[j] / d;
        }
        u[3] = -1.0L;
        for (j = 0; j < 4; ++j) {
            for (k = 0; k < 4; ++k) {
                jtj[4 * j + k] += u[j] * u[k];
            }
        }
        for (j = 0; j < 3; ++j) {
            for (k = 0; k < 3; ++k) {
                a[4 * j + k] += f * (((j == k) ? 1.0L : 0.0L) - u[j] * u[k]) / d;
            }
        }
    }
    s2 /= (ref_ld)(n - 4u);
    for (j = 0; j < 16; ++j) {
        a[j] += jtj[j];
    }
    for (k = 0; k < 4; ++k) {
        ref_ld t[16];
        memcpy(t, a, sizeof t);
        for (j = 0; j < 4; ++j) {
            col[j] = (j == k) ? 1.0L : 0.0L;
        }
        if (ref_i_solve(4, t, col)) {
            return -1;
        }
        for (j = 0; j < 4; ++j) {
            ainv[4 * j + k] = col[j];
        }
    }
    for (j = 0; j < 4; ++j) {
        for (k = 0; k < 4; ++k) {
            ref_ld acc = 0.0L;
            int m;
            for (l = 0; l < 4; ++l) {
                for (m = 0; m < 4; ++m) {
                    acc += ainv[4 * j + l] * jtj[4 * l + m] * ainv[4 * m + k];
                }
            }
            cov[j][k] = (double)(s2 * acc);
        }
    }
    return 0;
}

/* Sum over the samples of the self-calibration's estimating functions at
 * theta = (c, rho, v); sum psi psi^T added into b (5 x 5) when not NULL. */
static int ref_i_selfcal_psi(const double (*x)[3], size_t n, const ref_ld th[5], ref_ld tot[5],
                             ref_ld *b)
{
    const ref_ld k = (ref_ld)(n - 1u) / (ref_ld)n;
    const ref_ld kv = th[4] - th[4] * th[4] / th[3];
    ref_ld dbar = 0.0L;
    size_t i;
    int j;
    for (i = 0; i < n; ++i) {
        ref_ld z[3];
        for (j = 0; j < 3; ++j) {
            z[j] = LD(x[i][j]) - th[j];
        }
        dbar += sqrtl(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    }
    dbar /= (ref_ld)n;
    memset(tot, 0, 5 * sizeof tot[0]);
    for (i = 0; i < n; ++i) {
        ref_ld z[3], z2, d, p[5];
        for (j = 0; j < 3; ++j) {
            z[j] = LD(x[i][j]) - th[j];
        }
        z2 = z[0] * z[0] + z[1] * z[1] + z[2] * z[2];
        d = sqrtl(z2);
        if (!(d > 0.0L)) {
            return -1;
        }
        for (j = 0; j < 3; ++j) {
            p[j] = (z2 - th[3] - 5.0L * k * th[4]) * z[j];
        }
        p[3] = z2 - th[3] - 3.0L * k * th[4];
        p[4] = (d - dbar) * (d - dbar) - (ref_ld)(n - 4u) / (ref_ld)n * kv;
        for (j = 0; j < 5; ++j) {
            int l;
            tot[j] += p[j];
            for (l = 0; l < 5 && b != NULL; ++l) {
                b[5 * j + l] += p[j] * p[l];
            }
        }
    }
    return 0;
}

int ref_sandwich_selfcal(const double (*x)[3], size_t n, const double c[3], double r,
                         double v, double cov[3][3])
{
    ref_ld th[5], a[25], ainv[25], b[25], col[5], tp[5], tm[5];
    /* the widening of docs/coverage.md rule 7: 1 + K (v / r^2) s / s(100),
     * s = sqrt(2 / (n - 4)), n - 4 taken at least 10 */
    const ref_ld widen = 1.0L + LD(REF_COV_WIDEN_K) * (LD(v) / (LD(r) * LD(r)))
                                    * sqrtl(96.0L / ((n > 14u) ? (ref_ld)(n - 4u) : 10.0L));
    int j, k, l, m;
    if (n < 14u) {
        return -1;
    }
    for (j = 0; j < 3; ++j) {
        th[j] = LD(c[j]);
    }
    th[3] = LD(r) * LD(r);
    th[4] = LD(v);
    memset(b, 0, sizeof b);
    if (ref_i_selfcal_psi(x, n, th, tp, b)) {
        return -1;
    }
    for (k = 0; k < 5; ++k) { /* column k of A: central difference */
        const ref_ld h = (k < 3) ? 1e-3L * LD(r) : ((k == 3) ? 1e-4L * th[3] : 1e-3L * (th[4] + 1e-3L));
        const ref_ld keep = th[k];
        th[k] = keep + h;
        (void)ref_i_selfcal_psi(x, n, th, tp, NULL);
        th[k] = keep - h;
        (void)ref_i_selfcal_psi(x, n, th, tm, NULL);
        th[k] = keep;
        for (j = 0; j < 5; ++j) {
            a[5 * j + k] = (tp[j] - tm[j]) / (2.0L * h);
        }
    }
    for (k = 0; k < 5; ++k) {
        ref_ld t[25];
        memcpy(t, a, sizeof t);
        for (j = 0; j < 5; ++j) {
            col[j] = (j == k) ? 1.0L : 0.0L;
        }
        if (ref_i_solve(5, t, col)) {
            return -1;
        }
        for (j = 0; j < 5; ++j) {
            ainv[5 * j + k] = col[j];
        }
    }
    for (j = 0; j < 3; ++j) {
        for (k = 0; k < 3; ++k) {
            ref_ld acc = 0.0L;
            for (l = 0; l < 5; ++l) {
                for (m = 0; m < 5; ++m) {
                    acc += ainv[5 * j + l] * b[5 * l + m] * ainv[5 * k + m];
                }
            }
            cov[j][k] = (double)(acc * (ref_ld)n / (ref_ld)(n - 13u) * widen);
        }
    }
    return 0;
}

/* ---------------------------------------------------------------------- */
/* Cap / arc covariance by quadrature                                      */
/*
 * Composite Simpson over the polar (cap) or arc angle with REF_QA
 * intervals, and for the cap the periodic trapezoid rule over the azimuth
 * with REF_QB nodes (exact for trigonometric polynomials of degree below
 * REF_QB; the integrands have degree <= 2). The mean is computed first and
 * the covariance integrates (v - mean)(v - mean)^T (no cancellation), both
 * normalised by the quadrature's own measure. The full 3x3 matrix is
 * built and diagonalised: no symmetry is assumed.
 *
 * Closed forms they are checked against (derived, theta = half-angle):
 *  arc v = r (sin a, cos a), a ~ U(-theta, theta):
 *   E sin^2 a = (theta - sin theta cos theta) / (2 theta)     -> eq. 204;
 *   E cos a = sin theta / theta; E cos^2 a = (theta + sin cos)/(2 theta):
 *   Var = [theta (2 theta + sin 2theta) - 4 sin^2 theta] / (4 theta^2)
 *                                                             -> eq. 203.
 *  cap, density sin a on [0, theta] x [0, 2 pi), c = cos theta:
 *   E z = (1 + c)/2 = cos^2(theta/2) (eq. 208); E z^2 = (1 + c + c^2)/3,
 *   Var z = (1 - c)^2 / 12 = sin^4(theta/2) / 3                -> eq. 210;
 *   E x^2 = (1/2) int sin^3 / (1 - c) = (1 - c)(2 + c)/6
 *         = (2 + cos theta) sin^2(theta/2) / 3                 -> eq. 211.
 */
#define REF_QA 4000
#define REF_QB 32

static double ref_i_simpson_w(int i, double h)
{
    if (i == 0 || i == REF_QA) {
        return h / 3.0;
    }
    return (i % 2) ? 4.0 * h / 3.0 : 2.0 * h / 3.0;
}

static void ref_i_cap_point(double a, double bang, double r, double v[3])
{
    v[0] = r * sin(a) * cos(bang);
    v[1] = r * sin(a) * sin(bang);
    v[2] = r * cos(a);
}

void ref_cap_eigs_numeric(double theta, double r, double *lmin, double *lmax)
{
    const double two_pi = 6.283185307179586476925286766559;
    double h = theta / REF_QA, hb = two_pi / REF_QB, v[3], w[3], ev[3][3];
    double cm[3][3];
    ref_ld mu[3] = {0.0L, 0.0L, 0.0L}, cv[3][3], meas = 0.0L;
    int i, jb, j, k, pass;

    memset(cv, 0, sizeof cv);
    for (pass = 0; pass < 2; ++pass) {
        for (i = 0; i <= REF_QA; ++i) {
            double a = h * i;
            double wa = ref_i_simpson_w(i, h) * sin(a) * hb;
            for (jb = 0; jb < REF_QB; ++jb) {
                ref_i_cap_point(a, hb * jb, r, v);
                if (pass == 0) {
                    meas += LD(wa);
                    for (j = 0; j < 3; ++j) {
                        mu[j] += LD(wa) * LD(v[j]);
                    }
                } else {
                    ref_ld y[3];
                    for (j = 0; j < 3; ++j) {
                        y[j] = (ref_ld)v[j] - mu[j];
                    }
                    for (j = 0; j < 3; ++j) {
                        for (k = 0; k < 3; ++k) {
                            cv[j][k] += LD(wa) * y[j] * y[k];
                        }
                    }
                }
            }
        }
        if (pass == 0) {
            for (j = 0; j < 3; ++j) {
                mu[j] /= meas;
            }
        }
    }
    for (j = 0; j < 3; ++j) {
        for (k = 0; k < 3; ++k) {
            cm[j][k] = (double)(cv[j][k] / meas);
        }
    }
    ref_sym3_eig(REF_C3(cm), w, ev);
    *lmin = w[0];
    *lmax = w[2];
}

void ref_arc_eigs_numeric(double theta, double r, double *lmin, double *lmax)
{
    double h = 2.0 * theta / REF_QA, w[3], ev[3][3], cm[3][3];
    ref_ld mu[2] = {0.0L, 0.0L}, cv[2][2], meas = 0.0L;
    int i, j, k, pass;

    memset(cv, 0, sizeof cv);
    for (pass = 0; pass < 2; ++pass) {
        for (i = 0; i <= REF_QA; ++i) {
            double a = -theta + h * i, wa = ref_i_simpson_w(i, h);
            double v[2];
            v[0] = r * sin(a);
            v[1] = r * cos(a);
            if (pass == 0) {
                meas += LD(wa);
                mu[0] += LD(wa) * LD(v[0]);
                mu[1] += LD(wa) * LD(v[1]);
            } else {
                ref_ld y0 = (ref_ld)v[0] - mu[0], y1 = (ref_ld)v[1] - mu[1];
                cv[0][0] += LD(wa) * y0 * y0;
                cv[0][1] += LD(wa) * y0 * y1;
                cv[1][1] += LD(wa) * y1 * y1;
            }
        }
        if (pass == 0) {
            mu[0] /= meas;
            mu[1] /= meas;
        }
    }
    cv[1][0] = cv[0][1];
    memset(cm, 0, sizeof cm); /* embedded in 3-D: third eigenvalue is 0 */
    for (j = 0; j < 2; ++j) {
        for (k = 0; k < 2; ++k) {
            cm[j][k] = (double)(cv[j][k] / meas);
        }
    }
    ref_sym3_eig(REF_C3(cm), w, ev);
    *lmin = w[1];
    *lmax = w[2];
}
