/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_joint.c
 * @brief Functional joint centre as a stream (parent registration, child
 * markers in the parent frame, multi-marker solve).
 *
 * Implementation notes
 * --------------------
 * sfit_joint_add() validates everything first (state, counts, the parent
 * registration, every child coordinate and every mapped child point, the
 * counters) and only then writes: the accumulators, the frame count and the
 * residual summary. A rejected frame therefore leaves every byte as it was.
 *
 * The mean residual is a running mean, res += (rms - res)/frames, which
 * stays within rounding of the true mean for any number of frames.
 *
 * Calls into other modules (moments, multi) are gathered in the prv_acc_*
 * and prv_multi helpers below, so an API rename touches only them.
 */
#include "sfit/sfit_joint.h"

#include <string.h>

#include "sfit/sfit_mat3.h"
#include "sfit_float.h"
#include "sfit_solve.h"

const sfit_joint_cfg_t sfit_joint_cfg_default = {
    1u,
    {{SFIT_MODE_AUTO, SFIT_NOISE_NONE, 0.0f,
      {{0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}}, 0.0f, 0},
     SFIT_MULTI_WEIGHT_EQUAL},
    SFIT_JOINT_NOISE_SOLVE};

/* ---- the only calls into the moments and multi modules ---- */
static void prv_acc_init(sfit_moments_t *m)
{
    (void)sfit_moments_init(m);
}

static uint32_t prv_acc_count(const sfit_moments_t *m)
{
    return sfit_moments_count(m);
}

static void prv_acc_add(sfit_moments_t *m, const sfit_vec3_t *x)
{
    /* Validated by the caller (finite, in range, count < UINT32_MAX). */
    (void)sfit_moments_add(m, x);
}

static sfit_status_t prv_acc_stats(const sfit_moments_t *m, sfit_vec3_t *mean, sfit_mat3_t *c)
{
    return sfit_moments_stats(m, mean, c, NULL);
}

static sfit_status_t prv_chol(const sfit_mat3_t *a, sfit_mat3_t *l)
{
    return sfit_mat3_chol(a, l);
}

static void prv_chol_solve(const sfit_mat3_t *l, const sfit_vec3_t *b, sfit_vec3_t *x)
{
    (void)sfit_mat3_chol_solve(l, b, x);
}

static sfit_status_t prv_multi(const sfit_moments_t *acc, size_t count,
                               const sfit_multi_cfg_t *cfg, sfit_multi_result_t *out,
                               float *radii)
{
    return sfit_multi_fit(acc, count, cfg, out, radii);
}

static sfit_status_t prv_check_solve_cfg(const sfit_multi_cfg_t *cfg)
{
    sfit_status_t st = sfit_i_check_cfg(&cfg->fit);
    if (st != SFIT_OK) {
        return st;
    }
    if (cfg->weight != SFIT_MULTI_WEIGHT_EQUAL && cfg->weight != SFIT_MULTI_WEIGHT_SAMPLES) {
        return SFIT_E_ARG;
    }
    return SFIT_OK;
}

/* Cheap consistency test of a state: counts in range, every child count at
 * most the frame count, residual summary finite and non-negative. */
static int prv_state_ok(const sfit_joint_t *j)
{
    uint32_t i;
    if (j->parent.count < 3u || j->parent.count > (uint32_t)SFIT_CLUSTER_MAX_MARKERS) {
        return 0;
    }
    if (j->cfg.n_child < 1u || j->cfg.n_child > (uint32_t)SFIT_JOINT_MAX_CHILD) {
        return 0;
    }
    for (i = 0; i < j->cfg.n_child; i++) {
        if (prv_acc_count(&j->child[i]) > j->frames) {
            return 0;
        }
    }
    if (!sfit_i_isfinite(j->res_mean) || !sfit_i_isfinite(j->res_max) || j->res_mean < 0.0f
        || j->res_max < 0.0f) {
        return 0;
    }
    return 1;
}

static int prv_has_nan(const float x[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        uint32_t u;
        memcpy(&u, &x[i], sizeof u);
        if ((u & 0x7F800000u) == 0x7F800000u && (u & 0x007FFFFFu) != 0u) {
            return 1;
        }
    }
    return 0;
}

