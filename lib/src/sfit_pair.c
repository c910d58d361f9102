/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pair.c
 * @brief A pair of segments (SCoRE / SARA) as a stream, with the
 * errors-in-variables bias removed and a covariance on every result.
 *
 * Implementation notes (derivation: docs/pair.md)
 * ------------------------------------------------
 * Per frame: A = R_p^T R_c, g = R_c^T (t_c - t_p), d = R_p^T (t_c - t_p).
 * The sums are shifted by the first frame (B = A - A_ref, h = g - g_ref,
 * e = d - d_ref) and kept in two levels (inner blocks of SFIT_SUM_BLOCK
 * frames), so the centred second moments never come from a difference of
 * large raw sums. Layout of the sums (SFIT_PAIR_NSUM = 68):
 *   0..8    sum B (row-major)        9..11  sum h
 *   12..56  sum vec(B) vec(B)^T, packed upper triangle of the 9x9 (45)
 *   57..59  sum B h                  60     sum |h|^2
 *   61..63  sum e                    64, 65 parent sum |res|^2, sum (3 used - 6)
 *   66, 67  child sum |res|^2, sum (3 used - 6)
 * The 9x9 moment T gives the Schur complement S = sum B B^T (centred) and
 * the contractions sum B X B^T and sum B^T Y B of the covariance.
 *
 * sfit_pair_add() validates every input before it writes: a rejected frame
 * leaves every byte as it was.
 */
#include "sfit/sfit_pair.h"

#include <string.h>

#include "sfit/sfit_mat3.h"
#include "sfit_float.h"
#include "sfit_mat3_i.h"

const sfit_pair_cfg_t sfit_pair_cfg_default = {
    .method = SFIT_PAIR_METHOD_DEFAULT, .mode = SFIT_PAIR_MODE_AUTO,
    .noise = SFIT_PAIR_NOISE_RESIDUAL, .marker_var = 0.0f, .hinge_ratio = 0.0f,
    .max_trust = 0.0f, .max_misfit = 0.0f, .axis_tol = 0.0f, .wobble = 0.0f, .min_frames = 0u};

/* Defaults of the thresholds left at 0 in the options. */
#define PRV_HINGE_RATIO 0.02f
#define PRV_MAX_TRUST 0.25f
#define PRV_MAX_MISFIT 2.0f
#define PRV_AXIS_TOL 0.1745329f /* 10 degrees */
#define PRV_WOBBLE 0.0436332f /* 2.5 degrees rms: a 2-5 degree out-of-axis rotation in step with the flexion */
#define PRV_MIN_FRAMES 30u
/* Ball: lambda_1 of the corrected S must be this many of its noise
 * standard deviations above zero for the centre to be fixed by the data. */
#define PRV_Z_BALL 5.0f
/* chi^2(2 dof) 95 % quantile: the 95 % cone of a unit axis. */
#define PRV_CHI2_2_95 5.991465f
/* No relative rotation: the largest eigenvalue of S / frames below this
 * (rad^2) is no motion at all. */
#define PRV_MIN_SPREAD 1e-12f

/* Sum layout. */
#define PRV_SB 0
#define PRV_SH 9
#define PRV_T 12
#define PRV_SBH 57
#define PRV_SHH 60
#define PRV_SE 61
#define PRV_RP 64
#define PRV_RC 66

/* Index of (a, b) in the packed upper triangle of a 9x9 symmetric matrix. */
static int prv_tidx(int a, int b)
{
    if (a > b) {
        const int t = a;
        a = b;
        b = t;
    }
    return 9 * a - (a * (a - 1)) / 2 + (b - a);
}

static int prv_cfg_ok(const sfit_pair_cfg_t *c)
{
    if ((uint32_t)c->method > (uint32_t)SFIT_PAIR_METHOD_SCORE
        || (uint32_t)c->mode > (uint32_t)SFIT_PAIR_MODE_HINGE
        || (uint32_t)c->noise > (uint32_t)SFIT_PAIR_NOISE_GIVEN) {
        return 0;
    }
    if (!sfit_i_isfinite(c->marker_var) || !(c->marker_var >= 0.0f)
        || !sfit_i_isfinite(c->hinge_ratio) || !(c->hinge_ratio >= 0.0f)
        || !sfit_i_isfinite(c->max_trust) || !(c->max_trust >= 0.0f)
        || !sfit_i_isfinite(c->max_misfit) || !(c->max_misfit >= 0.0f)
        || !sfit_i_isfinite(c->axis_tol) || !(c->axis_tol >= 0.0f)
        || !(c->axis_tol < 1.5f) || !sfit_i_isfinite(c->wobble) || !(c->wobble >= 0.0f)) {
        return 0;
    }
    return 1;
}

static int prv_state_ok(const sfit_pair_t *s)
{
    int k;
    if (s->n_p < 3u || s->n_p > (uint32_t)SFIT_CLUSTER_MAX_MARKERS || s->n_c < 3u
        || s->n_c > (uint32_t)SFIT_CLUSTER_MAX_MARKERS) {
        return 0;
    }
    if (s->inblk >= (uint32_t)SFIT_SUM_BLOCK || s->inblk > s->frames || !prv_cfg_ok(&s->cfg)) {
        return 0;
    }
    for (k = 0; k < 6; k++) {
        if (!sfit_i_isfinite(s->k_p[k]) || !sfit_i_isfinite(s->k_c[k])) {
            return 0;
        }
    }
    return sfit_i_finite3(s->cen_p.v) && sfit_i_finite3(s->cen_c.v);
}

