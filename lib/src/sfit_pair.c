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
 * large raw sums. Layout of the sums (SFIT_PAIR_NSUM = 92):
 *   0..8    sum B (row-major)        9..11  sum h
 *   12..56  sum vec(B) vec(B)^T, packed upper triangle of the 9x9 (45)
 *   57..83  sum vec(B) h^T (9x3, row 3i+j, column k: B_ij h_k)
 *   84      sum |h|^2                85..87 sum e
 *   88, 89  parent sum |res|^2, sum (3 used - 6)
 *   90, 91  child sum |res|^2, sum (3 used - 6)
 * The 9x3 moment gives sum B W h for any constant weight W at solve time
 * (the weighted default, docs/pair.md#weighting); its contraction with I is
 * SCoRE's right-hand side sum B h.
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
/* Hinge wobble: an out-of-axis rotation is seen when the corrected lambda_1
 * passes this many of its noise standard deviations (nz1 / sqrt(N)); its
 * part in step with the flexion, which no fit can see, is taken as up to
 * twice the seen part in amplitude (PRV_WOBBLE_K times in variance). */
#define PRV_WOBBLE_Z 2.0f
#define PRV_WOBBLE_K 4.0f
/* cfg.wobble 0: the in-step wobble the AXIS_FREE range test assumes, a
 * knee's 2-5 degrees (2.5 degrees rms; it decides only whether the flexion
 * range can tell the axis from such a wobble), and the floor under the
 * model part, 0.5 degrees rms: what a real knee hides below its noise (on
 * the shared knee trial the block jackknife of the centre needs it). */
#define PRV_WOBBLE_RANGE 0.0436332f
#define PRV_WOBBLE_FLOOR 0.00872665f
#define PRV_MIN_FRAMES 30u
/* Ball: lambda_1 of the corrected S must be this many of its noise
 * standard deviations above zero for the centre to be fixed by the data. */
#define PRV_Z_BALL 5.0f
/* chi^2(2 dof) 95 % quantile: the 95 % cone of a unit axis. */
#define PRV_CHI2_2_95 5.991465f
/* Skin motion: theta's directions whose spread is below this share of the
 * largest are left out of the regression (the motion does not excite them;
 * there theta is the rotation noise). */
#define PRV_STA_EXCITED 0.03f
/* No relative rotation: the largest eigenvalue of S / frames below this
 * (rad^2) is no motion at all. */
#define PRV_MIN_SPREAD 1e-12f

/* Sum layout. */
/* sum B starts the layout (index 0): it is indexed directly. */
#define PRV_SH 9
#define PRV_T 12
#define PRV_SBH 57
#define PRV_SHH 84
#define PRV_SE 85
#define PRV_RP 88
#define PRV_RC 90

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
    if ((uint32_t)c->method > (uint32_t)SFIT_PAIR_METHOD_UNWEIGHTED
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
    int a;

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
    sfit_i_spread(cl->pos, cl->count, cen->v, &jm);
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
            v[k] = b[k];
        }
        for (k = 0; k < 3; k++) {
            h[k] = g[k] - s->g_ref[k];
        }
        for (k = 0; k < 3; k++) {
            v[PRV_SH + k] = h[k];
            v[PRV_SE + k] = d[k] - s->d_ref[k];
        }
        for (i = 0; i < 9; i++) {
            for (j = 0; j < 3; j++) {
                v[PRV_SBH + 3 * i + j] = b[i] * h[j];
            }
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
    float xh[27];       /* centred 9x3 moment sum vec(B) h^T (raw h, not centroid coordinates) */
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

/* out(a, b) = sum_cd X_cd T(r a + s c, r b + s d), r s = 3: (r, s) = (3, 1)
 * gives sum B X B^T (a, b), (1, 3) gives sum B^T X B (a, b). */
static void prv_contract(const float tc[45], const sfit_mat3_t *x, int r, int s,
                         sfit_mat3_t *out)
{
    int a, b, c, d;
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            float sum = 0.0f;
            for (c = 0; c < 3; c++) {
                for (d = 0; d < 3; d++) {
                    sum += x->m[3 * c + d] * tc[prv_tidx(r * a + s * c, r * b + s * d)];
                }
            }
            out->m[3 * a + b] = sum;
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
    prv_contract(y->tc, p, 1, 3, &t3); /* sum B^T P B */
    prv_sandwich(&y->abar, &t3, &t2);
    prv_contract(y->tc, c, 3, 1, &t3); /* sum B C B^T */
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
            y->tc[t] = q[PRV_T + t] - q[i] * q[j] / y->n;
        }
    }
    {
        const sfit_mat3_t eye = {{1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f}};
        prv_contract(y->tc, &eye, 3, 1, &y->s);
    }
    for (k = 0; k < 9; k++) {
        y->abar.m[k] = s->a_ref[k] + q[k] / y->n;
    }
    for (i = 0; i < 9; i++) {
        for (j = 0; j < 3; j++) {
            y->xh[3 * i + j] = q[PRV_SBH + 3 * i + j] - q[i] * q[PRV_SH + j] / y->n;
        }
    }
    for (i = 0; i < 3; i++) {
        r0[i] = y->xh[9 * i] + y->xh[9 * i + 4] + y->xh[9 * i + 8];
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

/* Working state of one solve (the phases below share it). */
typedef struct prv_ctx {
    prv_sys_t y;
    sfit_pair_result_t res;
    sfit_mat3_t nm, sc, w_c, qinv, vec, scinv;
    sfit_vec3_t lam;
    float rhs[3], cpp[3], ccc[3], n1[3], n2[3], axc[3], b[3];
    float ratio12, z, cost, expect, proj;
    uint32_t flags;
    sfit_pair_mode_t mode;
    int corrected;
    int weighted;       /* the ball centre is the weighted one (prv_weighted) */
    float sta_excess;   /* ball: angle-correlated residual beyond the noise (sum |r|^2) */
    float l1c;          /* corrected smallest eigenvalue of S (out-of-axis rotation) */
    float nz1;          /* its noise expectation (the correction along n1) */
    sfit_mat3_t dpn;    /* hinge: d point / d axis */
    sfit_mat3_t w;      /* its weight (child frame, normalised to trace 3 of W^-1) */
} prv_ctx_t;

/* Status of an eigen-decomposition as the solve reports it. */
static sfit_status_t prv_eig_status(sfit_status_t st)
{
    return (st == SFIT_E_NONFINITE) ? SFIT_E_RANGE : st;
}

/* Marker variance of each cluster; K_p, K_c scaled by it. */
static void prv_noise(const sfit_pair_t *s, prv_ctx_t *c, float ssr_p, float dof_p, float ssr_c,
                      float dof_c)
{
    prv_sys_t *y = &c->y;
    int k;
    if (s->cfg.noise == SFIT_PAIR_NOISE_GIVEN) {
        y->var_p = s->cfg.marker_var;
        y->var_c = s->cfg.marker_var;
    } else {
        y->var_p = (dof_p > 0.0f) ? ssr_p / dof_p : -1.0f;
        y->var_c = (dof_c > 0.0f) ? ssr_c / dof_c : -1.0f;
        if (y->var_p < 0.0f && y->var_c < 0.0f) {
            y->var_p = 0.0f;
            y->var_c = 0.0f;
            c->flags |= (uint32_t)SFIT_PAIR_FLAG_NO_NOISE;
        } else if (y->var_p < 0.0f) {
            y->var_p = y->var_c;
        } else if (y->var_c < 0.0f) {
            y->var_c = y->var_p;
        } else {
            /* both clusters measured */
        }
    }
    for (k = 0; k < 9; k++) {
        y->kp.m[k] *= y->var_p;
        y->kc.m[k] *= y->var_c;
    }
}

/* The noise inflation N (K_p + Abar K_c Abar^T) and the system to solve:
 * corrected, S - N K_p - N Abar Q^-1 K_c Abar^T, Q = I - K_c, right-hand
 * side r' - N Abar Q^-1 K_c gbar'; plain, S and r'. */
static sfit_status_t prv_system(prv_ctx_t *c)
{
    prv_sys_t *y = &c->y;
    sfit_mat3_t tmp, q, l;
    int k, i;
    prv_sandwich(&y->abar, &y->kc, &tmp);
    for (k = 0; k < 9; k++) {
        c->nm.m[k] = y->n * (y->kp.m[k] + tmp.m[k]);
        q.m[k] = ((k % 4 == 0) ? 1.0f : 0.0f) - y->kc.m[k];
    }
    prv_symmetrise(&c->nm);
    if (sfit_mat3_chol(&q, &l) != SFIT_OK) {
        return SFIT_E_RANGE; /* var_c J_c^-1 beyond 1 rad^2: not a rotation noise */
    }
    sfit_i_chol_inverse(&l, &c->qinv);
    sfit_i_mat3_mul(&c->qinv, &y->kc, &c->w_c);
    prv_symmetrise(&c->w_c);
    prv_sandwich(&y->abar, &c->w_c, &tmp);
    c->sc = y->s;
    for (i = 0; i < 3; i++) {
        c->rhs[i] = y->r[i];
    }
    if (c->corrected) {
        float wg[3];
        for (k = 0; k < 9; k++) {
            c->sc.m[k] -= y->n * (y->kp.m[k] + tmp.m[k]);
        }
        prv_symmetrise(&c->sc);
        sfit_i_mat3_vec(&c->w_c, y->gbar, wg);
        for (i = 0; i < 3; i++) {
            c->rhs[i] -= y->n * sfit_i_dot3(&y->abar.m[3 * i], wg);
        }
    }
    return SFIT_OK;
}

/* Eigen-decomposition of the system, the decision statistics (from the
 * corrected eigenvalues) and the mode. */
static sfit_status_t prv_decide(const sfit_pair_t *s, prv_ctx_t *c, float hr)
{
    prv_sys_t *y = &c->y;
    sfit_vec3_t ws;
    sfit_status_t st = sfit_mat3_eig_sym(&y->s, &ws, NULL);
    if (st != SFIT_OK) {
        return prv_eig_status(st);
    }
    if (!(ws.v[2] > PRV_MIN_SPREAD * y->n)) {
        return SFIT_E_DEGENERATE; /* the relative rotation never changed */
    }
    st = sfit_mat3_eig_sym(&c->sc, &c->lam, &c->vec);
    if (st != SFIT_OK) {
        return prv_eig_status(st);
    }
    prv_col(&c->vec, 0, c->n1);
    prv_col(&c->vec, 1, c->n2);
    {
        const float nz1 = prv_quad(&c->nm, c->n1);
        const float l1c = c->corrected ? c->lam.v[0] : c->lam.v[0] - nz1;
        const float l2c = c->corrected ? c->lam.v[1] : c->lam.v[1] - prv_quad(&c->nm, c->n2);
        c->l1c = l1c;
        c->nz1 = nz1;
        c->ratio12 = (l2c > 0.0f) ? l1c / l2c : 1.0f;
        if (nz1 > 0.0f) {
            c->z = SFIT_SQRTF(y->n) * l1c / nz1;
        } else {
            c->z = (l1c > 0.0f) ? 1e30f : 0.0f;
        }
    }
    if (s->cfg.mode == SFIT_PAIR_MODE_AUTO) {
        c->mode = (c->ratio12 < hr) ? SFIT_PAIR_MODE_HINGE : SFIT_PAIR_MODE_BALL;
        if ((c->ratio12 >= hr / 3.0f && c->ratio12 < 3.0f * hr)
            || (c->mode == SFIT_PAIR_MODE_BALL && c->z < PRV_Z_BALL)) {
            c->flags |= (uint32_t)SFIT_PAIR_FLAG_AMBIGUOUS;
        }
    } else {
        c->mode = s->cfg.mode;
    }
    return SFIT_OK;
}

/* Back to the plain system (the correction took it below zero). */
static void prv_plain(prv_ctx_t *c)
{
    int i;
    c->flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
    c->corrected = 0;
    c->sc = c->y.s;
    for (i = 0; i < 3; i++) {
        c->rhs[i] = c->y.r[i];
    }
}

/* Ball: Cholesky solve of the system (plain SCoRE when the corrected one is
 * not positive definite). */
static sfit_status_t prv_solve_ball(prv_ctx_t *c, float mt)
{
    sfit_mat3_t l;
    const float den = prv_quad(&c->y.s, c->n1);
    c->res.trust_ratio = (den > 0.0f) ? prv_quad(&c->nm, c->n1) / den : 1.0f;
    if (sfit_mat3_chol(&c->sc, &l) != SFIT_OK) {
        if (!c->corrected) {
            return SFIT_E_DEGENERATE;
        }
        prv_plain(c);
        if (sfit_mat3_chol(&c->sc, &l) != SFIT_OK) {
            return SFIT_E_DEGENERATE;
        }
    }
    sfit_i_chol_solve(&l, c->rhs, c->cpp);
    sfit_i_chol_inverse(&l, &c->scinv);
    if (c->res.trust_ratio > mt) {
        c->flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
    }
    return SFIT_OK;
}

/* E[[w]x M [w]x^T] for w ~ (0, sig), M symmetric:
 * (tr sig tr M - tr(sig M)) I - tr M sig - tr sig M + sig M + M sig. */
static void prv_emat(const sfit_mat3_t *sig, const sfit_mat3_t *m, sfit_mat3_t *out)
{
    sfit_mat3_t sm;
    const float ts = sig->m[0] + sig->m[4] + sig->m[8], tm = m->m[0] + m->m[4] + m->m[8];
    float tsm;
    int i, j;
    sfit_i_mat3_mul(sig, m, &sm);
    tsm = sm.m[0] + sm.m[4] + sm.m[8];
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            out->m[3 * i + j] = ((i == j) ? ts * tm - tsm : 0.0f) - tm * sig->m[3 * i + j]
                                - ts * m->m[3 * i + j] + sm.m[3 * i + j] + sm.m[3 * j + i];
        }
    }
}