sfit_status_t sfit_joint_init(sfit_joint_t *j, const sfit_cluster_t *parent,
                              const sfit_joint_cfg_t *cfg)
{
    uint32_t i;
    if (j == NULL || parent == NULL) {
        return SFIT_E_ARG;
    }
    if (cfg == NULL) {
        cfg = &sfit_joint_cfg_default;
    }
    if (parent->count < 3u || parent->count > (uint32_t)SFIT_CLUSTER_MAX_MARKERS) {
        return SFIT_E_ARG;
    }
    for (i = 0; i < parent->count; i++) {
        if (sfit_i_check_sample(parent->pos[i].v) != SFIT_OK) {
            return SFIT_E_ARG;
        }
    }
    if (cfg->n_child < 1u || cfg->n_child > (uint32_t)SFIT_JOINT_MAX_CHILD) {
        return SFIT_E_ARG;
    }
    if (prv_check_solve_cfg(&cfg->solve) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    if (cfg->noise_model != SFIT_JOINT_NOISE_SOLVE
        && (cfg->noise_model != SFIT_JOINT_NOISE_MARKER || cfg->solve.fit.noise != SFIT_NOISE_ISO)) {
        return SFIT_E_ARG;
    }
    {
        /* parent or cfg may point into *j: copy before clearing */
        const sfit_cluster_t pc = *parent;
        const sfit_joint_cfg_t cc = *cfg;
        memset(j, 0, sizeof *j);
        j->parent = pc;
        j->cfg = cc;
    }
    for (i = 0; i < (uint32_t)SFIT_JOINT_MAX_CHILD; i++) {
        prv_acc_init(&j->child[i]);
    }
    return SFIT_OK;
}

sfit_status_t sfit_joint_reset(sfit_joint_t *j)
{
    uint32_t i;
    if (j == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    for (i = 0; i < (uint32_t)SFIT_JOINT_MAX_CHILD; i++) {
        prv_acc_init(&j->child[i]);
    }
    j->frames = 0u;
    j->res_mean = 0.0f;
    j->res_max = 0.0f;
    return SFIT_OK;
}

sfit_status_t sfit_joint_add(sfit_joint_t *j, const sfit_vec3_t *parent, size_t n_parent,
                             const sfit_vec3_t *child, size_t n_child, sfit_pose_t *pose)
{
    sfit_vec3_t xs[SFIT_JOINT_MAX_CHILD];
    uint8_t seen[SFIT_JOINT_MAX_CHILD];
    sfit_pose_t ps;
    sfit_cluster_fit_t fit;
    sfit_status_t st, child_st = SFIT_OK;
    size_t i;
    float nf;

    memset(seen, 0, sizeof seen);

    if (j == NULL || parent == NULL || child == NULL || !prv_state_ok(j)
        || n_parent != (size_t)j->parent.count || n_child != (size_t)j->cfg.n_child) {
        return SFIT_E_ARG;
    }
    if (j->frames == UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    /* Child coordinates: Inf rejects the frame at once; out of range is
     * reported in the order of the status rule (after the parent's
     * NONFINITE and TOO_FEW, before its DEGENERATE). */
    for (i = 0; i < n_child; i++) {
        sfit_status_t si;
        seen[i] = 0u;
        if (prv_has_nan(child[i].v)) {
            continue;
        }
        si = sfit_i_check_sample(child[i].v);
        if (si == SFIT_E_NONFINITE) {
            return si;
        }
        if (si != SFIT_OK) {
            child_st = si;
        }
        seen[i] = 1u;
    }
    st = sfit_cluster_register(&j->parent, parent, n_parent, &ps, &fit);
    if (st == SFIT_E_NONFINITE || st == SFIT_E_TOO_FEW || st == SFIT_E_ARG) {
        return st;
    }
    if (child_st != SFIT_OK) {
        return child_st;
    }
    if (st != SFIT_OK) {
        return st;
    }
    for (i = 0; i < n_child; i++) {
        if (seen[i] == 0u) {
            continue;
        }
        if (sfit_pose_to_segment(&ps, &child[i], &xs[i]) != SFIT_OK
            || sfit_i_check_sample(xs[i].v) != SFIT_OK) {
            return SFIT_E_RANGE;
        }
    }
    /* Commit. Child counts are <= frames < UINT32_MAX (prv_state_ok). */
    for (i = 0; i < n_child; i++) {
        if (seen[i] != 0u) {
            prv_acc_add(&j->child[i], &xs[i]);
        }
    }
    j->frames++;
    nf = (float)j->frames;
    j->res_mean += (fit.rms - j->res_mean) / nf;
    if (fit.rms > j->res_max) {
        j->res_max = fit.rms;
    }
    if (pose != NULL) {
        *pose = ps;
    }
    return SFIT_OK;
}

sfit_status_t sfit_joint_fit(const sfit_joint_t *j, sfit_joint_result_t *out, float *radii)
{
    sfit_joint_result_t r;
    sfit_multi_cfg_t cfg;
    sfit_status_t st;

    if (j == NULL || out == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    memset(&r, 0, sizeof r);
    cfg = j->cfg.solve;
    if (j->cfg.noise_model == SFIT_JOINT_NOISE_MARKER) {
        if (cfg.fit.noise != SFIT_NOISE_ISO) {
            return SFIT_E_ARG;
        }
        st = sfit_joint_noise_cov(j, cfg.fit.noise_var, &cfg.fit.noise_cov);
        if (st != SFIT_OK) {
            return st;
        }
        cfg.fit.noise = SFIT_NOISE_COV;
    }
    st = prv_multi(j->child, (size_t)j->cfg.n_child, &cfg, &r.fit, radii);
    if (st != SFIT_OK) {
        return st;
    }
    r.frames = j->frames;
    r.residual_mean = j->res_mean;
    r.residual_max = j->res_max;
    *out = r;
    return SFIT_OK;
}

/* Levi-Civita symbol eps(a, b, c) of distinct or repeated indices 0..2. */
static float prv_eps(int a, int b, int c)
{
    if (a == b || b == c || a == c) {
        return 0.0f;
    }
    return ((b - a + 3) % 3 == 1) ? 1.0f : -1.0f;
}

/* Template centroid pb and the inverse of J = sum (|p|^2 I - p p^T) about
 * it (positive definite for a valid, non-collinear template). */
static sfit_status_t prv_inertia_inv(const sfit_cluster_t *cl, float pb[3], sfit_mat3_t *ji)
{
    sfit_mat3_t jm, l;
    const float np = (float)cl->count;
    uint32_t i;
    int a, b;
    for (a = 0; a < 3; a++) {
        pb[a] = 0.0f;
    }
    for (i = 0; i < cl->count; i++) {
        if (sfit_i_check_sample(cl->pos[i].v) != SFIT_OK) {
            return SFIT_E_ARG;
        }
        for (a = 0; a < 3; a++) {
            pb[a] += (cl->pos[i].v[a] - cl->pos[0].v[a]) / np;
        }
    }
    for (a = 0; a < 3; a++) {
        pb[a] += cl->pos[0].v[a];
    }
    memset(&jm, 0, sizeof jm);
    for (i = 0; i < cl->count; i++) {
        float p[3], p2;
        for (a = 0; a < 3; a++) {
            p[a] = cl->pos[i].v[a] - pb[a];
        }
        p2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                jm.m[3 * a + b] += ((a == b) ? p2 : 0.0f) - p[a] * p[b];
            }
        }
    }
    if (prv_chol(&jm, &l) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    for (a = 0; a < 3; a++) {
        sfit_vec3_t e = {{0.0f, 0.0f, 0.0f}}, x;
        e.v[a] = 1.0f;
        prv_chol_solve(&l, &e, &x);
        for (b = 0; b < 3; b++) {
            ji->m[3 * b + a] = x.v[b];
        }
    }
    return SFIT_OK;
}

/* Q = mean over the child markers with >= 2 samples of E[y y^T] =
 * m m^T + (N-1)/N C, y relative to pb. Returns the markers used. */
static uint32_t prv_second_moment(const sfit_joint_t *j, const float pb[3], sfit_mat3_t *q)
{
    uint32_t i, used = 0u;
    int a, b;
    memset(q, 0, sizeof *q);
    for (i = 0; i < j->cfg.n_child; i++) {
        sfit_vec3_t m;
        sfit_mat3_t cm;
        float f;
        if (prv_acc_stats(&j->child[i], &m, &cm) != SFIT_OK) {
            continue; /* fewer than 2 samples */
        }
        f = (float)(prv_acc_count(&j->child[i]) - 1u) / (float)prv_acc_count(&j->child[i]);
        for (a = 0; a < 3; a++) {
            m.v[a] -= pb[a];
        }
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                q->m[3 * a + b] += m.v[a] * m.v[b] + f * cm.m[3 * a + b];
            }
        }
        used++;
    }
    if (used > 0u) {
        const float inv = 1.0f / (float)used;
        for (a = 0; a < 9; a++) {
            q->m[a] *= inv;
        }
    }
    return used;
}

/* E[[y]x A [y]x^T] from Q = E[y y^T]: entry (r, s) is
 * sum_{i,k,c,d} eps(r,i,c) eps(s,k,d) Q_ik A_cd. For each (r, i) there is
 * one c with eps != 0 (c = 3 - r - i, r != i), so the sum has 4 terms. */
static void prv_cross_sandwich(const sfit_mat3_t *q, const sfit_mat3_t *a, sfit_mat3_t *out)
{
    int r, s, i, k;
    for (r = 0; r < 3; r++) {
        for (s = 0; s < 3; s++) {
            float sum = 0.0f;
            for (i = 0; i < 3; i++) {
                for (k = 0; k < 3; k++) {
                    if (i != r && k != s) {
                        const int c = 3 - r - i, d = 3 - s - k;
                        sum += prv_eps(r, i, c) * prv_eps(s, k, d) * q->m[3 * i + k]
                               * a->m[3 * c + d];
                    }
                }
            }
            out->m[3 * r + s] = sum;
        }
    }
}

sfit_status_t sfit_joint_noise_cov(const sfit_joint_t *j, float marker_var, sfit_mat3_t *cov)
{
    sfit_mat3_t ji, q, acc, out;
    float pb[3], np;
    int a, b;

    if (j == NULL || cov == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(marker_var)) {
        return SFIT_E_NONFINITE;
    }
    if (marker_var < 0.0f) {
        return SFIT_E_ARG;
    }
    if (prv_inertia_inv(&j->parent, pb, &ji) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    if (prv_second_moment(j, pb, &q) == 0u) {
        return SFIT_E_TOO_FEW;
    }
    prv_cross_sandwich(&q, &ji, &acc);
    np = (float)j->parent.count;
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            /* symmetrise; add the translation and marker terms */
            const float v = 0.5f * (acc.m[3 * a + b] + acc.m[3 * b + a])
                            + ((a == b) ? 1.0f + 1.0f / np : 0.0f);
            out.m[3 * a + b] = marker_var * v;
            if (!sfit_i_isfinite(out.m[3 * a + b])) {
                return SFIT_E_RANGE;
            }
        }
    }
    *cov = out;
    return SFIT_OK;
}

sfit_status_t sfit_joint_center_at(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                   const sfit_vec3_t *parent, size_t n_parent,
                                   sfit_vec3_t *center, sfit_vec3_t *axis)
{
    sfit_pose_t ps;
    sfit_vec3_t c, a;
    sfit_status_t st;
    int i;

    if (j == NULL || res == NULL || parent == NULL || center == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    st = sfit_cluster_register(&j->parent, parent, n_parent, &ps, NULL);
    if (st != SFIT_OK) {
        return st;
    }
    if (sfit_pose_to_global(&ps, &res->fit.center, &c) != SFIT_OK) {
        return SFIT_E_RANGE;
    }
    for (i = 0; i < 3; i++) {
        const float *rr = &ps.r.m[3 * i];
        a.v[i] = rr[0] * res->fit.axis.v[0] + rr[1] * res->fit.axis.v[1]
                 + rr[2] * res->fit.axis.v[2];
    }
    if (sfit_i_check_sample(c.v) != SFIT_OK || sfit_i_check_sample(a.v) != SFIT_OK) {
        return SFIT_E_RANGE;
    }
    *center = c;
    if (axis != NULL) {
        *axis = a;
    }
    return SFIT_OK;
}