/* Centroid and tr(J^-1) I - J^-1 of a template, J = sum (|q|^2 I - q q^T)
 * about the centroid. */
static sfit_status_t prv_template(const sfit_cluster_t *cl, sfit_vec3_t *cen, float kp[6])
{
    sfit_mat3_t jm, l, inv;
    float tr;
    uint32_t i;
    int a, b;

    if (cl->count < 3u || cl->count > (uint32_t)SFIT_CLUSTER_MAX_MARKERS) {
        return SFIT_E_ARG;
    }
    for (i = 0; i < cl->count; i++) {
        if (sfit_i_check_sample(cl->pos[i].v) != SFIT_OK) {
            return SFIT_E_ARG;
        }
    }
    for (a = 0; a < 3; a++) {
        float m = 0.0f;
        for (i = 0; i < cl->count; i++) {
            m += cl->pos[i].v[a] - cl->pos[0].v[a];
        }
        cen->v[a] = cl->pos[0].v[a] + m / (float)cl->count;
    }
    memset(&jm, 0, sizeof jm);
    for (i = 0; i < cl->count; i++) {
        float q[3], q2;
        for (a = 0; a < 3; a++) {
            q[a] = cl->pos[i].v[a] - cen->v[a];
        }
        q2 = sfit_i_dot3(q, q);
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                jm.m[3 * a + b] += ((a == b) ? q2 : 0.0f) - q[a] * q[b];
            }
        }
    }
    if (sfit_mat3_chol(&jm, &l) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    sfit_i_chol_inverse(&l, &inv);
    tr = inv.m[0] + inv.m[4] + inv.m[8];
    sfit_i_sym_pack(&inv, kp);
    for (a = 0; a < 6; a++) {
        kp[a] = ((a < 3) ? tr : 0.0f) - kp[a];
    }
    return SFIT_OK;
}

sfit_status_t sfit_pair_init(sfit_pair_t *s, const sfit_cluster_t *parent,
                             const sfit_cluster_t *child, const sfit_pair_cfg_t *cfg)
{
    sfit_vec3_t cp, cc;
    float kp[6], kc[6];
    sfit_pair_cfg_t cf;
    sfit_status_t st;

    if (s == NULL || parent == NULL || child == NULL) {
        return SFIT_E_ARG;
    }
    cf = (cfg != NULL) ? *cfg : sfit_pair_cfg_default;
    if (!prv_cfg_ok(&cf)) {
        return SFIT_E_ARG;
    }
    st = prv_template(parent, &cp, kp);
    if (st == SFIT_OK) {
        st = prv_template(child, &cc, kc);
    }
    if (st != SFIT_OK) {
        return st;
    }
    {
        const uint32_t np = parent->count, nc = child->count;
        memset(s, 0, sizeof *s);
        s->cfg = cf;
        s->cen_p = cp;
        s->cen_c = cc;
        memcpy(s->k_p, kp, sizeof kp);
        memcpy(s->k_c, kc, sizeof kc);
        s->n_p = np;
        s->n_c = nc;
    }
    return SFIT_OK;
}

sfit_status_t sfit_pair_reset(sfit_pair_t *s)
{
    if (s == NULL || !prv_state_ok(s)) {
        return SFIT_E_ARG;
    }
    memset(s->a_ref, 0, sizeof s->a_ref);
    memset(s->g_ref, 0, sizeof s->g_ref);
    memset(s->d_ref, 0, sizeof s->d_ref);
    memset(s->tot, 0, sizeof s->tot);
    memset(s->blk, 0, sizeof s->blk);
    s->frames = 0u;
    s->inblk = 0u;
    return SFIT_OK;
}

/* A pose: finite, rotation entries within 1 + 1e-3, translation in range. */
static sfit_status_t prv_check_pose(const sfit_pose_t *p)
{
    int k;
    for (k = 0; k < 9; k++) {
        if (!sfit_i_isfinite(p->r.m[k])) {
            return SFIT_E_NONFINITE;
        }
    }
    {
        const sfit_status_t st = sfit_i_check_sample(p->t.v);
        if (st != SFIT_OK) {
            return st;
        }
    }
    for (k = 0; k < 9; k++) {
        if (SFIT_FABSF(p->r.m[k]) > 1.001f) {
            return SFIT_E_RANGE;
        }
    }
    return SFIT_OK;
}

/* A registration residual: NULL (none), or rms >= 0 finite with used in
 * 3..count. ssr and dof are set (0 when NULL). */
static sfit_status_t prv_check_fit(const sfit_cluster_fit_t *f, uint32_t count, float *ssr,
                                   float *dof)
{
    *ssr = 0.0f;
    *dof = 0.0f;
    if (f == NULL) {
        return SFIT_OK;
    }
    if (f->used < 3u || f->used > count) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(f->rms)) {
        return SFIT_E_NONFINITE;
    }
    if (!(f->rms >= 0.0f)) {
        return SFIT_E_ARG;
    }
    *ssr = f->rms * f->rms * (float)f->used;
    if (!sfit_i_isfinite(*ssr)) {
        return SFIT_E_RANGE;
    }
    *dof = 3.0f * (float)f->used - 6.0f;
    return SFIT_OK;
}

