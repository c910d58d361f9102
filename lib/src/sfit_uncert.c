/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_uncert.c
 * @brief Centre covariance and radius variance of a sphere fit.
 *
 * Derivations (moments, samples, sandwich): docs/api.md#uncertainty.
 */
#include "sfit/sfit_uncert.h"

#include "sfit_moments_i.h"
#include "sfit_pass.h"

static sfit_status_t prv_finish(const sfit_mat3_t *cov, float radius_var, const float crc[3],
                                float noise_var, sfit_uncert_t *out)
{
    sfit_uncert_t u;
    float p[6];
    int i;
    sfit_i_sym_pack(cov, p); /* exactly symmetric: the mean of the two triangles */
    sfit_i_sym_unpack(p, &u.center_cov);
    u.radius_var = radius_var;
    u.noise_var = noise_var;
    for (i = 0; i < 3; i++) {
        u.center_radius_cov[i] = crc[i];
    }
    for (i = 0; i < 6; i++) {
        if (!sfit_i_isfinite(p[i])) {
            return SFIT_E_RANGE;
        }
    }
    if (!sfit_i_finite3(u.center_radius_cov) || !sfit_i_isfinite(radius_var)) {
        return SFIT_E_RANGE;
    }
    *out = u;
    return SFIT_OK;
}

/* Fit and noise level handed in: any NaN/Inf NONFINITE, else out of domain ARG. */
static sfit_status_t prv_check_fit(const sfit_vec3_t *center, float radius, float noise_var)
{
    sfit_status_t st;
    if (!sfit_i_isfinite(noise_var)) {
        return SFIT_E_NONFINITE;
    }
    st = sfit_i_check_fit(center, &radius);
    if (st != SFIT_OK) {
        return st;
    }
    return (noise_var < 0.0f) ? SFIT_E_ARG : SFIT_OK;
}

sfit_status_t sfit_uncert_moments(const sfit_moments_t *m, const sfit_vec3_t *center,
                                  float radius, float noise_var, sfit_uncert_noise_t kind,
                                  sfit_uncert_t *out)
{
    sfit_vec3_t mean, a, q;
    sfit_mat3_t c, l, k, kk, cov;
    float nf, n1, f1, f2, sgn, r2, crc[3];
    int i, j;
    sfit_status_t st;

    if (m == NULL || center == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    if (kind != SFIT_UNCERT_NOISE_KNOWN && kind != SFIT_UNCERT_NOISE_ESTIMATED) {
        return SFIT_E_ARG;
    }
    st = sfit_i_enough(prv_check_fit(center, radius, noise_var), m);
    if (st == SFIT_OK) {
        /* SFIT_E_RANGE for a corrupted accumulator (mean and C unwritten) */
        st = sfit_moments_stats(m, &mean, &c, NULL);
    }
    if (st != SFIT_OK) {
        return st;
    }
    for (i = 0; i < 3; i++) {
        c.m[4 * i] -= noise_var;
        a.v[i] = mean.v[i] - center->v[i];
    }
    if (sfit_mat3_chol(&c, &l) != SFIT_OK) {
        return SFIT_E_NOT_POSDEF;
    }
    sfit_i_chol_inverse(&l, &k);
    sfit_i_mat3_vec(&k, a.v, q.v);
    nf = (float)sfit_moments_count(m);
    n1 = nf - 1.0f;
    r2 = radius * radius;
    sgn = (kind == SFIT_UNCERT_NOISE_KNOWN) ? 1.0f : -1.0f;
    f1 = noise_var * (r2 + 7.5f * noise_var) / n1;
    f2 = (nf / n1) * (noise_var / n1) * noise_var;
    sfit_i_mat3_mul(&k, &k, &kk);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            cov.m[3 * i + j] = f1 * k.m[3 * i + j] + f2 * (r2 * kk.m[3 * i + j] + sgn * q.v[i] * q.v[j]);
        }
    }
    for (i = 0; i < 3; i++) {
        crc[i] = -noise_var * radius * q.v[i] / n1;
    }
    return prv_finish(&cov, noise_var * (1.0f / nf + sfit_i_dot3(a.v, q.v) / n1), crc, noise_var,
                      out);
}

/* Fewest samples: 4 sphere parameters plus one residual degree of freedom. */
#define PRV_GEO_MIN_N ((SFIT_MIN_SAMPLES > 5u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)5u)
/* Self-calibrated sandwich: the small-sample factor N/(N - 13) needs N > 13. */
#define PRV_SC_MIN_N ((SFIT_MIN_SAMPLES > 14u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)14u)

/* Pass 1 over the samples: sums of u (tot[0..2]), of d - d0 (tot[3], d0
 * the first distance) and, when k == 5, of (d - d0)^2 (tot[4]);
 * SFIT_E_DEGENERATE for a sample at c. */
static sfit_status_t prv_pass_dirs(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c,
                                   float *d0, int k, sfit_i_sum_t *s)
{
    sfit_i_rows_t q;
    sfit_i_rows_init(&q, SFIT_I_ROWS_DIRS, 0.0f, NULL, 0.0f);
    q.first = 1;
    if (!sfit_i_pass(pts, n, c->v, NULL, &q, k, s)) {
        return SFIT_E_DEGENERATE;
    }
    *d0 = q.ref;
    return SFIT_OK;
}