/* Z - X for Z = D^-1(X), D(Z) = E[exp([w]x) Z exp([w]x)^T]
 * = Z - (K Z + Z K) / 2 + E[[w]x Z [w]x^T] (K = tr sig I - sig): two
 * fixed-point steps Z <- X + Z - D(Z) from Z = X; only small terms are
 * formed. */
static void prv_dinv_delta(const sfit_mat3_t *k, const sfit_mat3_t *sig, const sfit_mat3_t *x,
                           sfit_mat3_t *out)
{
    sfit_mat3_t z, kz, e;
    int it, i;
    z = *x;
    memset(out, 0, sizeof *out);
    for (it = 0; it < 2; it++) {
        sfit_i_mat3_mul(k, &z, &kz);
        prv_emat(sig, &z, &e);
        for (i = 0; i < 9; i++) {
            const int t = 3 * (i % 3) + i / 3;
            out->m[i] = 0.5f * (kz.m[i] + kz.m[t]) - e.m[i];
        }
        for (i = 0; i < 9; i++) {
            z.m[i] = x->m[i] + out->m[i];
        }
    }
}

/* Noise covariance (child frame) of the joint model's residual of one frame
 * at the point (xp, xc), averaged over the frames:
 * Abar^T P Abar + (sum B^T P B) / N + C (docs/pair.md#weighting). */