sfit_status_t sfit_pair_add(sfit_pair_t *s, const sfit_pose_t *pose_p,
                            const sfit_cluster_fit_t *fit_p, const sfit_pose_t *pose_c,
                            const sfit_cluster_fit_t *fit_c)
{
    float a[9], g[3], d[3], dt[3], v[SFIT_PAIR_NSUM];
    float ssr_p, dof_p, ssr_c, dof_c;
    sfit_status_t st;
    int i, j, k;

    if (s == NULL || pose_p == NULL || pose_c == NULL || !prv_state_ok(s)) {
        return SFIT_E_ARG;
    }
    st = prv_check_pose(pose_p);
    if (st == SFIT_OK) {
        st = prv_check_pose(pose_c);
    }
    if (st == SFIT_OK) {
        st = prv_check_fit(fit_p, s->n_p, &ssr_p, &dof_p);
    }
    if (st == SFIT_OK) {
        st = prv_check_fit(fit_c, s->n_c, &ssr_c, &dof_c);
    }
    if (st != SFIT_OK) {
        return st;
    }
    if (s->frames == UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    /* A = R_p^T R_c, g = R_c^T dt, d = R_p^T dt, dt = t_c - t_p. */
    for (i = 0; i < 3; i++) {
        dt[i] = pose_c->t.v[i] - pose_p->t.v[i];
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            a[3 * i + j] = pose_p->r.m[i] * pose_c->r.m[j] + pose_p->r.m[3 + i] * pose_c->r.m[3 + j]
                           + pose_p->r.m[6 + i] * pose_c->r.m[6 + j];
        }
        g[i] = pose_c->r.m[i] * dt[0] + pose_c->r.m[3 + i] * dt[1] + pose_c->r.m[6 + i] * dt[2];
        d[i] = pose_p->r.m[i] * dt[0] + pose_p->r.m[3 + i] * dt[1] + pose_p->r.m[6 + i] * dt[2];
    }
    if (!sfit_i_finite3(dt) || !sfit_i_finite3(g) || !sfit_i_finite3(d)) {
        return SFIT_E_RANGE;
    }
    if (s->frames == 0u) {
        /* The first frame is the shift: its B, h, e are zero. */
        memcpy(s->a_ref, a, sizeof a);
        memcpy(s->g_ref, g, sizeof g);
        memcpy(s->d_ref, d, sizeof d);
    }
    {
        float b[9], h[3];
        for (k = 0; k < 9; k++) {
            b[k] = a[k] - s->a_ref[k];
            v[PRV_SB + k] = b[k];
        }
        for (k = 0; k < 3; k++) {
            h[k] = g[k] - s->g_ref[k];
        }
        for (k = 0; k < 3; k++) {
            v[PRV_SH + k] = h[k];
            v[PRV_SE + k] = d[k] - s->d_ref[k];
            v[PRV_SBH + k] = b[3 * k] * h[0] + b[3 * k + 1] * h[1] + b[3 * k + 2] * h[2];
        }
        k = PRV_T;
        for (i = 0; i < 9; i++) {
            for (j = i; j < 9; j++) {
                v[k++] = b[i] * b[j];
            }
        }
        v[PRV_SHH] = sfit_i_dot3(h, h);
    }
    v[PRV_RP] = ssr_p;
    v[PRV_RP + 1] = dof_p;
    v[PRV_RC] = ssr_c;
    v[PRV_RC + 1] = dof_c;
    /* Commit. */
    for (k = 0; k < SFIT_PAIR_NSUM; k++) {
        s->blk[k] += v[k];
    }
    if (++s->inblk == (uint32_t)SFIT_SUM_BLOCK) {
        for (k = 0; k < SFIT_PAIR_NSUM; k++) {
            s->tot[k] += s->blk[k];
            s->blk[k] = 0.0f;
        }
        s->inblk = 0u;
    }
    s->frames++;
    return SFIT_OK;
}

sfit_status_t sfit_pair_add_markers(sfit_pair_t *s, const sfit_cluster_t *parent,
                                    const sfit_vec3_t *pm, size_t n_pm,
                                    const sfit_cluster_t *child, const sfit_vec3_t *cm,
                                    size_t n_cm)
{
    sfit_pose_t pp, pc;
    sfit_cluster_fit_t fp, fc;
    sfit_status_t st;

    if (s == NULL || parent == NULL || child == NULL || pm == NULL || cm == NULL
        || !prv_state_ok(s) || parent->count != s->n_p || child->count != s->n_c) {
        return SFIT_E_ARG;
    }
    st = sfit_cluster_register(parent, pm, n_pm, &pp, &fp);
    if (st != SFIT_OK) {
        return st;
    }
    st = sfit_cluster_register(child, cm, n_cm, &pc, &fc);
    if (st != SFIT_OK) {
        return st;
    }
    return sfit_pair_add(s, &pp, &fp, &pc, &fc);
}

/* ---------------------------------------------------------------- solve */

/* out = [x]x m [x]x^T for a symmetric m. */
static void prv_cross_quad(const float x[3], const sfit_mat3_t *m, sfit_mat3_t *out)
{
    sfit_mat3_t xm;
    const float cx[9] = {0.0f, -x[2], x[1], x[2], 0.0f, -x[0], -x[1], x[0], 0.0f};
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            xm.m[3 * i + j] = cx[3 * i] * m->m[j] + cx[3 * i + 1] * m->m[3 + j]
                              + cx[3 * i + 2] * m->m[6 + j];
        }
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            out->m[3 * i + j] = xm.m[3 * i] * cx[3 * j] + xm.m[3 * i + 1] * cx[3 * j + 1]
                                + xm.m[3 * i + 2] * cx[3 * j + 2];
        }
    }
}