/* Pass 2 of the moments and geometric covariances (pass 1 saw no zero
 * distance): sfit_i_pass() rows SFIT_I_ROWS_CENTRED about ub and dbar. */
static void prv_pass_centred(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c,
                             const float ub[3], float dbar, int k, sfit_i_sum_t *s)
{
    sfit_i_rows_t q;
    sfit_i_rows_init(&q, SFIT_I_ROWS_CENTRED, 0.0f, ub, dbar);
    (void)sfit_i_pass(pts, n, c->v, NULL, &q, k, s);
}

/* After the checks of the fit (st): samples checked (at least nmin),
 * pass 1 done, ubar = mean direction. */
static sfit_status_t prv_start(sfit_status_t st, const sfit_vec3_t *pts, size_t n,
                               const sfit_vec3_t *c, size_t nmin, float *d0, sfit_i_sum_t *s,
                               float ub[3])
{
    int j;
    if (st == SFIT_OK) {
        st = sfit_i_check_points(pts, n, nmin);
    }
    if (st == SFIT_OK) {
        st = prv_pass_dirs(pts, n, c, d0, 4, s);
    }
    for (j = 0; j < 3 && st == SFIT_OK; j++) {
        ub[j] = s->tot[j] / (float)n;
    }
    return st;
}

sfit_status_t sfit_uncert_points(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                 float radius, float noise_var, sfit_uncert_t *out)
{
    sfit_i_sum_t s;
    sfit_mat3_t a, l, k;
    float ub[3], q[3], crc[3], d0 = 0.0f, nf;
    int j;
    sfit_status_t st;

    st = (pts == NULL || center == NULL || out == NULL) ? SFIT_E_ARG
                                                        : prv_check_fit(center, radius, noise_var);
    st = prv_start(st, pts, n, center, (size_t)SFIT_MIN_SAMPLES, &d0, &s, ub);
    if (st != SFIT_OK) {
        return st;
    }
    nf = (float)n;
    prv_pass_centred(pts, n, center, ub, d0, 6, &s);
    sfit_i_sym_unpack(s.tot, &a);
    if (sfit_mat3_chol(&a, &l) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    sfit_i_chol_inverse(&l, &k);
    sfit_i_mat3_vec(&k, ub, q);
    for (j = 0; j < 9; j++) {
        k.m[j] *= noise_var;
    }
    for (j = 0; j < 3; j++) {
        crc[j] = -noise_var * q[j];
    }
    return prv_finish(&k, noise_var * (1.0f / nf + sfit_i_dot3(ub, q)), crc, noise_var, out);
}

sfit_status_t sfit_uncert_geometric(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                    sfit_uncert_t *out)
{
    sfit_i_sum_t s;
    float ub[3], q[3], wq[3], crc[3], d0 = 0.0f, dbar, nf, s2;
    sfit_mat3_t mu, ap, l, k, w, cov;
    int j;
    sfit_status_t st;

    st = (pts == NULL || center == NULL || out == NULL) ? SFIT_E_ARG : sfit_i_check_fit(center, NULL);
    st = prv_start(st, pts, n, center, PRV_GEO_MIN_N, &d0, &s, ub);
    if (st != SFIT_OK) {
        return st;
    }
    nf = (float)n;
    dbar = d0 + s.tot[3] / nf;
    prv_pass_centred(pts, n, center, ub, dbar, 13, &s);
    s2 = s.tot[12] / (nf - 4.0f);
    if (!sfit_i_isfinite(s2)) {
        return SFIT_E_RANGE;
    }
    sfit_i_sym_unpack(&s.tot[0], &mu);
    if (sfit_mat3_chol(&mu, &l) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    for (j = 0; j < 6; j++) {
        s.tot[6 + j] += s.tot[j];
    }
    sfit_i_sym_unpack(&s.tot[6], &ap);
    if (sfit_mat3_chol(&ap, &l) != SFIT_OK) {
        /* The cost is not convex at this centre: not a minimum of the
         * geometric fit, or the noise swamps the curvature of the data. */
        return SFIT_E_NOT_POSDEF;
    }
    sfit_i_chol_inverse(&l, &k);
    sfit_i_mat3_mul(&k, &mu, &w);  /* W = K Mu */
    sfit_i_mat3_mul(&w, &k, &cov); /* Cov / s^2 = K Mu K */
    for (j = 0; j < 9; j++) {
        cov.m[j] *= s2;
    }
    sfit_i_mat3_vec(&k, ub, q);
    sfit_i_mat3_vec(&w, q, wq);
    for (j = 0; j < 3; j++) {
        crc[j] = -s2 * wq[j];
    }
    /* Var(r) = s^2 (1/N + ubar^T K Mu K ubar), K Mu K ubar = W q. */
    return prv_finish(&cov, s2 * (1.0f / nf + sfit_i_dot3(ub, wq)), crc, s2, out);
}

float sfit_i_cov_widen(float v, float r, size_t n)
{
    const float dof = (n > 14u) ? (float)(n - 4u) : 10.0f;
    return 1.0f + SFIT_I_COV_WIDEN_K * (v / (r * r)) * SFIT_SQRTF(96.0f / dof);
}

sfit_status_t sfit_uncert_selfcal(const sfit_vec3_t *pts, size_t n,
                                  const sfit_vec3_t *center, float radius,
                                  float noise_var, sfit_uncert_t *out)
{
    sfit_moments_t acc;
    sfit_i_sum_t s;
    sfit_vec3_t mean;
    sfit_mat3_t c, l, k, g, t, cov;
    sfit_i_rows_t q;
    float nf, rho, v, alpha, betap, d0 = 0.0f, kp[3], wk[3], w[3], den, crc[3];
    int i, j;
    sfit_status_t st;

    st = (pts == NULL || center == NULL || out == NULL) ? SFIT_E_ARG
                                                        : prv_check_fit(center, radius, noise_var);
    if (st == SFIT_OK) {
        st = sfit_i_check_points(pts, n, PRV_SC_MIN_N);
    }
    if (st == SFIT_OK) {
        st = prv_pass_dirs(pts, n, center, &d0, 5, &s);
    }
    if (st != SFIT_OK) {
        return st;
    }
    nf = (float)n;
    (void)sfit_i_moments_of(pts, n, &acc); /* validated above */
    (void)sfit_moments_stats(&acc, &mean, &c, NULL);
    v = noise_var;
    rho = radius * radius;
    sfit_i_rows_init(&q, SFIT_I_ROWS_SANDWICH, 0.0f, NULL, 0.0f);
    q.dbar = d0 + s.tot[3] / nf;
    q.mf2 = s.tot[4] / nf - (s.tot[3] / nf) * (s.tot[3] / nf);
    q.kv = ((nf - 1.0f) / nf) * v;
    alpha = -(nf - 4.0f) * (v / rho) * (v / rho);
    betap = -(nf - 4.0f) * (1.0f - 2.0f * v / rho) - 3.0f * ((nf - 1.0f) / nf) * alpha;
    q.alpha_n = alpha / nf;
    q.sv = ((nf - 4.0f) / nf) * (v - v * (v / rho));
    for (i = 0; i < 3; i++) {
        q.m[i] = mean.v[i];
        q.a[i] = mean.v[i] - center->v[i];
        q.p[i] = ((nf - 1.0f) / betap) * q.a[i];
        c.m[4 * i] -= v;
    }
    for (i = 0; i < 9; i++) {
        c.m[i] *= nf - 1.0f; /* M~ = (N-1)(C - sigma^2 I) */
    }
    if (!(betap < 0.0f) || sfit_mat3_chol(&c, &l) != SFIT_OK) {
        return SFIT_E_NOT_POSDEF;
    }
    sfit_i_chol_inverse(&l, &k);
    (void)sfit_i_pass(pts, n, center->v, NULL, &q, 9, &s); /* pass 1 saw no zero distance */
    /* G = M~ - p w'^T, w' = -2 sum f u - 2 alpha a; G^-1 by Sherman-Morrison */
    for (i = 0; i < 3; i++) {
        w[i] = -2.0f * s.tot[6 + i] - 2.0f * alpha * q.a[i];
    }
    sfit_i_mat3_vec(&k, q.p, kp);
    sfit_i_mat3_vec(&k, w, wk); /* K symmetric: w^T K = (K w)^T */
    den = 1.0f - sfit_i_dot3(w, kp);
    if (!(den > 0.0f)) {
        return SFIT_E_NOT_POSDEF;
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            g.m[3 * i + j] = k.m[3 * i + j] + kp[i] * wk[j] / den;
        }
    }
    sfit_i_sym_unpack(s.tot, &c); /* B = sum eta eta^T */
    sfit_i_mat3_mul(&g, &c, &t);
    for (i = 0; i < 3; i++) { /* g <- G^-T */
        for (j = i + 1; j < 3; j++) {
            const float x = g.m[3 * i + j];
            g.m[3 * i + j] = g.m[3 * j + i];
            g.m[3 * j + i] = x;
        }
    }
    sfit_i_mat3_mul(&t, &g, &cov);
    alpha = (nf / (nf - 13.0f)) * sfit_i_cov_widen(v, radius, n);
    for (i = 0; i < 9; i++) {
        /* N/(N - 5): 5 parameters fitted (c, r, sigma^2); (N - 5)/(N - 13):
         * B is as variable as a Wishart matrix of (N - 5)/2 degrees of
         * freedom, whose inverse has mean nu/(nu - 4) (docs/api.md#uncert);
         * then the widening by (sigma_hat / r)^2 of docs/coverage.md rule 7 */
        cov.m[i] *= alpha;
    }
    /* radius: first order, as sfit_uncert_moments (K = M~^-1) */
    sfit_i_mat3_vec(&k, q.a, kp);
    for (i = 0; i < 3; i++) {
        crc[i] = -v * radius * kp[i];
    }
    return prv_finish(&cov, v * (1.0f / nf + sfit_i_dot3(q.a, kp)), crc, v, out);
}
