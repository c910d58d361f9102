/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_fit.c
 * @brief GDKE / UGDK sphere and planar (circle) solutions from moments.
 *
 * Implementation notes
 * --------------------
 * With M2 = sum y y^T and M3 = sum |y|^2 y (centred, from the accumulator),
 * C = M2/(N-1) and S = M3/(N-1), the Kasa normal equations give the centre
 * offset from the mean w = C'^-1 S / 2, with C' = C - Sigma_hat (Sigma_hat = 0
 * for GDKE), and r^2 = (N-1)/N tr C' + |w|^2. The centre is assembled as
 * origin + (d + w), d the mean's offset from the accumulator's origin, so
 * the large coordinate is added once, at the end.
 *
 * The eigenvalues of C are always computed (Jacobi): they are reported, they
 * detect coincident / collinear / near-planar samples, and in planar mode
 * the pseudo-inverse uses the two largest eigen-directions of C' (eq. 217).
 *
 * Trust: two spectral radii are reported.
 *  - leontief_ratio nu = rho(C'^-1 Sigma): the Leontief condition of eq. 194
 *    is rho(C0^-1 Sigma) < 1, C0 the noise-free covariance, which C'
 *    estimates without bias (eq. 173). Computed as the largest eigenvalue of
 *    L^-1 Sigma L^-T with C' = L L^T (a symmetric 3x3 eigenproblem; in
 *    planar mode a 2x2 one over the kept directions).
 *  - trust_ratio mu = rho(C^-1 Sigma) with the measured C (eq. 193 as the
 *    issue tracker names it). The generalised eigenvalues are linked by
 *    Sigma v = nu (C - Sigma) v  <=>  Sigma v = nu/(1+nu) C v, so
 *    mu = nu / (1 + nu) exactly. mu is GDKE's shrinkage of the centre
 *    offset along the weakest direction (E C = C0 + Sigma), which is why
 *    GDKE's bias on a cap is mu |c - m| (DESIGN.md section 2). nu >= 1
 *    (mu >= 1/2) raises SFIT_FLAG_UNTRUSTED.
 */
#include "sfit/sfit_fit.h"

#include <float.h>
#include <string.h>

#include "sfit/sfit_mat3.h"
#include "sfit_internal.h"

const sfit_fit_cfg_t sfit_fit_cfg_default = {
    SFIT_MODE_AUTO, SFIT_NOISE_NONE, 0.0f, {{0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}},
    0.0f};

sfit_status_t sfit_i_check_cfg(const sfit_fit_cfg_t *cfg)
{
    int i;
    switch (cfg->mode) {
    case SFIT_MODE_AUTO:
    case SFIT_MODE_SPHERE:
    case SFIT_MODE_PLANAR:
        break;
    default:
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(cfg->planar_ratio) || cfg->planar_ratio < 0.0f
        || cfg->planar_ratio >= 1.0f) {
        return SFIT_E_ARG;
    }
    switch (cfg->noise) {
    case SFIT_NOISE_NONE:
        break;
    case SFIT_NOISE_ISO:
        if (!sfit_i_isfinite(cfg->noise_var) || cfg->noise_var < 0.0f) {
            return SFIT_E_ARG;
        }
        break;
    case SFIT_NOISE_COV:
        for (i = 0; i < 9; i++) {
            if (!sfit_i_isfinite(cfg->noise_cov.m[i])) {
                return SFIT_E_ARG;
            }
        }
        {
            /* Positive semi-definite, necessary conditions: non-negative
             * diagonal and every 2x2 principal minor >= 0 (lower triangle). */
            const float *c = cfg->noise_cov.m;
            if (c[0] < 0.0f || c[4] < 0.0f || c[8] < 0.0f || c[3] * c[3] > c[0] * c[4]
                || c[6] * c[6] > c[0] * c[8] || c[7] * c[7] > c[4] * c[8]) {
                return SFIT_E_ARG;
            }
        }
        break;
    default:
        return SFIT_E_ARG;
    }
    return SFIT_OK;
}