/* p = a b^T-style products: out = a m a^T (a full, m full). */
static void prv_sandwich(const sfit_mat3_t *a, const sfit_mat3_t *m, sfit_mat3_t *out)
{
    sfit_mat3_t am;
    int i, j;
    sfit_i_mat3_mul(a, m, &am);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            out->m[3 * i + j] = am.m[3 * i] * a->m[3 * j] + am.m[3 * i + 1] * a->m[3 * j + 1]
                                + am.m[3 * i + 2] * a->m[3 * j + 2];
        }
    }
}

/* The centred moments and the pose-noise model the solve works with. */
typedef struct prv_sys {
    float tc[45];       /* centred 9x9 moment of B */
    sfit_mat3_t s;      /* S = sum (A - Abar)(A - Abar)^T */
    sfit_mat3_t abar;   /* mean A */
    float r[3];         /* sum (A - Abar)(g' - gbar'), centroid coordinates */
    float gbar[3];      /* mean g', centroid coordinates */
    float mid[3];       /* mid-point of the clusters, parent frame, centroid coordinates */
    float hh;           /* sum |g' - gbar'|^2 */
    float n;            /* frames */
    float var_p, var_c; /* marker variances */
    sfit_mat3_t jp, jc; /* J^-1 of each template (rotation noise per unit variance) */
    sfit_mat3_t kp, kc; /* var (tr J^-1 I - J^-1) */
} prv_sys_t;

/* sum B X B^T (i, k) = sum_jl X_jl T(3i+j, 3k+l). */
static void prv_contract_right(const float tc[45], const sfit_mat3_t *x, sfit_mat3_t *out)
{
    int i, k, j, l;
    for (i = 0; i < 3; i++) {
        for (k = 0; k < 3; k++) {
            float sum = 0.0f;
            for (j = 0; j < 3; j++) {
                for (l = 0; l < 3; l++) {
                    sum += x->m[3 * j + l] * tc[prv_tidx(3 * i + j, 3 * k + l)];
                }
            }
            out->m[3 * i + k] = sum;
        }
    }
}

/* sum B^T Y B (j, l) = sum_ik Y_ik T(3i+j, 3k+l). */
static void prv_contract_left(const float tc[45], const sfit_mat3_t *y, sfit_mat3_t *out)
{
    int i, k, j, l;
    for (j = 0; j < 3; j++) {
        for (l = 0; l < 3; l++) {
            float sum = 0.0f;
            for (i = 0; i < 3; i++) {
                for (k = 0; k < 3; k++) {
                    sum += y->m[3 * i + k] * tc[prv_tidx(3 * i + j, 3 * k + l)];
                }
            }
            out->m[3 * j + l] = sum;
        }
    }
}

/* G(P, C) = S P S / N + Abar (sum B^T P B) Abar^T + sum B C B^T: the
 * covariance of the Schur right-hand side for per-frame equation noise
 * A^T P A + C (child frame), P fixed in the parent frame, C in the child's. */
static void prv_gmat(const prv_sys_t *y, const sfit_mat3_t *p, const sfit_mat3_t *c,
                     sfit_mat3_t *out)
{
    sfit_mat3_t t1, t2, t3;
    int k;
    prv_sandwich(&y->s, p, &t1);
    prv_contract_left(y->tc, p, &t3);
    prv_sandwich(&y->abar, &t3, &t2);
    prv_contract_right(y->tc, c, &t3);
    for (k = 0; k < 9; k++) {
        out->m[k] = t1.m[k] / y->n + t2.m[k] + t3.m[k];
    }
}

/* Equation noise of a point x (parent frame) / y (child frame), about the
 * centroids: P = var_p ([x] J_p^-1 [x]^T + I / M_p), C likewise. */
static void prv_point_noise(const prv_sys_t *y, const sfit_pair_t *s, const float xp[3],
                            const float xc[3], sfit_mat3_t *p, sfit_mat3_t *c)
{
    int k;
    prv_cross_quad(xp, &y->jp, p);
    prv_cross_quad(xc, &y->jc, c);
    for (k = 0; k < 9; k++) {
        p->m[k] *= y->var_p;
        c->m[k] *= y->var_c;
    }
    for (k = 0; k < 3; k++) {
        p->m[4 * k] += y->var_p / (float)s->n_p;
        c->m[4 * k] += y->var_c / (float)s->n_c;
    }
}

