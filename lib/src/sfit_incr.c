/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_incr.c
 * @brief Incremental GDKE / UGDK: a new centre after every sample (chapter 5.4).
 *
 * Implementation notes
 * --------------------
 * The chapter's recursion (eq. 224-232, re-derived in docs/incremental.md;
 * eq. 229 needs a minus sign) carries the running mean, C, C^-1 (by
 * Sherman-Morrison) and S, each as a running average. Written that way in
 * float it drifts: every update rounds C, C^-1 and S by about one ulp, the
 * errors add up like a random walk (relative error ~ eps sqrt(N)), and the
 * centre amplifies them by about cond(C) |c - m| / r. Measured against a
 * double batch fit (|c| = 2700 mm, r = 100 mm, 45 degree cap, shifted
 * frame): 2.8e-3 r after 10^6 samples. Propagating C^-1 is not the cause
 * (a running C with a fresh solve drifts as much); the summation is.
 *
 * What this file keeps instead (state sfit_incr_t, fixed size):
 *  - the mean as p + d, p a frame origin near the mean, d small;
 *    d += (z - d)/n with z = x - p computed directly from the sample
 *    (never d = n (m_{n+1} - m_n), which multiplies the rounding of the
 *    mean by n);
 *  - M2 = sum y y^T about the running mean, by Welford's rank-one update
 *    M2 += e delta^T, e = x - m_n, delta = x - m_{n+1} = e - e/n (the
 *    unscaled form of eq. 227);
 *  - instead of the centred third moment (whose recursion, eq. 230, needs
 *    M2 u every sample, 26 FLOPs), the raw sums about p:
 *    T = sum |z|^2 z and Q = sum |z|^2. From them the Kasa system about p
 *    is  M2 a = (T - Q d) / 2,  centre = p + a  (derivation below);
 *  - every sum in two levels: an inner sum (`_lo`) of at most
 *    SFIT_INCR_BLOCK samples and an outer sum it is folded into, so each
 *    rounding is relative to a partial sum of ~sqrt(N) terms, not N;
 *  - at each fold, p moves to the current mean and T, Q are re-expressed
 *    about it from the centred moments (exact identities), so d stays
 *    small and T - Q d never cancels badly even when the samples sweep
 *    across the sphere.
 * The estimate is then a 3x3 LDL^T solve (no square root) from the state,
 * done only when asked for. Result: within 1e-5 r of the double batch fit
 * at 10^6 samples in the same test, for 105 FLOPs per sample (GDKE, add +
 * solve) against the chapter's 123.
 *
 * Kasa system about p (z = x - p, mean of z = d, N samples): minimising
 * sum (|z|^2 - 2 a.z - k)^2 over a, k gives k = Q/N - 2 a.d and
 *   T - Q d = 2 (sum z z^T - N d d^T) a = 2 M2 a.
 * It is the batch GDKE c = m + C^-1 S / 2 rewritten, since the centred
 * third moment is M3 = sum |y|^2 y = T - Q d - 2 M2 d.
 * UGDK (eq. 171-176, 228): C' = C - Sigma, i.e. M2' = M2 - (N-1) Sigma, and
 * M2' w = M3 / 2 with w = c - m. Substituting M3 gives, for a = w + d,
 *   M2' a = (T - Q d)/2 - (N-1) Sigma d,
 * a 3x3 solve like GDKE's. C'^-1 could not have been carried by rank-one
 * updates anyway: C'_{n+1} = (n-1)/n C'_n - Sigma/n + rank one (eq. 228)
 * is a full-rank change.
 * Radius (eq. 232): r^2 = (N-1)/N tr C' + |w|^2 = tr M2' / N + |a - d|^2.
 *
 * FLOP tallies count every float add, sub, mul, div and sqrt executed (int
 * to float conversions and comparisons are not FLOPs); the per-line counts
 * are in brackets, the running total after the colon.
 */
#include "sfit/sfit_incr.h"

