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

#include "sfit_internal.h"

const sfit_joint_cfg_t sfit_joint_cfg_default = {
    1u,
    {{SFIT_MODE_AUTO, SFIT_NOISE_NONE, 0.0f,
      {{0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f}}, 0.0f},
     SFIT_MULTI_WEIGHT_EQUAL}};

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

static sfit_status_t prv_multi(const sfit_moments_t *acc, size_t count,
                               const sfit_multi_cfg_t *cfg, sfit_multi_result_t *out,
                               float *radii)
{
    return sfit_multi_solve(acc, count, cfg, out, radii);
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
    memset(j, 0, sizeof *j);
    j->parent = *parent;
    j->cfg = *cfg;
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
    uint8_t seen[SFIT_JOINT_MAX_CHILD] = {0u};
    sfit_pose_t ps;
    sfit_cluster_fit_t fit;
    sfit_status_t st;
    size_t i;
    float nf;

    if (j == NULL || parent == NULL || child == NULL || !prv_state_ok(j)
        || n_parent != (size_t)j->parent.count || n_child != (size_t)j->cfg.n_child) {
        return SFIT_E_ARG;
    }
    if (j->frames == UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    /* Child coordinates first: Inf or out of range rejects the frame. */
    for (i = 0; i < n_child; i++) {
        seen[i] = 0u;
        if (prv_has_nan(child[i].v)) {
            continue;
        }
        st = sfit_i_check_sample(child[i].v);
        if (st != SFIT_OK) {
            return st;
        }
        seen[i] = 1u;
    }
    st = sfit_cluster_register(&j->parent, parent, n_parent, &ps, &fit);
    if (st != SFIT_OK) {
        return st;
    }
    for (i = 0; i < n_child; i++) {
        if (seen[i] == 0u) {
            continue;
        }
        (void)sfit_pose_to_segment(&ps, &child[i], &xs[i]);
        st = sfit_i_check_sample(xs[i].v);
        if (st != SFIT_OK) {
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

sfit_status_t sfit_joint_solve(const sfit_joint_t *j, sfit_joint_result_t *out, float *radii)
{
    sfit_joint_result_t r;
    sfit_status_t st;

    if (j == NULL || out == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    memset(&r, 0, sizeof r);
    st = prv_multi(j->child, (size_t)j->cfg.n_child, &j->cfg.solve, &r.fit, radii);
    if (st != SFIT_OK) {
        return st;
    }
    r.frames = j->frames;
    r.residual_mean = j->res_mean;
    r.residual_max = j->res_max;
    *out = r;
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
    (void)sfit_pose_to_global(&ps, &res->fit.center, &c);
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