static void prv_resid_cov(const prv_sys_t *y, const sfit_mat3_t *pm, const sfit_mat3_t *cm,
                          sfit_mat3_t *out)
{
    sfit_mat3_t at, t;
    int i;
    for (i = 0; i < 9; i++) {
        at.m[i] = y->abar.m[3 * (i % 3) + i / 3];
    }
    prv_sandwich(&at, pm, out);
    prv_contract(y->tc, pm, 1, 3, &t);
    for (i = 0; i < 9; i++) {
        out->m[i] += t.m[i] / y->n + cm->m[i];
    }
    prv_symmetrise(out);
}

/* The weighted ball centre (the default): the first estimate's residual
 * covariance, averaged over the frames (child frame), gives a constant
 * weight W; the corrected weighted Schur system
 *   [D_p^-1(sum B V B^T) + N (D_p^-1(X) - X + Abar (V - W') Abar^T - (P^-1 Y P^-1 - Y))] c_p
 *     = P^-1 [sum B V h' + N Abar (V - W') gbar'],
 * V = D_c^-1(W), W' = C^-1 W C^-1, P = I - K_p/2, C = I - K_c/2,
 * X = Abar V Abar^T, Y = Abar W' Abar^T, is formed from the 9x9 and 9x3
 * moments (docs/pair.md#weighting). cpp, scinv and w are replaced when it
 * is positive definite; 0 (nothing changed) otherwise. */