/* Sigma_hat as a full symmetric matrix (lower triangle of the option). */
void sfit_i_sigma(const sfit_fit_cfg_t *cfg, sfit_mat3_t *sg)
{
    memset(sg, 0, sizeof *sg);
    if (cfg->noise == SFIT_NOISE_ISO) {
        sg->m[0] = cfg->noise_var;
        sg->m[4] = cfg->noise_var;
        sg->m[8] = cfg->noise_var;
    } else if (cfg->noise == SFIT_NOISE_COV) {
        const float *s = cfg->noise_cov.m;
        const float p[6] = {s[0], s[4], s[8], s[3], s[6], s[7]};
        sfit_i_sym_unpack(p, sg);
    } else {
        /* SFIT_NOISE_NONE: zero */
    }
}

/* Column k of V as a vector, sign chosen so the largest component is > 0. */
static void prv_axis(const sfit_mat3_t *v, int k, sfit_vec3_t *ax)
{
    int i, imax = 0;
    float big = -1.0f, sgn;
    for (i = 0; i < 3; i++) {
        const float a = SFIT_FABSF(v->m[3 * i + k]);
        if (a > big) {
            big = a;
            imax = i;
        }
    }
    sgn = (v->m[3 * imax + k] < 0.0f) ? -1.0f : 1.0f;
    for (i = 0; i < 3; i++) {
        ax->v[i] = sgn * v->m[3 * i + k];
    }
}

/* rho(L^-1 Sigma L^-T) for C' = L L^T. */
static sfit_status_t prv_trust_chol(const sfit_mat3_t *l, const sfit_mat3_t *sg, float *rho)
{
    sfit_mat3_t b;
    sfit_vec3_t col, x, w;
    float X[9];
    int i, j;
    sfit_status_t st;

    /* X = L^-1 Sigma, column by column (forward substitution). */
    for (j = 0; j < 3; j++) {
        const float *L = l->m;
        col.v[0] = sg->m[j];
        col.v[1] = sg->m[3 + j];
        col.v[2] = sg->m[6 + j];
        x.v[0] = col.v[0] / L[0];
        x.v[1] = (col.v[1] - L[3] * x.v[0]) / L[4];
        x.v[2] = (col.v[2] - L[6] * x.v[0] - L[7] * x.v[1]) / L[8];
        X[j] = x.v[0];
        X[3 + j] = x.v[1];
        X[6 + j] = x.v[2];
    }
    /* B = L^-1 X^T (= L^-1 Sigma L^-T since Sigma is symmetric). */
    for (j = 0; j < 3; j++) {
        const float *L = l->m;
        float y0, y1, y2;
        y0 = X[3 * j] / L[0];
        y1 = (X[3 * j + 1] - L[3] * y0) / L[4];
        y2 = (X[3 * j + 2] - L[6] * y0 - L[7] * y1) / L[8];
        b.m[j] = y0;
        b.m[3 + j] = y1;
        b.m[6 + j] = y2;
    }
    st = sfit_mat3_eig_sym(&b, &w, NULL);
    if (st != SFIT_OK) {
        return st;
    }
    *rho = 0.0f;
    for (i = 0; i < 3; i++) {
        const float a = SFIT_FABSF(w.v[i]);
        if (a > *rho) {
            *rho = a;
        }
    }
    return SFIT_OK;
}

