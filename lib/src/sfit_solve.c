/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_solve.c
 * @brief The sphere / circle system shared by sfit_fit_moments() and
 * sfit_multi_fit(): eigenvalues, geometry checks, Cholesky or planar
 * pseudo-inverse, trust ratio. Derivation: docs/api.md#solver.
 */
#include "sfit_solve.h"

#include <float.h>
#include <string.h>

/* Positive semi-definite test of the lower triangle of a finite 3x3 c by
 * the Cholesky factor that every fit links anyway: c / max(diag) plus a
 * shift of 2^-16 above the factor's pivot threshold must factor. A
 * semi-definite c (v v^T, every scale) then passes, with its rounding; an
 * indefinite one whose smallest eigenvalue is below -(2^-16 +
 * SFIT_CHOL_PIVOT_EPS) max(diag) is refused (a larger |off-diagonal| than
 * max(diag) overflows or fails a pivot). */
static int prv_psd(const float *c)
{
    sfit_mat3_t a;
    float dmax = FLT_MIN, s;
    int i;
    for (i = 0; i < 9; i += 4) {
        if (!(c[i] >= 0.0f)) {
            return 0;
        }
        dmax = (c[i] > dmax) ? c[i] : dmax;
    }
    s = 1.0f / dmax;
    for (i = 0; i < 9; i++) { /* the factor reads the lower triangle only */
        a.m[i] = c[i] * s;
    }
    for (i = 0; i < 9; i += 4) {
        a.m[i] += SFIT_CHOL_PIVOT_EPS + 1.52587890625e-5f;
    }
    return sfit_mat3_chol(&a, &a) == SFIT_OK;
}

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
        return prv_psd(c) ? SFIT_OK : SFIT_E_ARG;
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
    /* 0 <= planar_ratio < 1: NaN and +-Inf fail one of the comparisons */
    if (!(cfg->planar_ratio >= 0.0f && cfg->planar_ratio < 1.0f)
        || sfit_i_bool_byte(&cfg->eigen) > 1u) {
        return SFIT_E_ARG;
    }
    return sfit_i_check_noise(cfg->noise, cfg->noise_var, &cfg->noise_cov);
}

sfit_status_t sfit_i_check_multi_cfg(const sfit_multi_cfg_t *cfg)
{
    if (cfg->weight != SFIT_MULTI_WEIGHT_EQUAL && cfg->weight != SFIT_MULTI_WEIGHT_SAMPLES) {
        return SFIT_E_ARG;
    }
    return sfit_i_check_cfg(&cfg->fit);
}

sfit_status_t sfit_i_center_cov(const sfit_mat3_t *a, sfit_mode_t mode, const sfit_vec3_t *axis,
                                const sfit_mat3_t *m, float var, sfit_mat3_t *cov)
{
    sfit_mat3_t pap, l, ai, t, out;
    const float *ax = axis->v;
    const float sc = a->m[0] + a->m[4] + a->m[8];
    int r, s;
    pap = *a;
    if (mode == SFIT_MODE_PLANAR) {
        float aa[3], q;
        sfit_i_mat3_vec(a, ax, aa);
        q = sfit_i_dot3(ax, aa);
        for (r = 0; r < 3; r++) {
            for (s = 0; s < 3; s++) {
                pap.m[3 * r + s] += -ax[r] * aa[s] - aa[r] * ax[s] + (q + sc) * ax[r] * ax[s];
            }
        }
    }
    if (sfit_mat3_chol(&pap, &l) != SFIT_OK) {
        return SFIT_E_NOT_POSDEF;
    }
    sfit_i_chol_inverse(&l, &ai);
    if (mode == SFIT_MODE_PLANAR) {
        for (r = 0; r < 9; r++) {
            ai.m[r] -= ax[r / 3] * ax[r % 3] / sc;
        }
    }
    sfit_i_mat3_mul(&ai, m, &t);
    sfit_i_mat3_mul(&t, &ai, &out);
    for (r = 0; r < 9; r++) {
        out.m[r] *= var;
        if (!sfit_i_isfinite(out.m[r])) {
            return SFIT_E_RANGE;
        }
    }
    *cov = out;
    return SFIT_OK;
}

