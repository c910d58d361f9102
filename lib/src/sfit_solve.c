/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_solve.c
 * @brief The sphere / circle system shared by sfit_moments_fit() and
 * sfit_multi_fit(): eigenvalues, geometry checks, Cholesky or planar
 * pseudo-inverse, trust ratio. Derivation: docs/api.md#solver.
 */
#include "sfit_solve.h"

#include <float.h>
#include <string.h>

sfit_status_t sfit_i_check_noise(sfit_noise_kind_t kind, float var, const sfit_mat3_t *cov)
{
    const float *c = cov->m;
    int i;
    switch (kind) {
    case SFIT_NOISE_NONE:
        return SFIT_OK;
    case SFIT_NOISE_ISO:
        return (sfit_i_isfinite(var) && var >= 0.0f) ? SFIT_OK : SFIT_E_ARG;
    case SFIT_NOISE_COV:
        for (i = 0; i < 9; i++) {
            if (!sfit_i_isfinite(c[i])) {
                return SFIT_E_ARG;
            }
        }
        /* Positive semi-definite, necessary conditions: non-negative
         * diagonal and every 2x2 principal minor >= 0 (lower triangle). */
        if (c[0] < 0.0f || c[4] < 0.0f || c[8] < 0.0f || c[3] * c[3] > c[0] * c[4]
            || c[6] * c[6] > c[0] * c[8] || c[7] * c[7] > c[4] * c[8]) {
            return SFIT_E_ARG;
        }
        return SFIT_OK;
    default:
        return SFIT_E_ARG;
    }
}

sfit_status_t sfit_i_check_cfg(const sfit_fit_cfg_t *cfg)
{
    if (cfg->mode != SFIT_MODE_AUTO && cfg->mode != SFIT_MODE_SPHERE
        && cfg->mode != SFIT_MODE_PLANAR) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(cfg->planar_ratio) || cfg->planar_ratio < 0.0f
        || cfg->planar_ratio >= 1.0f || (cfg->eigen != 0 && cfg->eigen != 1)) {
        return SFIT_E_ARG;
    }
    return sfit_i_check_noise(cfg->noise, cfg->noise_var, &cfg->noise_cov);
}

/* Sigma_hat as a full symmetric matrix (lower triangle of the option). */
void sfit_i_sigma(sfit_noise_kind_t kind, float var, const sfit_mat3_t *cov, sfit_mat3_t *sg)
{
    memset(sg, 0, sizeof *sg);
    if (kind == SFIT_NOISE_ISO) {
        sg->m[0] = var;
        sg->m[4] = var;
        sg->m[8] = var;
    } else if (kind == SFIT_NOISE_COV) {
        const float *s = cov->m;
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
    sfit_vec3_t w;
    float x[9];
    int i, j;
    sfit_status_t st;

    /* X = L^-1 Sigma (Sigma's rows are its columns), B = L^-1 X^T. */
    for (j = 0; j < 3; j++) {
        sfit_i_chol_forward(l, &sg->m[3 * j], &x[3 * j]);
    }
    for (j = 0; j < 3; j++) {
        const float col[3] = {x[j], x[3 + j], x[6 + j]};
        float y[3];
        sfit_i_chol_forward(l, col, y);
        b.m[j] = y[0];
        b.m[3 + j] = y[1];
        b.m[6 + j] = y[2];
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
        k0 = sfit_i_dot3(v1, sys->rhs.v) / lamp.v[1];
        k1 = sfit_i_dot3(v2, sys->rhs.v) / lamp.v[2];
        for (i = 0; i < 3; i++) {
            r.w.v[i] = k0 * v1[i] + k1 * v2[i];
        }
        r.trace = lamp.v[1] + lamp.v[2];
        if (sys->noisy) {
            /* Trust on the kept plane: largest eigenvalue of the 2x2
             * B_ij = v_i^T Sigma v_j / sqrt(lambda_i lambda_j). */
            float sv1[3], sv2[3], b00, b01, b11, h;
            for (i = 0; i < 3; i++) {
                sv1[i] = sfit_i_dot3(&sg->m[3 * i], v1);
                sv2[i] = sfit_i_dot3(&sg->m[3 * i], v2);
            }
            b00 = sfit_i_dot3(v1, sv1) / lamp.v[1];
            b11 = sfit_i_dot3(v2, sv2) / lamp.v[2];
            b01 = sfit_i_dot3(v1, sv2) / SFIT_SQRTF(lamp.v[1] * lamp.v[2]);
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