static float prv_dot(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

sfit_status_t sfit_i_solve(const sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                           sfit_i_solution_t *out)
{
    const sfit_mat3_t *sg = &sys->sigma;
    sfit_mat3_t cp, vec, vecp, l;
    sfit_vec3_t lam, lamp;
    sfit_i_solution_t r;
    float ratio, rho = 0.0f;
    int i, planar;
    sfit_status_t st;

    st = sfit_mat3_eig_sym(&sys->c, &lam, &vec);
    if (st != SFIT_OK) {
        return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
    }
    /* Geometry checks on the eigenvalues of C. */
    if (!(lam.v[2] > FLT_MIN) || lam.v[2] <= sys->scale * sys->scale) {
        return SFIT_E_DEGENERATE; /* coincident */
    }
    if (lam.v[1] <= SFIT_COLLINEAR_RATIO * lam.v[2]) {
        return SFIT_E_DEGENERATE; /* collinear */
    }
    ratio = (planar_ratio > 0.0f) ? planar_ratio : SFIT_PLANAR_RATIO;

    memset(&r, 0, sizeof r);
    r.eigenvalues = lam;
    if (lam.v[0] < ratio * lam.v[2]) {
        r.flags |= (uint32_t)SFIT_FLAG_NEAR_PLANAR;
    }
    planar = (mode == SFIT_MODE_PLANAR)
             || (mode == SFIT_MODE_AUTO && (r.flags & (uint32_t)SFIT_FLAG_NEAR_PLANAR) != 0u);
    for (i = 0; i < 9; i++) {
        cp.m[i] = sys->c.m[i] - sg->m[i];
    }

    if (!planar) {
        /* Sphere: Cholesky of C' = C - Sigma_hat, w = C'^-1 b. */
        st = sfit_mat3_chol(&cp, &l);
        if (st != SFIT_OK) {
            return sys->noisy ? SFIT_E_NOT_POSDEF : SFIT_E_DEGENERATE;
        }
        (void)sfit_mat3_chol_solve(&l, &sys->rhs, &r.w);
        r.trace = cp.m[0] + cp.m[4] + cp.m[8];
        if (sys->noisy) {
            st = prv_trust_chol(&l, sg, &rho);
            if (st != SFIT_OK) {
                return st;
            }
        }
        prv_axis(&vec, 0, &r.axis);
        r.mode = SFIT_MODE_SPHERE;
    } else {
        /* Planar (eq. 217): pseudo-inverse over the two largest
         * eigen-directions of C'. With no noise model, or isotropic noise,
         * C' has C's eigenvectors and eigenvalues shifted by sigma^2. */
        float v1[3], v2[3], k0, k1;
        if (sys->noisy && !(sg->m[1] == 0.0f && sg->m[2] == 0.0f && sg->m[5] == 0.0f
                            && sg->m[0] == sg->m[4] && sg->m[0] == sg->m[8])) {
            st = sfit_mat3_eig_sym(&cp, &lamp, &vecp);
            if (st != SFIT_OK) {
                return st;
            }
        } else {
            vecp = vec;
            for (i = 0; i < 3; i++) {
                lamp.v[i] = lam.v[i] - sg->m[0];
            }
        }
        if (!(lamp.v[1] > SFIT_CHOL_PIVOT_EPS * lamp.v[2])) {
            return sys->noisy ? SFIT_E_NOT_POSDEF : SFIT_E_DEGENERATE;
        }
        for (i = 0; i < 3; i++) {
            v1[i] = vecp.m[3 * i + 1];
            v2[i] = vecp.m[3 * i + 2];
        }
        k0 = prv_dot(v1, sys->rhs.v) / lamp.v[1];
        k1 = prv_dot(v2, sys->rhs.v) / lamp.v[2];
        for (i = 0; i < 3; i++) {
            r.w.v[i] = k0 * v1[i] + k1 * v2[i];
        }
        r.trace = lamp.v[1] + lamp.v[2];
        if (sys->noisy) {
            /* Trust on the kept plane: largest eigenvalue of the 2x2
             * B_ij = v_i^T Sigma v_j / sqrt(lambda_i lambda_j). */
            float sv1[3], sv2[3], b00, b01, b11, h;
            for (i = 0; i < 3; i++) {
                sv1[i] = prv_dot(&sg->m[3 * i], v1);
                sv2[i] = prv_dot(&sg->m[3 * i], v2);
            }
            b00 = prv_dot(v1, sv1) / lamp.v[1];
            b11 = prv_dot(v2, sv2) / lamp.v[2];
            b01 = prv_dot(v1, sv2) / SFIT_SQRTF(lamp.v[1] * lamp.v[2]);
            /* Spectral radius of the symmetric 2x2: |mean| + half-gap. */
            h = 0.5f * (b00 - b11);
            rho = 0.5f * SFIT_FABSF(b00 + b11) + SFIT_SQRTF(h * h + b01 * b01);
        }
        prv_axis(&vecp, 0, &r.axis);
        r.mode = SFIT_MODE_PLANAR;
    }
    r.rho = rho;
    if (rho >= 1.0f) {
        r.flags |= (uint32_t)SFIT_FLAG_UNTRUSTED;
    }
    for (i = 0; i < 3; i++) {
        if (!sfit_i_isfinite(r.w.v[i])) {
            return SFIT_E_RANGE;
        }
    }
    if (!sfit_i_isfinite(r.rho) || !sfit_i_isfinite(r.trace)) {
        return SFIT_E_RANGE;
    }
    *out = r;
    return SFIT_OK;
}

float sfit_i_coincident_scale(const float origin[3], const float d[3])
{
    float scale = 0.0f;
    int i;
    for (i = 0; i < 3; i++) {
        const float a = SFIT_FABSF(origin[i] + d[i]);
        if (a > scale) {
            scale = a;
        }
    }
    return scale * (SFIT_COINCIDENT_ULPS * FLT_EPSILON);
}

sfit_status_t sfit_fit_solve(const sfit_moments_t *m, const sfit_fit_cfg_t *cfg,
                             sfit_result_t *out)
{
    sfit_cmom_t t;
    sfit_i_system_t sys;
    sfit_i_solution_t sol;
    sfit_result_t r;
    float inv, r2;
    int i;
    sfit_status_t st;

    if (m == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    if (cfg == NULL) {
        cfg = &sfit_fit_cfg_default;
    }
    st = sfit_i_check_cfg(cfg);
    if (st != SFIT_OK) {
        return st;
    }
    if (sfit_moments_count(m) < SFIT_MIN_SAMPLES) {
        return SFIT_E_TOO_FEW;
    }
    sfit_i_moments_total(m, &t);
    /* C = M2/(N-1); b = S/2 = M3/(2(N-1)). */
    inv = 1.0f / (float)(t.n - 1u);
    {
        float p[6];
        for (i = 0; i < 6; i++) {
            p[i] = t.m2[i] * inv;
        }
        sfit_i_sym_unpack(p, &sys.c);
    }
    for (i = 0; i < 3; i++) {
        sys.rhs.v[i] = (0.5f * inv) * t.m3[i];
    }
    sfit_i_sigma(cfg, &sys.sigma);
    sys.noisy = (cfg->noise != SFIT_NOISE_NONE);
    sys.scale = sfit_i_coincident_scale(m->origin, t.d);

    st = sfit_i_solve(&sys, cfg->mode, cfg->planar_ratio, &sol);
    if (st != SFIT_OK) {
        return st;
    }
    /* r^2 = (N-1)/N tr C' (over the directions used) + |w|^2 (eq. 176/218). */
    r2 = ((float)(t.n - 1u) / (float)t.n) * sol.trace + prv_dot(sol.w.v, sol.w.v);
    if (!(r2 > 0.0f)) {
        return SFIT_E_NOT_POSDEF;
    }
    memset(&r, 0, sizeof r);
    r.radius = SFIT_SQRTF(r2);
    for (i = 0; i < 3; i++) {
        r.center.v[i] = m->origin[i] + (t.d[i] + sol.w.v[i]);
        if (!sfit_i_isfinite(r.center.v[i])) {
            return SFIT_E_RANGE;
        }
    }
    if (!sfit_i_isfinite(r.radius)) {
        return SFIT_E_RANGE;
    }
    r.n = t.n;
    r.eigenvalues = sol.eigenvalues;
    r.axis = sol.axis;
    r.leontief_ratio = sol.rho;
    r.trust_ratio = sol.rho / (1.0f + sol.rho);
    r.flags = sol.flags;
    if (t.n < SFIT_FEW_SAMPLES) {
        r.flags |= (uint32_t)SFIT_FLAG_FEW_SAMPLES;
    }
    r.method = sys.noisy ? SFIT_METHOD_UGDK : SFIT_METHOD_GDKE;
    r.mode = sol.mode;
    *out = r;
    return SFIT_OK;
}

sfit_status_t sfit_fit_batch(const sfit_vec3_t *pts, size_t n, const sfit_fit_cfg_t *cfg,
                             sfit_result_t *out)
{
    sfit_moments_t acc;
    sfit_status_t st;

    if (out == NULL || (pts == NULL && n > 0u)) {
        return SFIT_E_ARG;
    }
    (void)sfit_moments_init(&acc);
    st = sfit_moments_add_block(&acc, pts, n, NULL);
    if (st != SFIT_OK) {
        return st;
    }
    return sfit_fit_solve(&acc, cfg, out);
}