/* Build the centred system from the sums. 0 when a sum is not finite. */
static int prv_build(const sfit_pair_t *s, prv_sys_t *y, float *dof_p, float *dof_c,
                     float *ssr_p, float *ssr_c)
{
    float q[SFIT_PAIR_NSUM], r0[3], sp[3];
    const float *cp = s->cen_p.v, *cc = s->cen_c.v;
    int i, j, k;
    float tr;

    for (k = 0; k < SFIT_PAIR_NSUM; k++) {
        q[k] = s->tot[k] + s->blk[k];
        if (!sfit_i_isfinite(q[k])) {
            return 0;
        }
    }
    for (k = 0; k < 9; k++) {
        if (!sfit_i_isfinite(s->a_ref[k])) {
            return 0;
        }
    }
    if (!sfit_i_finite3(s->g_ref) || !sfit_i_finite3(s->d_ref)) {
        return 0;
    }
    y->n = (float)s->frames;
    for (i = 0; i < 9; i++) {
        for (j = i; j < 9; j++) {
            const int t = prv_tidx(i, j);
            y->tc[t] = q[PRV_T + t] - q[PRV_SB + i] * q[PRV_SB + j] / y->n;
        }
    }
    {
        const sfit_mat3_t eye = {{1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f}};
        prv_contract_right(y->tc, &eye, &y->s);
    }
    for (k = 0; k < 9; k++) {
        y->abar.m[k] = s->a_ref[k] + q[PRV_SB + k] / y->n;
    }
    for (i = 0; i < 3; i++) {
        r0[i] = q[PRV_SBH + i];
        for (j = 0; j < 3; j++) {
            r0[i] -= q[PRV_SB + 3 * i + j] * q[PRV_SH + j] / y->n;
        }
    }
    /* Centroid coordinates: g' = g + cen_c - A^T cen_p, so
     * r' = r - S cen_p and sum |h' - mean|^2 = hh - 2 cen_p.r + cen_p.S cen_p. */
    sfit_i_mat3_vec(&y->s, cp, sp);
    y->hh = q[PRV_SHH] - sfit_i_dot3(&q[PRV_SH], &q[PRV_SH]) / y->n - 2.0f * sfit_i_dot3(cp, r0)
            + sfit_i_dot3(cp, sp);
    for (i = 0; i < 3; i++) {
        y->r[i] = r0[i] - sp[i];
        y->gbar[i] = s->g_ref[i] + q[PRV_SH + i] / y->n + cc[i]
                     - (y->abar.m[i] * cp[0] + y->abar.m[3 + i] * cp[1] + y->abar.m[6 + i] * cp[2]);
        /* child centroid in the parent frame: mean d + Abar cen_c */
        y->mid[i] = 0.5f * (s->d_ref[i] + q[PRV_SE + i] / y->n + sfit_i_dot3(&y->abar.m[3 * i], cc)
                            - cp[i]);
    }
    *ssr_p = q[PRV_RP];
    *dof_p = q[PRV_RP + 1];
    *ssr_c = q[PRV_RC];
    *dof_c = q[PRV_RC + 1];
    /* J^-1 = (tr k / 2) I - k. */
    sfit_i_sym_unpack(s->k_p, &y->kp);
    sfit_i_sym_unpack(s->k_c, &y->kc);
    tr = 0.5f * (s->k_p[0] + s->k_p[1] + s->k_p[2]);
    for (k = 0; k < 9; k++) {
        y->jp.m[k] = ((k % 4 == 0) ? tr : 0.0f) - y->kp.m[k];
    }
    tr = 0.5f * (s->k_c[0] + s->k_c[1] + s->k_c[2]);
    for (k = 0; k < 9; k++) {
        y->jc.m[k] = ((k % 4 == 0) ? tr : 0.0f) - y->kc.m[k];
    }
    return 1;
}

static float prv_quad(const sfit_mat3_t *m, const float v[3])
{
    float t[3];
    sfit_i_mat3_vec(m, v, t);
    return sfit_i_dot3(v, t);
}

/* Column k of an eigenvector matrix. */
static void prv_col(const sfit_mat3_t *v, int k, float out[3])
{
    out[0] = v->m[k];
    out[1] = v->m[3 + k];
    out[2] = v->m[6 + k];
}

/* out = m^+ restricted to eigen-columns 1 and 2: sum_k v_k v_k^T / w_k. */
static void prv_pinv2(const sfit_mat3_t *v, const sfit_vec3_t *w, sfit_mat3_t *out)
{
    int i, j, k;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            float sum = 0.0f;
            for (k = 1; k < 3; k++) {
                sum += v->m[3 * i + k] * v->m[3 * j + k] / w->v[k];
            }
            out->m[3 * i + j] = sum;
        }
    }
}

/* a := symmetric part of a. */
static void prv_symmetrise(sfit_mat3_t *a)
{
    float p[6];
    sfit_i_sym_pack(a, p);
    sfit_i_sym_unpack(p, a);
}

