/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_coverage.c
 * @brief Coverage design aids for caps and arcs (eq. 198-213).
 *
 * Implementation notes
 * --------------------
 * Coverage. Normalised (r = 1) eigenvalues, t = theta^2, s2 = sin^2(theta/2):
 *   cap axial      s2^2 / 3
 *   cap lateral    (3 - 2 s2) s2 / 3            (2 + cos theta = 3 - 2 s2)
 *   arc tangential 1/2 - sinc(2 theta)/2
 *                = sum_{k>=1} (-1)^(k+1) 4^k t^k / (2 (2k+1)!)
 *   arc radial     1/2 + sinc(2 theta)/2 - sinc(theta)^2
 *                = sum_{k>=2} (-1)^k (k-1) 4^k t^k / (2k+2)!
 * (the radial series: sinc^2(theta) = (1 - cos 2 theta)/(2 theta^2) =
 * sum_{k>=0} (-1)^k 4^(k+1) t^k / (2 (2k+2)!); subtracting it from
 * 1/2 + sinc(2 theta)/2 leaves (-1)^k 4^k t^k [1/(2k+1)! - 4/(2k+2)!] / 2 =
 * (-1)^k (k-1) 4^k t^k / (2k+2)!; the k = 0 and k = 1 terms vanish.) The
 * series need no trigonometric function and keep full relative precision
 * for small theta, where eq. 203 cancels theta^2-sized terms down to
 * theta^4/45. At theta = pi the largest term is ~6.5 for a result of 0.5,
 * so a few ulp are lost at most; 18 terms reach below 1e-10.
 *
 * Differences: tangential - radial = sin(theta) (sin theta - theta cos theta)
 * / theta^2 > 0 on (0, pi); lateral - axial = s2 (3 - 3 s2) / 3 =
 * s2 cos^2(theta/2) > 0 on (0, pi). Both vanish only at pi: the min / max
 * labels of eq. 203/204 and 210/211 hold for every theta, no crossover.
 *
 * Inverses bisect theta in [0, pi] on an increasing function g (axial /
 * radial eigenvalue, or the eigenvalue ratio), returning the upper end of
 * the final bracket (so g(theta) >= target up to rounding).
 */
#include "sfit/sfit_coverage.h"

#include <float.h>

#include "sfit_float.h"

#define PRV_PI_F 3.14159265f /* rounds to 3.14159274f, just above pi */
#define PRV_SIN_TERMS 8      /* Taylor terms of sin(x), x <= pi/2: error < 1e-11 */
#define PRV_ARC_TERMS 18     /* series terms of the arc eigenvalues at theta <= pi */

typedef enum prv_what { PRV_MIN = 0, PRV_RATIO = 1 } prv_what_t;

static int prv_kind_ok(sfit_coverage_kind_t kind)
{
    switch (kind) {
    case SFIT_COVERAGE_CAP:
    case SFIT_COVERAGE_ARC:
        return 1;
    default:
        return 0;
    }
}

/* sin(x) for 0 <= x <= pi/2 by its Taylor series in Horner form. */
static float prv_sin(float x)
{
    const float x2 = x * x;
    float acc = 1.0f;
    int k;
    /* sin x = x (1 - x^2/(2.3) (1 - x^2/(4.5) (1 - ...))) */
    for (k = PRV_SIN_TERMS; k >= 1; k--) {
        const float a = (float)(2 * k);
        acc = 1.0f - x2 / (a * (a + 1.0f)) * acc;
    }
    return x * acc;
}

/* Normalised cap eigenvalues (r = 1). */
static void prv_cap(float theta, float *ax, float *lat)
{
    const float s = prv_sin(0.5f * theta);
    const float s2 = s * s;
    *ax = s2 * s2 / 3.0f;
    *lat = (3.0f - 2.0f * s2) * s2 / 3.0f;
}

/* Normalised arc eigenvalues (r = 1): radial and tangential (series above). */
static void prv_arc(float theta, float *rad, float *tng)
{
    const float t4 = 4.0f * theta * theta;
    float p = -t4 / 24.0f; /* p_k = (-1)^k (4t)^k / (2k+2)!, here p_1 */
    float q = t4 / 12.0f;  /* q_k = (-1)^(k+1) (4t)^k / (2 (2k+1)!), here q_1 */
    float sr = 0.0f, st = q;
    int k;
    for (k = 2; k <= PRV_ARC_TERMS; k++) {
        const float a = (float)(2 * k);
        p = -p * t4 / ((a + 1.0f) * (a + 2.0f));
        q = -q * t4 / (a * (a + 1.0f));
        sr += (float)(k - 1) * p;
        st += q;
    }
    *rad = sr;
    *tng = st;
}

/* Normalised eigenvalues of either kind. */
static void prv_eigs(sfit_coverage_kind_t kind, float theta, float *lo, float *hi)
{
    if (kind == SFIT_COVERAGE_CAP) {
        prv_cap(theta, lo, hi);
    } else {
        prv_arc(theta, lo, hi);
    }
}

/* g(theta): the normalised smaller eigenvalue, or the eigenvalue ratio. */
static float prv_g(sfit_coverage_kind_t kind, prv_what_t what, float theta)
{
    float lo, hi;
    prv_eigs(kind, theta, &lo, &hi);
    if (what == PRV_MIN) {
        return lo;
    }
    return (hi > 0.0f) ? lo / hi : 0.0f;
}