static SFIT_I_NOINLINE int prv_weighted(const sfit_pair_t *s, prv_ctx_t *c, float mm)
{
    prv_sys_t *y = &c->y;
    sfit_mat3_t pm, cm, sig, w, l, sgp, sgc, v, vw, t1, t2, m, e;
    float xc[3], rv[3], rhs[3], cp[3], tr;
    int i, j, k;
    for (i = 0; i < 3; i++) {
        xc[i] = y->abar.m[i] * c->cpp[0] + y->abar.m[3 + i] * c->cpp[1]
                + y->abar.m[6 + i] * c->cpp[2] - y->gbar[i];
    }
    prv_point_noise(y, s, c->cpp, xc, &pm, &cm);
    /* The weights are the marker noise's: when the joint model's residual at
     * the first estimate is far above what that noise explains (the MISFIT
     * test of prv_scale), the residual is not noise and the frames are not
     * weighted. */
    {
        const float cost = prv_quad(&y->s, c->cpp) - 2.0f * sfit_i_dot3(c->cpp, y->r) + y->hh;
        const float expect = (y->n - 2.0f)
                             * (pm.m[0] + pm.m[4] + pm.m[8] + cm.m[0] + cm.m[4] + cm.m[8]);
        if (!(expect > 0.0f) || !(cost <= mm * expect)) {
            return 0;
        }
    }
    prv_resid_cov(y, &pm, &cm, &sig);
    tr = sig.m[0] + sig.m[4] + sig.m[8];
    if (!(tr > 0.0f) || !sfit_i_isfinite(tr)) {
        return 0;
    }
    for (i = 0; i < 9; i++) {
        sig.m[i] *= 3.0f / tr;
    }
    if (sfit_mat3_chol(&sig, &l) != SFIT_OK) {
        return 0;
    }
    sfit_i_chol_inverse(&l, &w);
    prv_symmetrise(&w);
    for (i = 0; i < 9; i++) {
        sgp.m[i] = y->var_p * y->jp.m[i];
        sgc.m[i] = y->var_c * y->jc.m[i];
    }
    /* V - W' = (D_c^-1(W) - W) - (F W + W F + F W F), F = C^-1 K_c / 2. */
    prv_dinv_delta(&y->kc, &sgc, &w, &vw);
    for (i = 0; i < 9; i++) {
        v.m[i] = w.m[i] + vw.m[i];
        t1.m[i] = ((i % 4 == 0) ? 1.0f : 0.0f) - 0.5f * y->kc.m[i];
    }
    if (sfit_mat3_chol(&t1, &l) != SFIT_OK) {
        return 0;
    }
    sfit_i_chol_inverse(&l, &t2);
    for (i = 0; i < 9; i++) {
        t1.m[i] = 0.5f * y->kc.m[i];
    }
    sfit_i_mat3_mul(&t2, &t1, &e); /* F */
    sfit_i_mat3_mul(&e, &w, &t1);  /* F W */
    sfit_i_mat3_mul(&t1, &e, &t2); /* F W F^T (F W F, K_c and C commute) */
    for (i = 0; i < 9; i++) {
        const int t = 3 * (i % 3) + i / 3;
        vw.m[i] -= t1.m[i] + t1.m[t] + t2.m[i];
    }
    prv_symmetrise(&vw);
    /* Matrix: sum B V B^T and D_p^-1 of it; the N-terms. */
    prv_contract(y->tc, &v, 3, 1, &m);
    prv_symmetrise(&m);
    prv_dinv_delta(&y->kp, &sgp, &m, &t1);
    for (i = 0; i < 9; i++) {
        m.m[i] += t1.m[i];
    }
    {
        sfit_mat3_t x, dy;
        prv_sandwich(&y->abar, &v, &x);
        prv_dinv_delta(&y->kp, &sgp, &x, &t1); /* D_p^-1(X) - X */
        prv_sandwich(&y->abar, &vw, &t2);      /* X - Y */
        for (i = 0; i < 9; i++) {
            x.m[i] -= t2.m[i]; /* Y */
        }
        /* P^-1 Y P^-1 - Y = E Y + Y E^T + E Y E^T, E = P^-1 K_p / 2. */
        for (i = 0; i < 9; i++) {
            l.m[i] = ((i % 4 == 0) ? 1.0f : 0.0f) - 0.5f * y->kp.m[i];
        }
        {
            sfit_mat3_t lc, pinv, kh;
            if (sfit_mat3_chol(&l, &lc) != SFIT_OK) {
                return 0;
            }
            sfit_i_chol_inverse(&lc, &pinv);
            for (i = 0; i < 9; i++) {
                kh.m[i] = 0.5f * y->kp.m[i];
            }
            sfit_i_mat3_mul(&pinv, &kh, &e);
        }
        sfit_i_mat3_mul(&e, &x, &l);
        prv_sandwich(&e, &x, &dy);
        for (i = 0; i < 9; i++) {
            const int t = 3 * (i % 3) + i / 3;
            dy.m[i] += l.m[i] + l.m[t];
        }
        for (i = 0; i < 9; i++) {
            m.m[i] += y->n * (t1.m[i] + t2.m[i] - dy.m[i]);
        }
    }
    prv_symmetrise(&m);
    /* Right-hand side: sum B V h (centred) - (sum B V B^T) cen_p + N Abar (V - W') gbar'. */
    for (i = 0; i < 3; i++) {
        float sum = 0.0f;
        for (j = 0; j < 3; j++) {
            for (k = 0; k < 3; k++) {
                sum += v.m[3 * j + k] * y->xh[3 * (3 * i + j) + k];
            }
        }
        rv[i] = sum;
    }
    prv_contract(y->tc, &v, 3, 1, &t1);
    sfit_i_mat3_vec(&t1, s->cen_p.v, cp);
    sfit_i_mat3_vec(&vw, y->gbar, xc);
    for (i = 0; i < 3; i++) {
        rv[i] += y->n * sfit_i_dot3(&y->abar.m[3 * i], xc) - cp[i];
    }
    sfit_i_mat3_vec(&e, rv, rhs); /* P^-1 = I + E */
    for (i = 0; i < 3; i++) {
        rhs[i] += rv[i];
    }
    if (sfit_mat3_chol(&m, &l) != SFIT_OK) {
        return 0;
    }
    sfit_i_chol_solve(&l, rhs, cp);
    /* back to the unknown of the plain pipeline: u = P^-1 c_p */
    sfit_i_mat3_vec(&e, cp, xc);
    for (i = 0; i < 3; i++) {
        xc[i] += cp[i];
    }
    if (!sfit_i_finite3(xc)) {
        return 0;
    }
    memcpy(c->cpp, xc, sizeof xc);
    sfit_i_chol_inverse(&l, &c->scinv);
    c->w = w;
    c->weighted = 1;
    return 1;
}

/* Hinge: the pseudo-inverse over eigenvalues 2 and 3 (plain SARA's
 * subspace when the corrected second eigenvalue is not positive). */