uint32_t sfit_i_multi_used(const sfit_moments_t *markers, size_t count, uint64_t *sum_n1)
{
    uint32_t used = 0u;
    size_t p;
    *sum_n1 = 0u;
    for (p = 0u; p < count; p++) {
        const uint32_t n = sfit_moments_count(&markers[p]);
        if (n >= SFIT_MIN_SAMPLES) {
            used++;
            *sum_n1 += (uint64_t)(n - 1u);
        }
    }
    return used;
}

float sfit_i_multi_weight(const sfit_multi_cfg_t *cfg, uint32_t n, uint32_t used,
                          uint64_t sum_n1)
{
    if (cfg->weight == SFIT_MULTI_WEIGHT_SAMPLES) {
        return ((float)(n - 1u) * (float)used) / (float)sum_n1;
    }
    return 1.0f;
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

/* Sigma_ij of a system with a noise model: the lower triangle of the
 * matrix, or var I. */
static float prv_sg(const sfit_i_system_t *sys, int i, int j)
{
    if (sys->noisy != (int)SFIT_NOISE_COV) {
        return (i == j) ? sys->sigma.var : 0.0f;
    }
    return (i >= j) ? sys->sigma.m->m[3 * i + j] : sys->sigma.m->m[3 * j + i];
}

/* m := Sigma (sub 0) or m - Sigma (sub 1), full (Sigma_ij: prv_sg). */
static void prv_sigma_to(const sfit_i_system_t *sys, float m[9], int sub)
{
    int i;
    for (i = 0; i < 9; i++) {
        const float g = prv_sg(sys, i / 3, i % 3);
        if (sub) {
            m[i] -= g;
        } else {
            m[i] = g;
        }
    }
}

/* Column 0 of V (finite: sfit_i_eig_sym checked it) as a vector, sign
 * chosen so that the component largest in magnitude (the first of equal
 * ones) is positive. On the bits, no FP operation: |x| of finite floats
 * is ordered as the bits with the sign shifted out, and the sign change
 * is the sign bit's (what a multiplication by -1 gives). */
static void prv_axis(const sfit_mat3_t *v, sfit_vec3_t *ax)
{
    uint32_t u0, u1, u2, sgn;
    memcpy(&u0, &v->m[0], sizeof u0);
    memcpy(&u1, &v->m[3], sizeof u1);
    memcpy(&u2, &v->m[6], sizeof u2);
    sgn = ((u0 << 1) > 0u) ? u0 : 0u; /* the first of the largest |v_i| > 0 */
    sgn = ((u1 << 1) > (sgn << 1)) ? u1 : sgn;
    sgn = ((u2 << 1) > (sgn << 1)) ? u2 : sgn;
    sgn &= 0x80000000u;
    u0 ^= sgn;
    u1 ^= sgn;
    u2 ^= sgn;
    memcpy(&ax->v[0], &u0, sizeof u0);
    memcpy(&ax->v[1], &u1, sizeof u1);
    memcpy(&ax->v[2], &u2, sizeof u2);
}

/* rho(L^-1 Sigma L^-T) for C' = L L^T; b and w are scratch. */
static sfit_status_t prv_trust_chol(const sfit_mat3_t *l, const sfit_i_system_t *sys,
                                    sfit_mat3_t *b, sfit_vec3_t *w, float *rho)
{
    float t;
    int i, j;
    sfit_status_t st;

    /* Y^T = (L^-1 Sigma)^T: row i of b := L^-1 (row i of Sigma = its
     * column i), in place (passes 0-2); then b is transposed to Y, and
     * B = L^-1 Y^T is formed row by row from the rows of Y, in place
     * (passes 3-5; B symmetric). One loop: one call site. */
    prv_sigma_to(sys, b->m, 0);
    for (i = 0; i < 6; i++) {
        if (i == 3) {
            int r;
            for (r = 0; r < 3; r++) {
                for (j = 0; j < r; j++) {
                    t = b->m[3 * r + j];
                    b->m[3 * r + j] = b->m[3 * j + r];
                    b->m[3 * j + r] = t;
                }
            }
        }
        sfit_i_chol_forward(l, &b->m[3 * (i % 3)], &b->m[3 * (i % 3)]);
    }
    b->m[1] = b->m[3];
    b->m[2] = b->m[6];
    b->m[5] = b->m[7];
    st = sfit_i_eig_sym(b->m, w, NULL);
    if (st != SFIT_OK) {
        return st;
    }
    *rho = 0.0f;
    for (i = 0; i < 3; i++) {
        const float a = SFIT_FABSF(w->v[i]);
        if (a > *rho) {
            *rho = a;
        }
    }
    return SFIT_OK;
}

/* 1 when Sigma is a multiple of I (or zero): then C' = C - Sigma has C's
 * eigenvectors and eigenvalues lambda - sigma^2. */
static int prv_sigma_iso(const sfit_i_system_t *sys)
{
    const float *sg;
    uint32_t u3, u6, u7;
    if (sys->noisy != (int)SFIT_NOISE_COV) {
        return 1;
    }
    sg = sys->sigma.m->m;
    /* the lower off-diagonal entries zero (either sign; a NaN is not):
     * their bits, the sign shifted out */
    memcpy(&u3, &sg[3], sizeof u3);
    memcpy(&u6, &sg[6], sizeof u6);
    memcpy(&u7, &sg[7], sizeof u7);
    return ((u3 | u6 | u7) << 1) == 0u && sg[0] == sg[4] && sg[0] == sg[8];
}

/* cp := C - Sigma (C when there is no noise model), C from the lower
 * triangle of the copy c. */
static void prv_cprime(const sfit_mat3_t *c, const sfit_i_system_t *sys, sfit_mat3_t *cp)
{
    sfit_i_sym_full(c, cp->m);
    if (sys->noisy) {
        prv_sigma_to(sys, cp->m, 1);
    }
}

/* Eigen-decomposition of C' into lamp and v (cp is destroyed). */
static sfit_status_t prv_eig_cprime(sfit_mat3_t *cp, sfit_vec3_t *lamp, sfit_mat3_t *v)
{
    const sfit_status_t st = sfit_i_eig_sym(cp->m, lamp, v->m);
    return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
}

/* prv_planar_test(): the bits of its result when it is not negative (a
 * negative result is a status). */
#define PRV_NEAR 1u   /* lambda_min(C') < ratio lambda_max(C') */
#define PRV_HAVE_P 2u /* lamp and v hold the eigen-decomposition of C' */
#define PRV_IS_NEAR(pt) ((((unsigned)(pt)) & PRV_NEAR) != 0u) /* pt >= 0 */
#define PRV_IS_P(pt) ((((unsigned)(pt)) & PRV_HAVE_P) != 0u)

/* The near-planar decision, lambda_min < ratio lambda_max, made on the
 * noise-corrected C' = C - Sigma whenever a noise model is given (C holds
 * the noise: a noisy circle looks like a sphere through C). With isotropic
 * or no noise the eigen-decomposition of C' is C's shifted (PRV_HAVE_P:
 * lamp and C's eigenvectors in v). A full Sigma first tries Weyl's bounds,
 * lambda_i(C) - tr(Sigma) <= lambda_i(C') <= lambda_i(C); only when they
 * cannot decide is C' decomposed (cp destroyed, v := its eigenvectors,
 * PRV_HAVE_P too). The threshold is out->trace. Returns PRV_NEAR |
 * PRV_HAVE_P (each or none), or a status < 0. */
static int prv_planar_test(sfit_i_system_t *sys, sfit_mat3_t *v, sfit_i_solution_t *out)
{
    const float *const ratio = &out->trace; /* the threshold (sfit_i_solve) */
    const sfit_vec3_t *const lam = &out->eigenvalues;
    sfit_vec3_t *const lamp = &out->w;
    sfit_status_t st;
    int i;
    if (!sys->noisy || prv_sigma_iso(sys)) {
        for (i = 0; i < 3; i++) {
            lamp->v[i] = sys->noisy ? lam->v[i] - prv_sg(sys, 0, 0) : lam->v[i];
        }
        return (int)(PRV_HAVE_P | ((lamp->v[0] < *ratio * lamp->v[2]) ? PRV_NEAR : 0u));
    }
    {
        const float *sg = sys->sigma.m->m; /* a full Sigma: not isotropic */
        const float trs = sg[0] + sg[4] + sg[8];
        if (lam->v[0] < *ratio * (lam->v[2] - trs)) {
            return (int)PRV_NEAR;
        }
        if (lam->v[0] - trs >= *ratio * lam->v[2]) {
            return 0;
        }
    }
    st = prv_eig_cprime(&sys->ms.c, lamp, v);
    if (st != SFIT_OK) {
        return (int)st;
    }
    return (int)(PRV_HAVE_P | ((lamp->v[0] < *ratio * lamp->v[2]) ? PRV_NEAR : 0u));
}

/* Sphere: Cholesky of C' = C - Sigma_hat (cp, factored in place), w = C'^-1 b;
 * the trust ratio from lamp (isotropic noise) or from L^-1 Sigma L^-T
 * (v and then lamp are scratch). */
static sfit_status_t prv_sphere(sfit_i_system_t *sys, int have_p, sfit_mat3_t *v,
                                sfit_i_solution_t *out)
{
    sfit_mat3_t *const cp = &sys->ms.c;
    sfit_vec3_t *const lamp = &out->w;
    sfit_status_t st;
    out->trace = cp->m[0] + cp->m[4] + cp->m[8];
    st = sfit_mat3_chol(cp, cp);
    if (st != SFIT_OK) {
        return sys->noisy ? SFIT_E_NOT_POSDEF : SFIT_E_DEGENERATE;
    }
    if (sys->noisy) {
        if (have_p && prv_sigma_iso(sys) && lamp->v[0] > 0.0f) {
            /* rho(C'^-1 sigma^2 I) = sigma^2 / lambda_min(C'). */
            out->rho = prv_sg(sys, 0, 0) / lamp->v[0];
        } else {
            st = prv_trust_chol(cp, sys, v, lamp, &out->rho); /* lamp: scratch */
            if (st != SFIT_OK) {
                return st;
            }
        }
    }
    sfit_i_chol_solve(cp, sys->ms.rhs.v, out->w.v); /* lamp (= out->w) read above */
    out->mode = SFIT_MODE_SPHERE;
    return SFIT_OK;
}

/* Trust on the kept plane of a planar solution (noisy systems): the
 * largest eigenvalue of the 2x2 B_ij = v_i^T Sigma v_j / sqrt(lambda_i
 * lambda_j) over the two largest eigen-directions of C' (lamp, v). Before
 * prv_planar(), which writes w over lamp (stack trick 2); when lamp[1] is
 * not positive prv_planar() refuses the system and rho is not read. */
static void prv_planar_trust(const sfit_i_system_t *sys, const sfit_vec3_t *lamp,
                             const sfit_mat3_t *v, sfit_i_solution_t *out)
{
    const float *const e = v->m; /* v1 = column 1, v2 = column 2 */
    float b00 = 0.0f, b01 = 0.0f, b11 = 0.0f, h;
    int i, j;
    for (i = 0; i < 3; i++) {
        float s1 = 0.0f, s2 = 0.0f; /* row i of Sigma v1, Sigma v2 */
        for (j = 0; j < 3; j++) {
            const float g = prv_sg(sys, i, j);
            s1 += g * e[3 * j + 1];
            s2 += g * e[3 * j + 2];
        }
        b00 += e[3 * i + 1] * s1;
        b11 += e[3 * i + 2] * s2;
        b01 += e[3 * i + 1] * s2;
    }
    b00 /= lamp->v[1];
    b11 /= lamp->v[2];
    b01 /= SFIT_SQRTF(lamp->v[1] * lamp->v[2]);
    /* Spectral radius of the symmetric 2x2: |mean| + half-gap. */
    h = 0.5f * (b00 - b11);
    out->rho = 0.5f * SFIT_FABSF(b00 + b11) + SFIT_SQRTF(h * h + b01 * b01);
}

/* Planar (eq. 217): pseudo-inverse over the two largest eigen-directions of
 * C' (lamp, v); a noisy system's trust ratio comes first
 * (prv_planar_trust). lamp may be out->w (written last, stack trick 2). */
SFIT_I_NOINLINE static sfit_status_t prv_planar(const sfit_i_system_t *sys, const sfit_vec3_t *lamp,
                                const sfit_mat3_t *v, sfit_i_solution_t *out)
{
    const float *const e = v->m; /* v1 = column 1, v2 = column 2 */
    float k0 = 0.0f, k1 = 0.0f;
    int i;
    if (!(lamp->v[1] > SFIT_CHOL_PIVOT_EPS * lamp->v[2])) {
        return sys->noisy ? SFIT_E_NOT_POSDEF : SFIT_E_DEGENERATE;
    }
    for (i = 0; i < 3; i++) {
        k0 += e[3 * i + 1] * sys->ms.rhs.v[i];
        k1 += e[3 * i + 2] * sys->ms.rhs.v[i];
    }
    k0 /= lamp->v[1];
    k1 /= lamp->v[2];
    out->trace = lamp->v[1] + lamp->v[2];
    for (i = 0; i < 3; i++) { /* last: lamp may be out->w */
        out->w.v[i] = k0 * e[3 * i + 1] + k1 * e[3 * i + 2];
    }
    prv_axis(v, &out->axis);
    out->mode = SFIT_MODE_PLANAR;
    return SFIT_OK;
}

/* The start of both solvers: out initialised (the planar threshold waits
 * in out->trace, stored before any call: no float register to keep, stack
 * trick 3) and C's storage mirrored into the full symmetric working matrix
 * of the Jacobi (stack trick 1). */
static void prv_init(sfit_i_system_t *sys, float planar_ratio, sfit_i_solution_t *out)
{
    sfit_mat3_t *const cp = &sys->ms.c;
    out->trace = (planar_ratio > 0.0f) ? planar_ratio : SFIT_PLANAR_RATIO;
    memset(out, 0, offsetof(sfit_i_solution_t, trace));
    out->rho = 0.0f;
    out->flags = 0u;
    out->mode = SFIT_MODE_AUTO; /* set by the sphere or planar solve */
    sfit_i_sym_full(cp, cp->m); /* in place: the lower triangle mirrored */
}

/* The geometry checks on C's eigenvalues (in out). */
static sfit_status_t prv_geometry(const sfit_i_system_t *sys, const sfit_i_solution_t *out)
{
    const sfit_vec3_t *const lam = &out->eigenvalues;
    /* lambda_max > FLT_MIN and >= SFIT_MIN_SPREAD^2 (NaN fails): the one
     * test that implies the other (SFIT_I_SPREAD2_NORMAL). */
    if ((SFIT_I_SPREAD2_NORMAL ? !(lam->v[2] >= SFIT_MIN_SPREAD * SFIT_MIN_SPREAD)
                               : !(lam->v[2] > FLT_MIN))
        || lam->v[2] <= sys->scale * sys->scale) {
        return SFIT_E_DEGENERATE; /* coincident, or a spread too small for float */
    }
    if (lam->v[1] <= SFIT_COLLINEAR_RATIO * lam->v[2]) {
        return SFIT_E_DEGENERATE; /* collinear */
    }
    return SFIT_OK;
}

sfit_status_t sfit_i_solution_finite(const sfit_i_solution_t *out)
{
    int i;
    for (i = 0; i < 3; i++) {
        if (!sfit_i_isfinite(out->w.v[i])) {
            return SFIT_E_RANGE;
        }
    }
    return sfit_i_isfinite(out->trace) ? SFIT_OK : SFIT_E_RANGE;
}

/* The end of the noisy solver: UNTRUSTED from rho, every output finite. */
static sfit_status_t prv_end(sfit_i_solution_t *out)
{
    if (out->rho >= 1.0f) {
        out->flags |= (uint8_t)SFIT_FLAG_UNTRUSTED;
    }
    return sfit_i_isfinite(out->rho) ? sfit_i_solution_finite(out) : SFIT_E_RANGE;
}

sfit_status_t sfit_i_solve_plain(sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                                 sfit_i_solution_t *out)
{
    sfit_mat3_t *const cp = &sys->ms.c;
    sfit_mat3_t c;
    const sfit_vec3_t *const lam = &out->eigenvalues;
    sfit_mat3_t v;
    sfit_status_t st;

    prv_init(sys, planar_ratio, out);
    c = *cp; /* C, mirrored by prv_init() */
    st = sfit_i_eig_sym(cp->m, &out->eigenvalues, v.m);
    if (st != SFIT_OK) {
        return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
    }
    st = prv_geometry(sys, out);
    if (st != SFIT_OK) {
        return st;
    }
    prv_axis(&v, &out->axis); /* the sphere's cap axis (before v is reused) */
    if (lam->v[0] < out->trace * lam->v[2]) { /* out->trace: the threshold */
        out->flags |= (uint8_t)SFIT_FLAG_NEAR_PLANAR;
        mode = (mode == SFIT_MODE_AUTO) ? SFIT_MODE_PLANAR : mode;
    }
    if (mode == SFIT_MODE_PLANAR) {
        st = prv_planar(sys, lam, &v, out);
    } else { /* C' = C: its Cholesky factor and w = C^-1 b */
        sfit_i_sym_full(&c, cp->m);
        out->trace = cp->m[0] + cp->m[4] + cp->m[8];
        if (sfit_mat3_chol(cp, cp) != SFIT_OK) {
            return SFIT_E_DEGENERATE;
        }
        sfit_i_chol_solve(cp, sys->ms.rhs.v, out->w.v);
        out->mode = SFIT_MODE_SPHERE;
    }
    return (st == SFIT_OK) ? sfit_i_solution_finite(out) : st;
}

/* One solver for every noise model: a system without one (SFIT_NOISE_NONE)
 * takes the same steps with Sigma = 0 (C' = C, no trust ratio) and gets
 * sfit_i_solve_plain()'s answer bit for bit, so that a build with the
 * screen links one full solver, not two (sfit_i_solve_plain() stays the
 * whole solver of sfit_fit_moments_default() alone). */
sfit_status_t sfit_i_solve(sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                           sfit_i_solution_t *out)
{
    /* C's storage in the system is the working matrix (Jacobi, then C' and
     * its factor); C itself is kept as a copy (stack trick 1, sfit_solve.h). */
    sfit_mat3_t *const cp = &sys->ms.c;
    sfit_mat3_t c;
    sfit_mat3_t v;
    /* C''s eigenvalues (or scratch) until w is written last (prv_sphere,
     * prv_planar): no frame of their own (stack trick 2, sfit_solve.h). */
    sfit_vec3_t *const lamp = &out->w;
    int pt;
    sfit_status_t st;

    /* The start of sfit_i_solve_plain(), written again: as a function of
     * its own it puts a frame on the Jacobi's path (measured 336 B on
     * sfit_fit_moments against its budget of 320). */
    prv_init(sys, planar_ratio, out);
    c = *cp; /* C, mirrored by prv_init() */
    st = sfit_i_eig_sym(cp->m, &out->eigenvalues, v.m);
    if (st != SFIT_OK) {
        return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
    }
    st = prv_geometry(sys, out);
    if (st != SFIT_OK) {
        return st;
    }
    prv_axis(&v, &out->axis); /* the sphere's cap axis (before v is reused) */
    prv_cprime(&c, sys, cp);
    pt = prv_planar_test(sys, &v, out);
    if (pt < 0) {
        return (sfit_status_t)pt;
    }
    if (PRV_IS_NEAR(pt)) {
        out->flags |= (uint8_t)SFIT_FLAG_NEAR_PLANAR;
    }
    if ((mode == SFIT_MODE_PLANAR) || (mode == SFIT_MODE_AUTO && PRV_IS_NEAR(pt))) {
        if (!PRV_IS_P(pt)) {
            st = prv_eig_cprime(cp, lamp, &v);
        }
        if (st == SFIT_OK) {
            if (sys->noisy) {
                prv_planar_trust(sys, lamp, &v, out);
            }
            st = prv_planar(sys, lamp, &v, out);
        }
    } else {
        if (PRV_IS_P(pt) && !prv_sigma_iso(sys)) {
            prv_cprime(&c, sys, cp); /* destroyed by the decomposition of C' */
        }
        st = prv_sphere(sys, PRV_IS_P(pt), &v, out);
    }
    return (st == SFIT_OK) ? prv_end(out) : st;
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