/* Smallest theta in [0, pi] with g(theta) >= target (g increasing). */
static float prv_bisect(sfit_coverage_kind_t kind, prv_what_t what, float target)
{
    float lo = 0.0f, hi = PRV_PI_F;
    int i;
    if (!(target > 0.0f)) {
        return 0.0f;
    }
    for (i = 0; i < SFIT_COVERAGE_BISECT_ITERS; i++) {
        const float mid = 0.5f * (lo + hi);
        if (!(mid > lo && mid < hi)) {
            break;
        }
        if (prv_g(kind, what, mid) < target) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return hi;
}

static sfit_status_t prv_check_theta_r(sfit_coverage_kind_t kind, float theta, float r)
{
    if (!prv_kind_ok(kind)) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(theta) || !sfit_i_isfinite(r)) {
        return SFIT_E_NONFINITE;
    }
    if (!(theta > 0.0f) || theta > PRV_PI_F || !(r > 0.0f)) {
        return SFIT_E_ARG;
    }
    return SFIT_OK;
}

sfit_status_t sfit_coverage_eigs(sfit_coverage_kind_t kind, float theta, float r, float *lmin,
                                 float *lmax)
{
    float a, b, rr;
    sfit_status_t st;
    st = prv_check_theta_r(kind, theta, r);
    if (st != SFIT_OK) {
        return st;
    }
    prv_eigs(kind, theta, &a, &b);
    rr = r * r;
    a *= rr;
    b *= rr;
    if (!sfit_i_isfinite(a) || !sfit_i_isfinite(b)) {
        return SFIT_E_RANGE;
    }
    if (lmin != NULL) {
        *lmin = a;
    }
    if (lmax != NULL) {
        *lmax = b;
    }
    return SFIT_OK;
}

sfit_status_t sfit_coverage_cap_eigs(float theta, float r, float *lmin, float *lmax)
{
    return sfit_coverage_eigs(SFIT_COVERAGE_CAP, theta, r, lmin, lmax);
}

sfit_status_t sfit_coverage_arc_eigs(float theta, float r, float *lmin, float *lmax)
{
    return sfit_coverage_eigs(SFIT_COVERAGE_ARC, theta, r, lmin, lmax);
}

sfit_status_t sfit_coverage_max_sigma(sfit_coverage_kind_t kind, float theta, float r,
                                      float *sigma_max)
{
    float g;
    sfit_status_t st;
    st = (sigma_max == NULL) ? SFIT_E_ARG : prv_check_theta_r(kind, theta, r);
    if (st != SFIT_OK) {
        return st;
    }
    g = prv_g(kind, PRV_MIN, theta);
    /* r sqrt(g): no r^2, so any finite r > 0 gives a finite result. */
    *sigma_max = r * SFIT_SQRTF(g);
    return SFIT_OK;
}

sfit_status_t sfit_coverage_min_theta(sfit_coverage_kind_t kind, float sigma_over_r,
                                      float *theta)
{
    float target;
    if (theta == NULL || !prv_kind_ok(kind)) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(sigma_over_r)) {
        return SFIT_E_NONFINITE;
    }
    if (sigma_over_r < 0.0f) {
        return SFIT_E_ARG;
    }
    target = sigma_over_r * sigma_over_r;
    {
        /* At the full sphere / circle the limit itself is reachable: a
         * target within rounding (4 ulps) of g(pi) is answered with pi,
         * anything beyond is out of range. */
        const float gpi = prv_g(kind, PRV_MIN, PRV_PI_F);
        if (target > gpi * (1.0f + 4.0f * FLT_EPSILON)) {
            return SFIT_E_RANGE;
        }
        if (target >= gpi) {
            *theta = PRV_PI_F;
            return SFIT_OK;
        }
    }
    *theta = prv_bisect(kind, PRV_MIN, target);
    return SFIT_OK;
}

sfit_status_t sfit_coverage_estimate_theta(sfit_coverage_kind_t kind, const sfit_vec3_t *eig,
                                           float *theta)
{
    float num, den, q;
    if (eig == NULL || theta == NULL || !prv_kind_ok(kind)) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_finite3(eig->v)) {
        return SFIT_E_NONFINITE;
    }
    if (eig->v[0] > eig->v[1] || eig->v[1] > eig->v[2] || !(eig->v[2] > 0.0f)) {
        return SFIT_E_ARG;
    }
    if (kind == SFIT_COVERAGE_CAP) {
        num = eig->v[0];
        den = 0.5f * (eig->v[1] + eig->v[2]);
    } else {
        num = eig->v[1];
        den = eig->v[2];
    }
    if (!(num > 0.0f)) {
        return SFIT_E_DEGENERATE;
    }
    q = num / den;
    if (!(q > 0.0f)) {
        return SFIT_E_DEGENERATE; /* the ratio underflowed */
    }
    if (q >= 1.0f) {
        *theta = PRV_PI_F;
        return SFIT_OK;
    }
    *theta = prv_bisect(kind, PRV_RATIO, q);
    return SFIT_OK;
}