static sfit_status_t prv_solve_hinge(prv_ctx_t *c, float mt)
{
    const float den = prv_quad(&c->y.s, c->n2);
    c->res.trust_ratio = (den > 0.0f) ? prv_quad(&c->nm, c->n2) / den : 1.0f;
    if (!(c->lam.v[1] > 0.0f)) {
        sfit_status_t st;
        if (!c->corrected) {
            return SFIT_E_DEGENERATE;
        }
        prv_plain(c);
        st = sfit_mat3_eig_sym(&c->sc, &c->lam, &c->vec);
        if (st != SFIT_OK) {
            return prv_eig_status(st);
        }
        if (!(c->lam.v[1] > 0.0f)) {
            return SFIT_E_DEGENERATE;
        }
        prv_col(&c->vec, 0, c->n1);
    }
    prv_pinv2(&c->vec, &c->lam, &c->scinv);
    sfit_i_mat3_vec(&c->scinv, c->rhs, c->cpp);
    if (c->res.trust_ratio > mt) {
        c->flags |= (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION;
    }
    return SFIT_OK;
}

/* Is the axis fixed? tan^2(at) (series, 1e-3 relative up to 30 degrees)
 * against the out-of-axis rotation seen and the one that cannot be seen
 * (a wobble wb in step with a flexion of spread sqrt(lambda_2) tilts the
 * axis by atan(wb / spread): a range test, the cone is prv_scale's). */
static void prv_axis_seen(prv_ctx_t *c, float at, float wb)
{
    const float a2 = at * at;
    const float tan2 =
        a2 * (1.0f + a2 * (2.0f / 3.0f + a2 * (17.0f / 45.0f + a2 * (62.0f / 315.0f))));
    const float flex2 = c->lam.v[1] / c->y.n; /* flexion spread^2 (rad^2) */
    if (c->ratio12 > tan2 || wb * wb > tan2 * flex2) {
        c->flags |= (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE;
    }
}

/* The SCoRE cost at the solution; the hinge point nearest the mid-point of
 * the clusters; the child point and axis. */
static void prv_points(prv_ctx_t *c)
{
    prv_sys_t *y = &c->y;
    float cperp[3], len;
    int i, k;
    c->cost = prv_quad(&y->s, c->cpp) - 2.0f * sfit_i_dot3(c->cpp, y->r) + y->hh;
    if (!(c->cost > 0.0f)) {
        c->cost = 0.0f;
    }
    memcpy(cperp, c->cpp, sizeof cperp);
    for (i = 0; i < 3; i++) {
        c->b[i] = y->mid[i] - cperp[i];
    }
    c->proj = sfit_i_dot3(c->n1, c->b);
    if (c->mode == SFIT_PAIR_MODE_HINGE) {
        for (i = 0; i < 3; i++) {
            c->cpp[i] = cperp[i] + c->proj * c->n1[i];
        }
    }
    /* Child point: (I - K_c/2) Q^-1 (Abar^T c - gbar'), plain: Abar^T c - gbar'. */
    for (i = 0; i < 3; i++) {
        float t = 0.0f;
        for (k = 0; k < 3; k++) {
            t += y->abar.m[3 * k + i] * c->cpp[k];
        }
        c->ccc[i] = t - y->gbar[i];
        c->axc[i] = y->abar.m[i] * c->n1[0] + y->abar.m[3 + i] * c->n1[1]
                    + y->abar.m[6 + i] * c->n1[2];
    }
    if (c->corrected) {
        float t[3];
        sfit_i_mat3_vec(&c->qinv, c->ccc, t);
        for (i = 0; i < 3; i++) {
            c->ccc[i] = t[i] - 0.5f * sfit_i_dot3(&y->kc.m[3 * i], t);
        }
    }
    if (!sfit_i_unit3(c->axc, &len)) {
        c->axc[0] = 1.0f;
        c->axc[1] = 0.0f;
        c->axc[2] = 0.0f;
    }
}

/* The weighted centre's right-hand side covariance, sum B W (A^T P A + C) W B^T:
 * the isotropic part p I of P exactly (A^T A = I: p sum B W W B^T), the rest
 * at the mean rotation (Abar^T P' Abar + sum B^T P' B / N, P' = P - p I). */
static void prv_gmat_weighted(const prv_sys_t *y, const sfit_mat3_t *w, const sfit_mat3_t *p,
                              const sfit_mat3_t *cm, sfit_mat3_t *out)
{
    sfit_mat3_t pa, sig, t;
    const float piso = (p->m[0] + p->m[4] + p->m[8]) / 3.0f;
    int i;
    pa = *p;
    for (i = 0; i < 3; i++) {
        pa.m[4 * i] -= piso;
    }
    prv_resid_cov(y, &pa, cm, &sig);
    for (i = 0; i < 3; i++) {
        sig.m[4 * i] += piso;
    }
    prv_sandwich(w, &sig, &t);
    prv_symmetrise(&t);
    prv_contract(y->tc, &t, 3, 1, out);
    prv_symmetrise(out);
}

/* Covariances of the centre and the axis (docs/pair.md#covariance), the
 * expected cost; then the corrected centre's (I - K_p/2). */
static SFIT_I_NOINLINE void prv_covariances(const sfit_pair_t *s, prv_ctx_t *c)
{
    prv_sys_t *y = &c->y;
    sfit_mat3_t pmat, cmat, g, pn, cn, pinv;
    int i, k;
    prv_point_noise(y, s, c->cpp, c->ccc, &pmat, &cmat);
    c->expect = (y->n - 2.0f)
                * (pmat.m[0] + pmat.m[4] + pmat.m[8] + cmat.m[0] + cmat.m[4] + cmat.m[8]);
    if (c->weighted) {
        prv_gmat_weighted(y, &c->w, &pmat, &cmat, &g);
    } else {
        prv_gmat(y, &pmat, &cmat, &g);
    }
    prv_sandwich(&c->scinv, &g, &c->res.center_cov);
    /* Axis: d n = -S^+ (d S) n, (d S) n = sum B xi, xi the noise of B^T n:
     * the same sandwich with P = var_p [n]J_p^-1[n]^T. */
    prv_cross_quad(c->n1, &y->jp, &pn);
    prv_cross_quad(c->axc, &y->jc, &cn);
    for (k = 0; k < 9; k++) {
        pn.m[k] *= y->var_p;
        cn.m[k] *= y->var_c;
    }
    prv_pinv2(&c->vec, &c->lam, &pinv);
    prv_gmat(y, &pn, &cn, &g);
    prv_sandwich(&pinv, &g, &c->res.axis_cov);
    if (c->mode == SFIT_PAIR_MODE_HINGE) {
        /* The point moves with the axis: d p = (a I + n b^T) d n. */
        for (i = 0; i < 3; i++) {
            for (k = 0; k < 3; k++) {
                pinv.m[3 * i + k] = ((i == k) ? c->proj : 0.0f) + c->n1[i] * c->b[k];
            }
        }
        c->dpn = pinv;
        prv_sandwich(&pinv, &c->res.axis_cov, &g);
        for (k = 0; k < 9; k++) {
            c->res.center_cov.m[k] += g.m[k];
        }
    }
    if (c->corrected) {
        float t[3];
        for (i = 0; i < 3; i++) {
            t[i] = c->cpp[i] - 0.5f * sfit_i_dot3(&y->kp.m[3 * i], c->cpp);
        }
        memcpy(c->cpp, t, sizeof t);
    }
    prv_symmetrise(&c->res.center_cov);
    prv_symmetrise(&c->res.axis_cov);
}

/* out = [x]x m. */
static void prv_cross_mul(const float x[3], const sfit_mat3_t *m, sfit_mat3_t *out)
{
    const float cx[9] = {0.0f, -x[2], x[1], x[2], 0.0f, -x[0], -x[1], x[0], 0.0f};
    const sfit_mat3_t c = {{cx[0], cx[1], cx[2], cx[3], cx[4], cx[5], cx[6], cx[7], cx[8]}};
    sfit_i_mat3_mul(&c, m, out);
}

/* E[beta beta^T] of beta_a = X_bd - X_db ((a, b, d) cyclic) for X with
 * E[X_pq X_p'q'] = C_pp' S_qq':
 * C_bb' S_dd' - C_bd' S_db' - C_db' S_bd' + C_dd' S_bb'. */
static void prv_bcov(const sfit_mat3_t *cm, const sfit_mat3_t *sg, sfit_mat3_t *out)
{
    int a, i;
    for (a = 0; a < 3; a++) {
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        for (i = 0; i < 3; i++) {
            const int b2 = (i + 1) % 3, d2 = (i + 2) % 3;
            out->m[3 * a + i] = cm->m[3 * b + b2] * sg->m[3 * d + d2]
                                - cm->m[3 * b + d2] * sg->m[3 * d + b2]
                                - cm->m[3 * d + b2] * sg->m[3 * b + d2]
                                + cm->m[3 * d + d2] * sg->m[3 * b + b2];
        }
    }
}

/* Ball: skin motion linear in the joint angle (docs/pair.md#model-error).
 * The joint model's residual in the child frame, r = A^T x - c_c - g, is
 * regressed on the relative rotation theta = vee(skew(Abar^T (A - Abar)))
 * (linear in A: the 9x9 and 9x3 moments give it). An offset L theta splits
 * into a skew part, a centre shift the fit absorbs (the bias), and the rest,
 * which shows; for L of independent entries of variance s^2 the visible
 * sum of squares is s^2 (3 tr C - tr(M^-1 G)) beyond the noise's, and the
 * absorbed shift has covariance s^2 M^-1 G M^-1, C = sum theta theta^T,
 * M = tr C I - C, G = tr(C^2) I - C^2. */
static SFIT_I_NOINLINE void prv_sta(const sfit_pair_t *s, prv_ctx_t *c)
{
    static const float k_chi[3] = {3.841f, 2.605f, 2.099f};
    static const float k_fq[3] = {82.8f, 3.563f, 1.828f};
    static const float k_nc[3] = {0.007f, 0.195f, 0.44f};
    const prv_sys_t *y = &c->y;
    float lm[3][9], lt[3][9], x[3], beta[3];
    sfit_mat3_t cm, crt, cinv, mm, minv, g2, h, t1, sig, pm, qm, l;
    float ess = 0.0f, trc, trs, noise, denom, vis, nk;
    int a, i, k, m, kept = 0;
    for (i = 0; i < 3; i++) {
        x[i] = c->cpp[i] + s->cen_p.v[i];
    }
    memset(lm, 0, sizeof lm);
    for (a = 0; a < 3; a++) {
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        for (k = 0; k < 3; k++) {
            lm[a][3 * k + b] = 0.5f * y->abar.m[3 * k + d];
            lm[a][3 * k + d] = -0.5f * y->abar.m[3 * k + b];
        }
    }
    for (a = 0; a < 3; a++) {
        for (m = 0; m < 9; m++) {
            float sum = 0.0f;
            for (k = 0; k < 9; k++) {
                sum += lm[a][k] * y->tc[prv_tidx(k, m)];
            }
            lt[a][m] = sum;
        }
    }
    /* C = L T L^T; crt(k, a) = sum_f r_k theta_a = sum_m L(a, m) R(m, k),
     * R(m, k) = sum_i x_i T(m, 3i + k) - xh(m, k). */
    for (a = 0; a < 3; a++) {
        for (k = 0; k < 3; k++) {
            float sum = 0.0f;
            for (m = 0; m < 9; m++) {
                sum += lt[a][m] * lm[k][m];
            }
            cm.m[3 * a + k] = sum;
        }
    }
    for (k = 0; k < 3; k++) {
        for (a = 0; a < 3; a++) {
            float sum = 0.0f;
            for (i = 0; i < 3; i++) {
                sum += x[i] * lt[a][3 * i + k];
            }
            for (m = 0; m < 9; m++) {
                sum -= lm[a][m] * y->xh[3 * m + k];
            }
            crt.m[3 * k + a] = sum;
        }
    }
    prv_symmetrise(&cm);
    /* The rotation noise is in both theta and r (the lever arm): less its
     * expectation, N ([c]x S_c + Abar^T [x]x S_p Abar), S = var J^-1. */
    {
        sfit_mat3_t sc, sp, t2;
        for (i = 0; i < 9; i++) {
            sc.m[i] = y->var_c * y->jc.m[i];
            sp.m[i] = y->var_p * y->jp.m[i];
        }
        prv_cross_mul(c->ccc, &sc, &h);
        prv_cross_mul(c->cpp, &sp, &t1);
        sfit_i_mat3_mul(&t1, &y->abar, &t2);
        for (i = 0; i < 9; i++) {
            t1.m[i] = y->abar.m[3 * (i % 3) + i / 3]; /* Abar^T */
        }
        sfit_i_mat3_mul(&t1, &t2, &g2);
        for (i = 0; i < 9; i++) {
            crt.m[i] -= y->n * (h.m[i] + g2.m[i]);
        }
    }
    /* Only the directions the motion excites: in one it hardly turns (a
     * ball moved about horizontal axes), theta is the rotation noise, which
     * the residual shares (the lever arm): dropped. C^+ over the rest. */
    {
        sfit_vec3_t ev;
        sfit_mat3_t vv;
        if (sfit_mat3_eig_sym(&cm, &ev, &vv) != SFIT_OK || !(ev.v[2] > 0.0f)) {
            return;
        }
        memset(&cinv, 0, sizeof cinv);
        memset(&t1, 0, sizeof t1);
        for (k = 0; k < 3; k++) {
            if (ev.v[k] >= PRV_STA_EXCITED * ev.v[2]) {
                kept++;
                for (i = 0; i < 9; i++) {
                    const float p = vv.m[3 * (i / 3) + k] * vv.m[3 * (i % 3) + k];
                    cinv.m[i] += p / ev.v[k];
                    t1.m[i] += p; /* projector */
                }
            }
        }
        /* C and crt on the kept directions */
        sfit_i_mat3_mul(&cm, &t1, &h);
        sfit_i_mat3_mul(&t1, &h, &cm);
        prv_symmetrise(&cm);
        sfit_i_mat3_mul(&crt, &t1, &h);
        crt = h;
        nk = (float)kept;
    }
    trc = cm.m[0] + cm.m[4] + cm.m[8];
    for (i = 0; i < 9; i++) {
        mm.m[i] = ((i % 4 == 0) ? trc : 0.0f) - cm.m[i];
    }
    if (sfit_mat3_chol(&mm, &l) != SFIT_OK) {
        return;
    }
    sfit_i_chol_inverse(&l, &minv);
    for (k = 0; k < 3; k++) {
        ess += prv_quad(&cinv, &crt.m[3 * k]);
    }
    /* beta: the skew part of X = sum theta r^T (X(a, k) = crt(k, a)). */
    for (a = 0; a < 3; a++) {
        const int b = (a + 1) % 3, d = (a + 2) % 3;
        beta[a] = crt.m[3 * d + b] - crt.m[3 * b + d];
    }
    vis = ess - prv_quad(&minv, beta);
    /* The noise's share: 3 tr Sigma - tr(M^-1 E[beta beta^T]),
     * E[beta_a beta_a'] = C_bb' S_dd' - C_bd' S_db' - C_db' S_bd' + C_dd' S_bb'. */
    prv_point_noise(y, s, c->cpp, c->ccc, &pm, &qm);
    prv_resid_cov(y, &pm, &qm, &sig);
    trs = sig.m[0] + sig.m[4] + sig.m[8];
    prv_bcov(&cm, &sig, &t1);
    sfit_i_mat3_mul(&minv, &t1, &h);
    noise = nk * trs - (h.m[0] + h.m[4] + h.m[8]);
    /* The offset's prior: each child marker slides on the skin by its own
     * displacement, linear in the joint angle and independent between
     * markers; the registration turns them into a motion of the cluster
     * whose effect on the joint point has the shape of the marker noise's:
     * L's rows have covariance P = [c]x J_c^-1 [c]x^T + I / M_c per unit s^2
     * (c: the point from the child's centroid). */
    prv_cross_quad(c->ccc, &y->jc, &pm);
    for (i = 0; i < 3; i++) {
        pm.m[4 * i] += 1.0f / (float)s->n_c;
    }
    sfit_i_mat3_mul(&cm, &cm, &g2);
    prv_symmetrise(&g2);
    prv_bcov(&g2, &pm, &t1); /* E[beta beta^T] per unit s^2 */
    sfit_i_mat3_mul(&minv, &t1, &h);
    denom = (pm.m[0] + pm.m[4] + pm.m[8]) * trc - (h.m[0] + h.m[4] + h.m[8]);
    prv_sandwich(&minv, &t1, &h);
    if (noise > 0.0f) {
        c->res.sta_ratio = vis / noise;
    }
    /* The skin is seen when the angle-correlated residual passes its 95 %
     * quantile under the noise alone, chi^2(nu) / nu, nu = 3 kept - 3
     * (1 for one direction). Its size: vis estimates the total scale
     * s^2 denom + noise from nu dof, vis ~ (s^2 denom + noise) chi^2(nu) / nu,
     * so s^2 is (vis nu / X - noise) / denom, X ~ chi^2(nu) (Jeffreys prior
     * on the scale). The region that holds 95 % of the centre's error under
     * that spread is s^2 = k_fq (vis - k_nc noise) / denom: k_fq is 3 F(3, nu)'s
     * 95 % quantile over chi^2(3)'s (the limit of much skin), and k_nc the
     * share of the noise to subtract so the region stays a 95 % one where the
     * skin is near the noise (0.19-0.21 for nu = 3 over sta_ratio 2.6-300;
     * tests/ref/sfit_ref_pair.c derives both by quadrature). */
    if (noise > 0.0f && vis > 0.0f && denom > 0.0f && sfit_i_isfinite(vis)
        && vis > k_chi[kept - 1] * noise) {
        const float s2 = k_fq[kept - 1] * (vis - k_nc[kept - 1] * noise) / denom;
        c->sta_excess = vis - noise;
        c->res.sta_rms = SFIT_SQRTF(c->sta_excess / y->n);
        prv_sandwich(&y->abar, &h, &t1);
        for (i = 0; i < 9; i++) {
            c->res.center_cov_model.m[i] = s2 * t1.m[i];
        }
        prv_symmetrise(&c->res.center_cov_model);
    }
}

/* The misfit and the scaling of both covariances; the model parts; the
 * axis cone; MISFIT. The joint model's residual larger than the
 * registrations predict scales the centre's covariance (Birge): for a ball
 * the part not explained by skin motion linear in the joint angle, whose
 * own share is center_cov_model; (1 + trust) restores the terms of relative
 * size trust_ratio that the first-order sandwich leaves out. Hinge: the
 * tilt the out-of-axis rotation seen can cause is axis_cov_model (wb: the
 * floor, wr: a knee's in-step wobble once one is seen); the point moves
 * with it. */
static void prv_scale(prv_ctx_t *c, float at, float mm, float wb, float wr)
{
    sfit_pair_result_t *r = &c->res;
    sfit_vec3_t wa;
    int k;
    r->misfit = (c->expect > 0.0f) ? (c->cost - c->sta_excess) / c->expect : 0.0f;
    if (!(r->misfit > 0.0f)) {
        r->misfit = 0.0f;
    }
    {
        const float f = ((r->misfit > 1.0f) ? r->misfit : 1.0f) * (1.0f + r->trust_ratio);
        const float fa = 1.0f + r->trust_ratio;
        for (k = 0; k < 9; k++) {
            r->center_cov.m[k] = r->center_cov.m[k] * f + r->center_cov_model.m[k];
            r->axis_cov.m[k] *= fa;
        }
    }
    if (c->mode == SFIT_PAIR_MODE_HINGE && c->lam.v[1] > 0.0f) {
        sfit_mat3_t t;
        const float l1 = (c->l1c > 0.0f) ? c->l1c : 0.0f;
        const int seen = l1 > PRV_WOBBLE_Z * c->nz1 / SFIT_SQRTF(c->y.n);
        /* A wobble seen: the knee wobbles, and how much of it follows the
         * flexion no data can tell; that part is taken as a knee's (wr) or
         * twice the seen part, whichever is larger. Unseen: the floor. */
        const float w2 = seen ? wr * wr : wb * wb;
        const float pr = 0.5f * w2 * c->y.n;
        const float lu = seen ? PRV_WOBBLE_K * l1 : 0.0f;
        const float q = (lu > pr) ? lu : pr;
        int i, j;
        r->wobble_rms = SFIT_SQRTF(l1 / c->y.n);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                r->axis_cov_model.m[3 * i + j] =
                    q * (c->vec.m[3 * i + 1] * c->vec.m[3 * j + 1] / c->lam.v[1]
                         + c->vec.m[3 * i + 2] * c->vec.m[3 * j + 2] / c->lam.v[2]);
            }
        }
        prv_sandwich(&c->dpn, &r->axis_cov_model, &t);
        for (k = 0; k < 9; k++) {
            r->axis_cov.m[k] += r->axis_cov_model.m[k];
            r->center_cov.m[k] += t.m[k];
        }
        prv_symmetrise(&r->center_cov);
    }
    if (sfit_mat3_eig_sym(&r->axis_cov, &wa, NULL) != SFIT_OK
        || PRV_CHI2_2_95 * wa.v[2] > at * at) {
        c->flags |= (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE;
    }
    if (c->mode != SFIT_PAIR_MODE_HINGE) {
        memset(&r->axis_cov, 0, sizeof r->axis_cov);
        if ((c->flags & (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE) != 0u) {
            c->flags &= ~(uint32_t)SFIT_PAIR_FLAG_AXIS_FREE;
            r->info |= (uint32_t)SFIT_PAIR_INFO_AXIS_FREE;
        }
        if (r->sta_rms > 0.0f) {
            r->info |= (uint32_t)SFIT_PAIR_INFO_SKIN;
        }
    }
    if (c->expect > 0.0f && r->misfit > mm) {
        c->flags |= (uint32_t)SFIT_PAIR_FLAG_MISFIT;
    }
}

/* The main reason of SFIT_FLAG_UNTRUSTED, by priority. */
static sfit_pair_reason_t prv_reason(uint32_t flags, sfit_pair_mode_t mode)
{
    if ((flags & (uint32_t)SFIT_FLAG_FEW_SAMPLES) != 0u) {
        return SFIT_PAIR_REASON_FEW_FRAMES;
    }
    if ((flags & (uint32_t)SFIT_PAIR_FLAG_NO_NOISE) != 0u) {
        return SFIT_PAIR_REASON_NO_NOISE;
    }
    if ((flags & (uint32_t)SFIT_PAIR_FLAG_SMALL_MOTION) != 0u) {
        return SFIT_PAIR_REASON_SMALL_MOTION;
    }
    if ((flags & (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE) != 0u && mode == SFIT_PAIR_MODE_HINGE) {
        return SFIT_PAIR_REASON_AXIS_FREE;
    }
    if ((flags & (uint32_t)SFIT_PAIR_FLAG_AMBIGUOUS) != 0u) {
        return SFIT_PAIR_REASON_AMBIGUOUS;
    }
    if ((flags & (uint32_t)SFIT_PAIR_FLAG_MISFIT) != 0u) {
        return SFIT_PAIR_REASON_MISFIT;
    }
    return SFIT_PAIR_REASON_NONE;
}

/* Fill the result (axis sign: largest component positive, the child axis
 * follows); 0 when something is not finite. */
static int prv_fill(const sfit_pair_t *s, prv_ctx_t *c, uint32_t mf)
{
    sfit_pair_result_t *r = &c->res;
    int i, im = 0, ok;
    for (i = 1; i < 3; i++) {
        if (SFIT_FABSF(c->n1[i]) > SFIT_FABSF(c->n1[im])) {
            im = i;
        }
    }
    if (c->n1[im] < 0.0f) {
        for (i = 0; i < 3; i++) {
            c->n1[i] = -c->n1[i];
            c->axc[i] = -c->axc[i];
        }
    }
    for (i = 0; i < 3; i++) {
        r->center_p.v[i] = c->cpp[i] + s->cen_p.v[i];
        r->center_c.v[i] = c->ccc[i] + s->cen_c.v[i];
        r->axis_p.v[i] = c->n1[i];
        r->axis_c.v[i] = c->axc[i];
        r->eigenvalues.v[i] = c->lam.v[i] / c->y.n;
    }
    r->method = c->corrected ? s->cfg.method : SFIT_PAIR_METHOD_SCORE;
    r->mode = c->mode;
    r->rms = SFIT_SQRTF(c->cost / c->y.n);
    r->marker_var_p = c->y.var_p;
    r->marker_var_c = c->y.var_c;
    r->marker_var = 0.5f * (c->y.var_p + c->y.var_c);
    r->noise = s->cfg.noise;
    r->frames = s->frames;
    if (s->frames < mf) {
        c->flags |= (uint32_t)SFIT_FLAG_FEW_SAMPLES;
    }
    r->reason = prv_reason(c->flags, c->mode);
    if (r->reason != SFIT_PAIR_REASON_NONE) {
        c->flags |= (uint32_t)SFIT_FLAG_UNTRUSTED;
    }
    r->flags = c->flags;
    ok = sfit_i_finite3(r->center_p.v) && sfit_i_finite3(r->center_c.v)
         && sfit_i_finite3(r->axis_p.v) && sfit_i_finite3(r->axis_c.v)
         && sfit_i_finite3(r->eigenvalues.v) && sfit_i_isfinite(r->trust_ratio)
         && sfit_i_isfinite(r->misfit) && sfit_i_isfinite(r->rms)
         && sfit_i_isfinite(r->marker_var) && sfit_i_isfinite(r->sta_rms)
         && sfit_i_isfinite(r->sta_ratio) && sfit_i_isfinite(r->wobble_rms);
    for (i = 0; i < 9; i++) {
        ok = ok && sfit_i_isfinite(r->center_cov.m[i]) && sfit_i_isfinite(r->axis_cov.m[i])
             && sfit_i_isfinite(r->center_cov_model.m[i])
             && sfit_i_isfinite(r->axis_cov_model.m[i]);
    }
    return ok;
}

/* A threshold of the options, or its default when 0. */
static float prv_or(float v, float def)
{
    return (v > 0.0f) ? v : def;
}

sfit_status_t sfit_pair_solve(const sfit_pair_t *s, sfit_pair_result_t *out)
{
    prv_ctx_t c;
    float ssr_p, ssr_c, dof_p, dof_c;
    sfit_status_t st;

    if (s == NULL || out == NULL || !prv_state_ok(s)) {
        return SFIT_E_ARG;
    }
    if (s->frames < 3u) {
        return SFIT_E_TOO_FEW;
    }
    memset(&c, 0, sizeof c);
    if (!prv_build(s, &c.y, &dof_p, &dof_c, &ssr_p, &ssr_c)) {
        return SFIT_E_RANGE;
    }
    prv_noise(s, &c, ssr_p, dof_p, ssr_c, dof_c);
    c.corrected = (s->cfg.method != SFIT_PAIR_METHOD_SCORE);
    st = prv_system(&c);
    if (st == SFIT_OK) {
        st = prv_decide(s, &c, prv_or(s->cfg.hinge_ratio, PRV_HINGE_RATIO));
    }
    if (st == SFIT_OK) {
        const float mt = prv_or(s->cfg.max_trust, PRV_MAX_TRUST);
        st = (c.mode == SFIT_PAIR_MODE_BALL) ? prv_solve_ball(&c, mt) : prv_solve_hinge(&c, mt);
    }
    if (st == SFIT_OK && c.corrected && c.mode == SFIT_PAIR_MODE_BALL
        && s->cfg.method == SFIT_PAIR_METHOD_DEFAULT) {
        (void)prv_weighted(s, &c, prv_or(s->cfg.max_misfit, PRV_MAX_MISFIT));
    }
    if (st != SFIT_OK) {
        return st;
    }
    {
        const float at = prv_or(s->cfg.axis_tol, PRV_AXIS_TOL);
        prv_axis_seen(&c, at, prv_or(s->cfg.wobble, PRV_WOBBLE_RANGE));
        prv_points(&c);
        prv_covariances(s, &c);
        if (c.mode == SFIT_PAIR_MODE_BALL) {
            prv_sta(s, &c);
        }
        prv_scale(&c, at, prv_or(s->cfg.max_misfit, PRV_MAX_MISFIT),
                  prv_or(s->cfg.wobble, PRV_WOBBLE_FLOOR), prv_or(s->cfg.wobble, PRV_WOBBLE_RANGE));
    }
    if (!prv_fill(s, &c, (s->cfg.min_frames > 0u) ? s->cfg.min_frames : PRV_MIN_FRAMES)) {
        return SFIT_E_RANGE;
    }
    *out = c.res;
    return SFIT_OK;
}