sfit_status_t sfit_pair_solve(const sfit_pair_t *s, sfit_pair_result_t *out)
{
    prv_sys_t y;
    sfit_pair_result_t res;
    sfit_mat3_t nm, sc, w_c, qinv, vec, tmp, tmp2, pmat, cmat, g, scinv;
    sfit_vec3_t lam;
    float ssr_p, ssr_c, dof_p, dof_c, rhs[3], cpp[3], ccc[3], n1[3], n2[3], axc[3];
    float ratio12 = 0.0f, z = 0.0f, hratio = 1.0f, cost, expect, len;
    uint32_t flags = 0u;
    sfit_pair_reason_t reason = SFIT_PAIR_REASON_NONE;
    sfit_pair_mode_t mode;
    int corrected, k, i;
    sfit_status_t st;
    const float hr = (s != NULL && s->cfg.hinge_ratio > 0.0f) ? s->cfg.hinge_ratio
                                                                 : PRV_HINGE_RATIO;
    const float mt = (s != NULL && s->cfg.max_trust > 0.0f) ? s->cfg.max_trust : PRV_MAX_TRUST;
    const float mm = (s != NULL && s->cfg.max_misfit > 0.0f) ? s->cfg.max_misfit
                                                                : PRV_MAX_MISFIT;
    const float at = (s != NULL && s->cfg.axis_tol > 0.0f) ? s->cfg.axis_tol : PRV_AXIS_TOL;
    const float wb = (s != NULL && s->cfg.wobble > 0.0f) ? s->cfg.wobble : PRV_WOBBLE;
    const uint32_t mf = (s != NULL && s->cfg.min_frames > 0u) ? s->cfg.min_frames
                                                               : PRV_MIN_FRAMES;

    if (s == NULL || out == NULL || !prv_state_ok(s)) {
        return SFIT_E_ARG;
    }
    if (s->frames < 3u) {
        return SFIT_E_TOO_FEW;
    }
    if (!prv_build(s, &y, &dof_p, &dof_c, &ssr_p, &ssr_c)) {
        return SFIT_E_RANGE;
    }
    memset(&res, 0, sizeof res);
    /* Marker variance of each cluster. */
    if (s->cfg.noise == SFIT_PAIR_NOISE_GIVEN) {
        y.var_p = s->cfg.marker_var;
        y.var_c = s->cfg.marker_var;
    } else {
        y.var_p = (dof_p > 0.0f) ? ssr_p / dof_p : -1.0f;
        y.var_c = (dof_c > 0.0f) ? ssr_c / dof_c : -1.0f;
        if (y.var_p < 0.0f && y.var_c < 0.0f) {
            y.var_p = 0.0f;
            y.var_c = 0.0f;
            flags |= (uint32_t)SFIT_PAIR_FLAG_NO_NOISE;
        } else if (y.var_p < 0.0f) {
            y.var_p = y.var_c;
        } else if (y.var_c < 0.0f) {
            y.var_c = y.var_p;
        }
    }
    for (k = 0; k < 9; k++) {
        y.kp.m[k] *= y.var_p;
        y.kc.m[k] *= y.var_c;
    }
    /* Noise inflation of S: N (K_p + Abar K_c Abar^T). */
    prv_sandwich(&y.abar, &y.kc, &tmp);
    for (k = 0; k < 9; k++) {
        nm.m[k] = y.n * (y.kp.m[k] + tmp.m[k]);
    }
    prv_symmetrise(&nm);
    /* Corrected system: S - N K_p - N Abar Q^-1 K_c Abar^T, Q = I - K_c;
     * right-hand side r' - N Abar Q^-1 K_c gbar'. */
    corrected = (s->cfg.method == SFIT_PAIR_METHOD_DEFAULT);
    {
        sfit_mat3_t q, l;
        for (k = 0; k < 9; k++) {
            q.m[k] = ((k % 4 == 0) ? 1.0f : 0.0f) - y.kc.m[k];
        }
        if (sfit_mat3_chol(&q, &l) != SFIT_OK) {
            return SFIT_E_RANGE; /* var_c J_c^-1 beyond 1 rad^2: not a rotation noise */
        }
        sfit_i_chol_inverse(&l, &qinv);
    }
    sfit_i_mat3_mul(&qinv, &y.kc, &w_c);
    prv_symmetrise(&w_c);
    prv_sandwich(&y.abar, &w_c, &tmp);
    sc = y.s;
    for (i = 0; i < 3; i++) {
        rhs[i] = y.r[i];
    }
    if (corrected) {
        float wg[3];
        for (k = 0; k < 9; k++) {
            sc.m[k] -= y.n * (y.kp.m[k] + tmp.m[k]);
        }
        prv_symmetrise(&sc);
        sfit_i_mat3_vec(&w_c, y.gbar, wg);
        for (i = 0; i < 3; i++) {
            rhs[i] -= y.n * sfit_i_dot3(&y.abar.m[3 * i], wg);
        }
    }
    /* Spread of the relative rotations. */
    {
        sfit_vec3_t ws;
        st = sfit_mat3_eig_sym(&y.s, &ws, NULL);
        if (st != SFIT_OK) {
            return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
        }
        if (!(ws.v[2] > PRV_MIN_SPREAD * y.n)) {
            return SFIT_E_DEGENERATE;
        }
    }
    st = sfit_mat3_eig_sym(&sc, &lam, &vec);
    if (st != SFIT_OK) {
        return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
    }
    prv_col(&vec, 0, n1);
    prv_col(&vec, 1, n2);
    {
        /* Decision statistics from the corrected eigenvalues. */
        const float nz1 = prv_quad(&nm, n1);
        const float l1c = corrected ? lam.v[0] : lam.v[0] - nz1;
        const float l2c = corrected ? lam.v[1] : lam.v[1] - prv_quad(&nm, n2);
        ratio12 = (l2c > 0.0f) ? l1c / l2c : 1.0f;
        if (nz1 > 0.0f) {
            z = SFIT_SQRTF(y.n) * l1c / nz1;
            /* the hinge model's residual rotation against the noise's */
            hratio = 1.0f + l1c / nz1;
        } else {
            z = (l1c > 0.0f) ? 1e30f : 0.0f;
        }
    }
    if (s->cfg.mode == SFIT_PAIR_MODE_AUTO) {
        mode = (ratio12 < hr) ? SFIT_PAIR_MODE_HINGE : SFIT_PAIR_MODE_BALL;
        if ((ratio12 >= hr / 3.0f && ratio12 < 3.0f * hr)
            || (mode == SFIT_PAIR_MODE_BALL && z < PRV_Z_BALL)) {
            flags |= (uint32_t)SFIT_PAIR_FLAG_AMBIGUOUS;
        }
    } else {
        mode = s->cfg.mode;
    }

    if (mode == SFIT_PAIR_MODE_BALL) {
        sfit_mat3_t l;
        const float den = prv_quad(&y.s, n1);
        res.trust_ratio = (den > 0.0f) ? prv_quad(&nm, n1) / den : 1.0f;
        if (sfit_mat3_chol(&sc, &l) != SFIT_OK) {
            if (!corrected) {
                return SFIT_E_DEGENERATE;
            }
            /* The correction took S below zero: the motion is too small for
             * the noise. Give plain SCoRE, flagged. */
            flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
            corrected = 0;
            sc = y.s;
            for (i = 0; i < 3; i++) {
                rhs[i] = y.r[i];
            }
            if (sfit_mat3_chol(&sc, &l) != SFIT_OK) {
                return SFIT_E_DEGENERATE;
            }
        }
        sfit_i_chol_solve(&l, rhs, cpp);
        sfit_i_chol_inverse(&l, &scinv);
        if (res.trust_ratio > mt) {
            flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
        }
    } else {
        const float den = prv_quad(&y.s, n2);
        res.trust_ratio = (den > 0.0f) ? prv_quad(&nm, n2) / den : 1.0f;
        if (!(lam.v[1] > 0.0f)) {
            /* Not even two directions are fixed: give plain SARA's subspace. */
            if (!corrected) {
                return SFIT_E_DEGENERATE;
            }
            flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
            corrected = 0;
            sc = y.s;
            for (i = 0; i < 3; i++) {
                rhs[i] = y.r[i];
            }
            st = sfit_mat3_eig_sym(&sc, &lam, &vec);
            if (st != SFIT_OK) {
                return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
            }
            if (!(lam.v[1] > 0.0f)) {
                return SFIT_E_DEGENERATE;
            }
            prv_col(&vec, 0, n1);
        }
        prv_pinv2(&vec, &lam, &scinv);
        sfit_i_mat3_vec(&scinv, rhs, cpp);
        if (res.trust_ratio > mt) {
            flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
        }
    }
    res.method = corrected ? SFIT_PAIR_METHOD_DEFAULT : SFIT_PAIR_METHOD_SCORE;
    /* Is the axis fixed? (A hinge's result; for a ball, about axis_p.) */
    {
        /* tan^2(at) (series, 1e-3 relative up to 30 degrees) against the
         * out-of-axis rotation seen and the one that cannot be seen. */
        const float a2 = at * at;
        const float tan2 = a2 * (1.0f + a2 * (2.0f / 3.0f + a2 * (17.0f / 45.0f
                                                            + a2 * (62.0f / 315.0f))));
        const float flex2 = lam.v[1] / y.n; /* flexion spread^2 (rad^2) */
        if (ratio12 > tan2 || wb * wb > tan2 * flex2) {
            flags |= (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE;
        }
    }
    /* The misfit: SCoRE's cost at the solution against its expectation. */
    cost = prv_quad(&y.s, cpp) - 2.0f * sfit_i_dot3(cpp, y.r) + y.hh;
    if (!(cost > 0.0f)) {
        cost = 0.0f;
    }
    /* Hinge: the point nearest the mid-point of the clusters. */
    {
        float cperp[3], b[3], proj;
        memcpy(cperp, cpp, sizeof cperp);
        for (i = 0; i < 3; i++) {
            b[i] = y.mid[i] - cperp[i];
        }
        proj = sfit_i_dot3(n1, b);
        if (mode == SFIT_PAIR_MODE_HINGE) {
            for (i = 0; i < 3; i++) {
                cpp[i] = cperp[i] + proj * n1[i];
            }
        }
        /* Child point: (I - K_c/2) Q^-1 (Abar^T c - gbar'), plain: Abar^T c - gbar'. */
        for (i = 0; i < 3; i++) {
            float t = 0.0f;
            for (k = 0; k < 3; k++) {
                t += y.abar.m[3 * k + i] * cpp[k];
            }
            ccc[i] = t - y.gbar[i];
            axc[i] = y.abar.m[i] * n1[0] + y.abar.m[3 + i] * n1[1] + y.abar.m[6 + i] * n1[2];
        }
        if (corrected) {
            float t[3];
            sfit_i_mat3_vec(&qinv, ccc, t);
            for (i = 0; i < 3; i++) {
                ccc[i] = t[i] - 0.5f * sfit_i_dot3(&y.kc.m[3 * i], t);
            }
        }
        if (!sfit_i_unit3(axc, &len)) {
            axc[0] = 1.0f;
            axc[1] = 0.0f;
            axc[2] = 0.0f;
        }
        /* Covariances. */
        prv_point_noise(&y, s, cpp, ccc, &pmat, &cmat);
        expect = (y.n - 2.0f) * (pmat.m[0] + pmat.m[4] + pmat.m[8] + cmat.m[0] + cmat.m[4]
                                 + cmat.m[8]);
        prv_gmat(&y, &pmat, &cmat, &g);
        prv_sandwich(&scinv, &g, &res.center_cov);
        {
            /* Axis: d n = -S^+ (d S) n, (d S) n = sum B xi, xi the noise of
             * B^T n: the same sandwich with P = var_p [n]J_p^-1[n]^T. */
            sfit_mat3_t pn, cn, gn;
            prv_cross_quad(n1, &y.jp, &pn);
            prv_cross_quad(axc, &y.jc, &cn);
            for (k = 0; k < 9; k++) {
                pn.m[k] *= y.var_p;
                cn.m[k] *= y.var_c;
            }
            {
                sfit_mat3_t pinv;
                prv_pinv2(&vec, &lam, &pinv);
                prv_gmat(&y, &pn, &cn, &gn);
                prv_sandwich(&pinv, &gn, &res.axis_cov);
            }
            if (mode == SFIT_PAIR_MODE_HINGE) {
                /* The point moves with the axis: d p = (a I + n b^T) d n. */
                for (i = 0; i < 3; i++) {
                    for (k = 0; k < 3; k++) {
                        tmp2.m[3 * i + k] = ((i == k) ? proj : 0.0f) + n1[i] * b[k];
                    }
                }
                prv_sandwich(&tmp2, &res.axis_cov, &tmp);
                for (k = 0; k < 9; k++) {
                    res.center_cov.m[k] += tmp.m[k];
                }
            }
        }
        if (corrected) {
            float t[3];
            for (i = 0; i < 3; i++) {
                t[i] = cpp[i] - 0.5f * sfit_i_dot3(&y.kp.m[3 * i], cpp);
            }
            memcpy(cpp, t, sizeof t);
        }
    }
    prv_symmetrise(&res.center_cov);
    prv_symmetrise(&res.axis_cov);
    res.misfit = (expect > 0.0f) ? cost / expect : 0.0f;
    {
        /* The joint model's residual larger than the registrations predict:
         * scale the centre's covariance by the ratio (Birge), the axis' by
         * the hinge model's own ratio (out-of-axis rotation is not noise).
         * The first-order covariance leaves out terms of relative size
         * trust_ratio (the noise of B times the equation noise): (1 + trust)
         * restores them (docs/pair.md#covariance). */
        const float f = ((res.misfit > 1.0f) ? res.misfit : 1.0f) * (1.0f + res.trust_ratio);
        const float fa = ((hratio > 1.0f) ? hratio : 1.0f) * (1.0f + res.trust_ratio);
        for (k = 0; k < 9; k++) {
            res.center_cov.m[k] *= f;
            res.axis_cov.m[k] *= fa;
        }
    }
    {
        sfit_vec3_t wa;
        if (sfit_mat3_eig_sym(&res.axis_cov, &wa, NULL) != SFIT_OK
            || PRV_CHI2_2_95 * wa.v[2] > at * at) {
            flags |= (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE;
        }
    }
    if (mode != SFIT_PAIR_MODE_HINGE) {
        memset(&res.axis_cov, 0, sizeof res.axis_cov);
    }
    if (expect > 0.0f && res.misfit > mm) {
        flags |= (uint32_t)SFIT_PAIR_FLAG_MISFIT;
    }
    /* Axis sign: largest component positive; the child axis follows. */
    {
        int im = 0;
        for (i = 1; i < 3; i++) {
            if (SFIT_FABSF(n1[i]) > SFIT_FABSF(n1[im])) {
                im = i;
            }
        }
        if (n1[im] < 0.0f) {
            for (i = 0; i < 3; i++) {
                n1[i] = -n1[i];
                axc[i] = -axc[i];
            }
        }
    }
    for (i = 0; i < 3; i++) {
        res.center_p.v[i] = cpp[i] + s->cen_p.v[i];
        res.center_c.v[i] = ccc[i] + s->cen_c.v[i];
        res.axis_p.v[i] = n1[i];
        res.axis_c.v[i] = axc[i];
        res.eigenvalues.v[i] = lam.v[i] / y.n;
    }
    res.mode = mode;
    res.rms = SFIT_SQRTF(cost / y.n);
    res.marker_var_p = y.var_p;
    res.marker_var_c = y.var_c;
    res.marker_var = 0.5f * (y.var_p + y.var_c);
    res.noise = s->cfg.noise;
    res.frames = s->frames;
    if (s->frames < mf) {
        flags |= (uint32_t)SFIT_FLAG_FEW_SAMPLES;
    }
    /* Reason, by priority. */
    if ((flags & (uint32_t)SFIT_FLAG_FEW_SAMPLES) != 0u) {
        reason = SFIT_PAIR_REASON_FEW_FRAMES;
    } else if ((flags & (uint32_t)SFIT_PAIR_FLAG_NO_NOISE) != 0u) {
        reason = SFIT_PAIR_REASON_NO_NOISE;
    } else if ((flags & (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION) != 0u) {
        reason = SFIT_PAIR_REASON_SMALL_MOTION;
    } else if ((flags & (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE) != 0u
               && mode == SFIT_PAIR_MODE_HINGE) {
        reason = SFIT_PAIR_REASON_AXIS_FREE;
    } else if ((flags & (uint32_t)SFIT_PAIR_FLAG_AMBIGUOUS) != 0u) {
        reason = SFIT_PAIR_REASON_AMBIGUOUS;
    } else if ((flags & (uint32_t)SFIT_PAIR_FLAG_MISFIT) != 0u) {
        reason = SFIT_PAIR_REASON_MISFIT;
    }
    if (reason != SFIT_PAIR_REASON_NONE) {
        flags |= (uint32_t)SFIT_FLAG_UNTRUSTED;
    }
    res.flags = flags;
    res.reason = reason;
    /* Everything written must be finite. */
    {
        int ok = sfit_i_finite3(res.center_p.v) && sfit_i_finite3(res.center_c.v)
                 && sfit_i_finite3(res.axis_p.v) && sfit_i_finite3(res.axis_c.v)
                 && sfit_i_finite3(res.eigenvalues.v) && sfit_i_isfinite(res.trust_ratio)
                 && sfit_i_isfinite(res.misfit) && sfit_i_isfinite(res.rms)
                 && sfit_i_isfinite(res.marker_var);
        for (k = 0; k < 9; k++) {
            ok = ok && sfit_i_isfinite(res.center_cov.m[k]) && sfit_i_isfinite(res.axis_cov.m[k]);
        }
        if (!ok) {
            return SFIT_E_RANGE;
        }
    }
    *out = res;
    return SFIT_OK;
}