#include <float.h>

#include "sfit_solve.h"

/* Fold the inner level into the outer one and move the frame origin p to
 * the current mean. 82 FLOPs, once every SFIT_INCR_BLOCK samples (and
 * every n/8 samples while n < 8 SFIT_INCR_BLOCK). M2 is centred, so only
 * T, Q, p and d change. */
static void prv_fold(sfit_incr_t *s)
{
    float md[3], mdn[3], m3[3], pn[3], dlt[3], dn[3], tr, dd, qn;
    const float nf = (float)s->n;
    const float *m = s->m2;
    int i;

    for (i = 0; i < 6; i++) {
        s->m2[i] += s->m2_lo[i];                                   /* [6]    : 6 */
        s->m2_lo[i] = 0.0f;
    }
    for (i = 0; i < 3; i++) {
        s->t[i] += s->t_lo[i];                                     /* [3]    : 9 */
        s->t_lo[i] = 0.0f;
    }
    s->q += s->q_lo;                                               /* [1]    : 10 */
    s->q_lo = 0.0f;
    s->nb = 0u;

    /* New origin pn = p + d (rounded); dn = mean - pn, a rounding residue. */
    for (i = 0; i < 3; i++) {
        pn[i] = s->p[i] + s->d[i];                                 /* [3]    : 13 */
        dlt[i] = pn[i] - s->p[i];                                  /* [3]    : 16 */
        dn[i] = s->d[i] - dlt[i];                                  /* [3]    : 19 */
    }
    tr = m[0] + m[1] + m[2];                                       /* [2]    : 21 */
    /* Centred third moment M3 = T - Q d - 2 M2 d. */
    md[0] = m[0] * s->d[0] + m[3] * s->d[1] + m[4] * s->d[2];      /* [5]    : 26 */
    md[1] = m[3] * s->d[0] + m[1] * s->d[1] + m[5] * s->d[2];      /* [5]    : 31 */
    md[2] = m[4] * s->d[0] + m[5] * s->d[1] + m[2] * s->d[2];      /* [5]    : 36 */
    for (i = 0; i < 3; i++) {
        m3[i] = (s->t[i] - s->q * s->d[i]) - (md[i] + md[i]);      /* [4x3]  : 48 */
    }
    /* Raw sums about pn, z' = y + dn (sum y = 0):
     *   Q' = tr M2 + N |dn|^2,  T' = M3 + (2 M2 + tr M2) dn + N |dn|^2 dn. */
    mdn[0] = m[0] * dn[0] + m[3] * dn[1] + m[4] * dn[2];           /* [5]    : 53 */
    mdn[1] = m[3] * dn[0] + m[1] * dn[1] + m[5] * dn[2];           /* [5]    : 58 */
    mdn[2] = m[4] * dn[0] + m[5] * dn[1] + m[2] * dn[2];           /* [5]    : 63 */
    dd = dn[0] * dn[0] + dn[1] * dn[1] + dn[2] * dn[2];            /* [5]    : 68 */
    qn = tr + nf * dd;                                             /* [2]    : 70 */
    for (i = 0; i < 3; i++) {
        s->t[i] = m3[i] + (mdn[i] + mdn[i]) + qn * dn[i];          /* [4x3]  : 82 */
        s->p[i] = pn[i];
        s->d[i] = dn[i];
    }
    s->q = qn;
}

/* Add one validated sample. 40 FLOPs (plus a fold when one is due). */
static void prv_add(sfit_incr_t *s, const float x[3])
{
    float z0, z1, z2, e0, e1, e2, u0, u1, u2, h0, h1, h2, q, inv;

    if (s->n == 0u) {
        memcpy(s->p, x, sizeof s->p); /* first frame origin: the first sample */
    }
    z0 = x[0] - s->p[0];                                           /* [1]    : 1 */
    z1 = x[1] - s->p[1];                                           /* [1]    : 2 */
    z2 = x[2] - s->p[2];                                           /* [1]    : 3 */
    e0 = z0 - s->d[0];               /* e = x - m_n */             /* [1]    : 4 */
    e1 = z1 - s->d[1];                                             /* [1]    : 5 */
    e2 = z2 - s->d[2];                                             /* [1]    : 6 */
    s->n++;
    inv = 1.0f / (float)s->n;                                      /* [1]    : 7 */
    s->inv_n = inv;
    u0 = e0 * inv;                   /* u = m_{n+1} - m_n (eq. 224) */ /* [1] : 8 */
    u1 = e1 * inv;                                                 /* [1]    : 9 */
    u2 = e2 * inv;                                                 /* [1]    : 10 */
    s->d[0] += u0;                                                 /* [1]    : 11 */
    s->d[1] += u1;                                                 /* [1]    : 12 */
    s->d[2] += u2;                                                 /* [1]    : 13 */
    h0 = e0 - u0;                    /* delta = x - m_{n+1} (eq. 225) */ /* [1] : 14 */
    h1 = e1 - u1;                                                  /* [1]    : 15 */
    h2 = e2 - u2;                                                  /* [1]    : 16 */
    /* M2 += e delta^T = (n/(n+1)) e e^T (symmetric; eq. 227 unscaled). */
    s->m2_lo[0] += e0 * h0;                                        /* [2]    : 18 */
    s->m2_lo[1] += e1 * h1;                                        /* [2]    : 20 */
    s->m2_lo[2] += e2 * h2;                                        /* [2]    : 22 */
    s->m2_lo[3] += e0 * h1;                                        /* [2]    : 24 */
    s->m2_lo[4] += e0 * h2;                                        /* [2]    : 26 */
    s->m2_lo[5] += e1 * h2;                                        /* [2]    : 28 */
    q = z0 * z0 + z1 * z1 + z2 * z2;                               /* [5]    : 33 */
    s->t_lo[0] += q * z0;                                          /* [2]    : 35 */
    s->t_lo[1] += q * z1;                                          /* [2]    : 37 */
    s->t_lo[2] += q * z2;                                          /* [2]    : 39 */
    s->q_lo += q;                                                  /* [1]    : 40 */
    s->nb++;
    /* Fold when the inner level holds n/8 samples (often while n is small
     * and the mean still moves fast) or SFIT_INCR_BLOCK samples. */
    if (s->nb >= SFIT_INCR_BLOCK || 8u * s->nb >= s->n) {
        prv_fold(s);
    }
}

const sfit_incr_cfg_t sfit_incr_cfg_default = {.noise = SFIT_NOISE_NONE, .noise_var = 0.0f};

sfit_status_t sfit_incr_init(sfit_incr_t *s, const sfit_incr_cfg_t *cfg)
{
    sfit_mat3_t sg;

    cfg = (cfg != NULL) ? cfg : &sfit_incr_cfg_default;
    if (s == NULL || sfit_i_check_noise(cfg->noise, cfg->noise_var, &cfg->noise_cov) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    sfit_i_sigma(cfg->noise, cfg->noise_var, &cfg->noise_cov, &sg);
    memset(s, 0, sizeof *s);
    s->noise = cfg->noise;
    sfit_i_sym_pack(&sg, s->sig);
    s->sig_tr = sg.m[0] + sg.m[4] + sg.m[8];
    return SFIT_OK;
}

sfit_status_t sfit_incr_reset(sfit_incr_t *s)
{
    sfit_noise_kind_t kind;
    float sig[6], tr;

    if (s == NULL) {
        return SFIT_E_ARG;
    }
    kind = s->noise;
    memcpy(sig, s->sig, sizeof sig);
    tr = s->sig_tr;
    memset(s, 0, sizeof *s);
    s->noise = kind;
    memcpy(s->sig, sig, sizeof sig);
    s->sig_tr = tr;
    return SFIT_OK;
}

uint32_t sfit_incr_count(const sfit_incr_t *s)
{
    return (s == NULL) ? 0u : s->n;
}

sfit_status_t sfit_incr_add(sfit_incr_t *s, const sfit_vec3_t *x)
{
    const sfit_status_t st = sfit_i_check_add(s, x);
    if (st == SFIT_OK && s->n == UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    if (st == SFIT_OK) {
        prv_add(s, x->v);
    }
    return st;
}

/* The state's noise model as a fit configuration (sphere mode). */
static void prv_cfg(const sfit_incr_t *s, sfit_fit_cfg_t *cfg)
{
    *cfg = sfit_fit_cfg_default;
    cfg->mode = SFIT_MODE_SPHERE;
    cfg->noise = s->noise;
    cfg->noise_var = s->sig[0];
    sfit_i_sym_unpack(s->sig, &cfg->noise_cov);
}

sfit_status_t sfit_incr_start(sfit_incr_t *s, const sfit_vec3_t *pts, size_t n,
                              sfit_sphere_t *out)
{
    sfit_moments_t acc;
    sfit_fit_cfg_t cfg;
    sfit_result_t batch;
    sfit_incr_t tmp;
    sfit_sphere_t est;
    sfit_status_t st;
    size_t i;

    if (s == NULL || (pts == NULL && n > 0u)) {
        return SFIT_E_ARG;
    }
    st = sfit_i_check_points(pts, n, (size_t)SFIT_MIN_SAMPLES);
    if (st != SFIT_OK) {
        return st;
    }
    /* The batch fit decides whether the start is usable (eigenvalue checks:
     * coincident, collinear, planar; C' positive definite). */
    (void)sfit_i_moments_of(pts, n, &acc); /* validated above */
    /* Geometry first (GDKE), so that a planar set is reported as
     * degenerate whatever the noise model; then the state's own model. */
    prv_cfg(s, &cfg);
    cfg.noise = SFIT_NOISE_NONE;
    st = sfit_fit_moments(&acc, &cfg, &batch);
    /* The check with the noise model, where the build's fit serves it (a
     * build without the full solver serves no full covariance): else
     * C' = C - Sigma is checked by the LDL^T of sfit_incr_fit() below
     * (SFIT_E_NOT_POSDEF). */
    if (st == SFIT_OK && s->noise != SFIT_NOISE_NONE && sfit_i_solve_serves(s->noise)) {
        prv_cfg(s, &cfg);
        st = sfit_fit_moments(&acc, &cfg, &batch);
    }
    if (st != SFIT_OK) {
        return st;
    }
    /* Build the new state aside; commit only when it solves too. */
    memcpy(&tmp, s, sizeof tmp);
    (void)sfit_incr_reset(&tmp);
    for (i = 0; i < n; i++) {
        prv_add(&tmp, pts[i].v);
    }
    st = sfit_incr_fit(&tmp, &est);
    if (st != SFIT_OK) {
        return st;
    }
    memcpy(s, &tmp, sizeof *s);
    if (out != NULL) {
        *out = est;
    }
    return SFIT_OK;
}

/* Why an LDL^T pivot of M2 - (N-1) Sigma failed: the samples themselves
 * (M2 singular: degenerate) or the noise model (not positive definite).
 * Off the counted path: runs only on failure. */
static sfit_status_t prv_why_singular(const sfit_incr_t *s, float tol)
{
    float m[6], l10, l20, d1, t, d2;
    int i;
    if (s->noise == SFIT_NOISE_NONE) {
        return SFIT_E_DEGENERATE;
    }
    for (i = 0; i < 6; i++) {
        m[i] = s->m2[i] + s->m2_lo[i];
    }
    if (!(m[0] > tol)) {
        return SFIT_E_DEGENERATE;
    }
    l10 = m[3] / m[0];
    l20 = m[4] / m[0];
    d1 = m[1] - l10 * m[3];
    t = m[5] - l20 * m[3];
    if (!(d1 > tol)) {
        return SFIT_E_DEGENERATE;
    }
    d2 = m[2] - l20 * m[4] - (t / d1) * t;
    return (d2 > tol) ? SFIT_E_NOT_POSDEF : SFIT_E_DEGENERATE;
}

/* Tally: 65 FLOPs for GDKE (6 div, 1 sqrt); UGDK isotropic +6 = 71;
 * UGDK full covariance +33 = 98 (the "iso +" / "cov +" lines). Measured
 * identical on the Cortex-M4F by tools/flopcount (docs/incremental.md). */
sfit_status_t sfit_incr_fit(const sfit_incr_t *s, sfit_sphere_t *out)
{
    float m[6], t[3], q, b[3], a[3], w[3];
    float dmax, amax, sc, tol, nm1, l10, l20, l21, d1, d2, tt, y1, y2, z0, z1, z2;
    float tr, r2;
    sfit_sphere_t r;
    int i;

    if (s == NULL || out == NULL || s->n < SFIT_MIN_SAMPLES) {
        return (s == NULL || out == NULL) ? SFIT_E_ARG : SFIT_E_TOO_FEW;
    }
    nm1 = (float)(s->n - 1u);
    for (i = 0; i < 6; i++) {
        m[i] = s->m2[i] + s->m2_lo[i];                             /* [6]    : 6 */
    }
    for (i = 0; i < 3; i++) {
        t[i] = s->t[i] + s->t_lo[i];                               /* [3]    : 9 */
    }
    q = s->q + s->q_lo;                                            /* [1]    : 10 */

    /* Geometry: coincident when the largest per-axis spread is rounding
     * noise of the coordinates (as sfit_fit_moments, SFIT_COINCIDENT_ULPS)
     * or below SFIT_MIN_SPREAD;
     * coincident, collinear or planar also when an LDL^T pivot is
     * <= SFIT_CHOL_PIVOT_EPS * the largest diagonal entry (below). */
    dmax = m[0];
    if (m[1] > dmax) { dmax = m[1]; }
    if (m[2] > dmax) { dmax = m[2]; }
    amax = SFIT_FABSF(s->p[0]);
    if (SFIT_FABSF(s->p[1]) > amax) { amax = SFIT_FABSF(s->p[1]); }
    if (SFIT_FABSF(s->p[2]) > amax) { amax = SFIT_FABSF(s->p[2]); }
    sc = (SFIT_COINCIDENT_ULPS * FLT_EPSILON) * amax;               /* [1]    : 11 */
    if (sc < SFIT_MIN_SPREAD) {
        /* a spread too small for float (as sfit_fit_moments): the third
         * moments' cubes lose their digits and the centre is silently off */
        sc = SFIT_MIN_SPREAD;
    }
    if (!(dmax > nm1 * (sc * sc)) || !sfit_i_isfinite(dmax)) {      /* [2]    : 13 */
        return SFIT_E_DEGENERATE;
    }
    tol = SFIT_CHOL_PIVOT_EPS * dmax;                               /* [1]    : 14 */

    /* UGDK: M2' = M2 - (N-1) Sigma and the right-hand side term
     * -2 (N-1) Sigma d (folded into the factor of d for isotropic noise). */
    if (s->noise == SFIT_NOISE_ISO) {
        const float k = nm1 * s->sig[0];                            /* [1]  iso +1 */
        const float qk = q + (k + k);                               /* [2]  iso +3 */
        m[0] -= k;                                                  /* [1]  iso +4 */
        m[1] -= k;                                                  /* [1]  iso +5 */
        m[2] -= k;                                                  /* [1]  iso +6 */
        for (i = 0; i < 3; i++) {
            b[i] = t[i] - qk * s->d[i];                             /* [2x3]   : 20 */
        }
    } else if (s->noise == SFIT_NOISE_COV) {
        float g[6], v[3];
        for (i = 0; i < 6; i++) {
            g[i] = nm1 * s->sig[i];                                 /* [6]  cov +6 */
            m[i] -= g[i];                                           /* [6]  cov +12 */
        }
        v[0] = g[0] * s->d[0] + g[3] * s->d[1] + g[4] * s->d[2];    /* [5]  cov +17 */
        v[1] = g[3] * s->d[0] + g[1] * s->d[1] + g[5] * s->d[2];    /* [5]  cov +22 */
        v[2] = g[4] * s->d[0] + g[5] * s->d[1] + g[2] * s->d[2];    /* [5]  cov +27 */
        for (i = 0; i < 3; i++) {
            b[i] = (t[i] - q * s->d[i]) - (v[i] + v[i]);            /* [2x3]   : 20, cov +6 */
        }
    } else {
        for (i = 0; i < 3; i++) {
            b[i] = t[i] - q * s->d[i];                              /* [2x3]   : 20 */
        }
    }

    /* LDL^T of m (packed XX,YY,ZZ,XY,XZ,YZ): D0 = m0, D1, D2 pivots. */
    if (!(m[0] > tol)) {
        return prv_why_singular(s, tol);
    }
    l10 = m[3] / m[0];                                              /* [1]    : 21 */
    l20 = m[4] / m[0];                                              /* [1]    : 22 */
    d1 = m[1] - l10 * m[3];                                         /* [2]    : 24 */
    if (!(d1 > tol)) {
        return prv_why_singular(s, tol);
    }
    tt = m[5] - l20 * m[3];                                         /* [2]    : 26 */
    l21 = tt / d1;                                                  /* [1]    : 27 */
    d2 = m[2] - l20 * m[4] - l21 * tt;                              /* [4]    : 31 */
    if (!(d2 > tol)) {
        return prv_why_singular(s, tol);
    }
    /* Solve m a = b / 2: forward (L), diagonal (D, with the 1/2), back (L^T). */
    y1 = b[1] - l10 * b[0];                                         /* [2]    : 33 */
    y2 = b[2] - l20 * b[0] - l21 * y1;                              /* [4]    : 37 */
    z0 = b[0] / m[0];                                               /* [1]    : 38 */
    z1 = y1 / d1;                                                   /* [1]    : 39 */
    z2 = y2 / d2;                                                   /* [1]    : 40 */
    z1 = z1 - l21 * z2;                                             /* [2]    : 42 */
    z0 = z0 - l10 * z1 - l20 * z2;                                  /* [4]    : 46 */
    a[0] = 0.5f * z0;                                               /* [1]    : 47 */
    a[1] = 0.5f * z1;                                               /* [1]    : 48 */
    a[2] = 0.5f * z2;                                               /* [1]    : 49 */

    for (i = 0; i < 3; i++) {
        r.center.v[i] = s->p[i] + a[i];                             /* [3]    : 52 */
        w[i] = a[i] - s->d[i];                                      /* [3]    : 55 */
    }
    tr = m[0] + m[1] + m[2];                                        /* [2]    : 57 */
    r2 = tr * s->inv_n + (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]); /* [7]    : 64 */
    if (!(r2 > 0.0f)) {
        return SFIT_E_NOT_POSDEF;
    }
    r.radius = SFIT_SQRTF(r2);                                      /* [1]    : 65 */
    r.n = s->n;
    if (!sfit_i_sphere_finite(&r.center, r.radius)) {
        return SFIT_E_RANGE;
    }
    *out = r;
    return SFIT_OK;
}

sfit_status_t sfit_incr_update(sfit_incr_t *s, const sfit_vec3_t *x, sfit_sphere_t *out)
{
    sfit_status_t st;
    if (out == NULL) {
        return SFIT_E_ARG;
    }
    st = sfit_incr_add(s, x);
    if (st != SFIT_OK) {
        return st;
    }
    return sfit_incr_fit(s, out);
}
