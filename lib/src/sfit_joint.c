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
    .n_child = 1u,
    .solve = {.fit = {.mode = SFIT_MODE_AUTO, .noise = SFIT_NOISE_NONE, .planar_ratio = 0.0f},
              .weight = SFIT_MULTI_WEIGHT_EQUAL},
    .noise_model = SFIT_JOINT_NOISE_SOLVE};

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

static sfit_status_t prv_acc_stats(const sfit_moments_t *m, sfit_vec3_t *mean, sfit_mat3_t *c,
                                   sfit_vec3_t *s)
{
    return sfit_moments_stats(m, mean, c, s);
}

static sfit_status_t prv_chol(const sfit_mat3_t *a, sfit_mat3_t *l)
{
    return sfit_mat3_chol(a, l);
}

static sfit_status_t prv_multi(const sfit_moments_t *acc, size_t count,
                               const sfit_multi_cfg_t *cfg, const sfit_multi_noise_t *noise,
                               sfit_multi_result_t *out, float *radii)
{
    return (noise != NULL) ? sfit_multi_fit_noise(acc, count, cfg, noise, out, radii)
                           : sfit_multi_fit(acc, count, cfg, out, radii);
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
    if (sfit_i_check_multi_cfg(&cfg->solve) != SFIT_OK) {
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
        const sfit_status_t si = sfit_i_check_marker(child[i].v, &seen[i], &child_st);
        if (si != SFIT_OK) {
            return si;
        }
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
        if (sfit_cluster_to_segment(&ps, &child[i], &xs[i]) != SFIT_OK
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

/* The parent template's centroid pb and the pose-noise model about it:
 * K = J^-1, J = sum (|p|^2 I - p p^T) (positive definite for a valid,
 * non-collinear template). */
typedef struct prv_pose_noise {
    float pb[3];
    sfit_mat3_t k;
} prv_pose_noise_t;

static sfit_status_t prv_pose_noise(const sfit_cluster_t *cl, prv_pose_noise_t *pn)
{
    sfit_mat3_t jm, l;
    const float np = (float)cl->count;
    uint32_t i;
    int a;
    for (a = 0; a < 3; a++) {
        pn->pb[a] = 0.0f;
    }
    for (i = 0; i < cl->count; i++) {
        if (sfit_i_check_sample(cl->pos[i].v) != SFIT_OK) {
            return SFIT_E_ARG;
        }
        for (a = 0; a < 3; a++) {
            pn->pb[a] += (cl->pos[i].v[a] - cl->pos[0].v[a]) / np;
        }
    }
    for (a = 0; a < 3; a++) {
        pn->pb[a] += cl->pos[0].v[a];
    }
    sfit_i_spread(cl->pos, cl->count, pn->pb, &jm);
    if (prv_chol(&jm, &l) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    sfit_i_chol_inverse(&l, &pn->k);
    return SFIT_OK;
}

/* [a]x b A [a]x^T summed over the second moment Q = E[a a^T]: entry (r, s)
 * is sum eps(r,i,c) eps(s,k,d) Q_ik A_cd; for each (r, i) with r != i the
 * only c with eps != 0 is 3 - r - i. Symmetrised. */
static void prv_cross_sandwich(const sfit_mat3_t *q, const sfit_mat3_t *a, sfit_mat3_t *out)
{
    int r, s, ik;
    for (r = 0; r < 3; r++) {
        for (s = 0; s < 3; s++) {
            float sum = 0.0f;
            for (ik = 0; ik < 9; ik++) { /* ik = 3 i + k */
                const int i = ik / 3, k = ik % 3;
                if (i != r && k != s) {
                    const int c = 3 - r - i, d = 3 - s - k;
                    const float e = (((i - r + 3) % 3 == 1) == ((k - s + 3) % 3 == 1)) ? 1.0f
                                                                                       : -1.0f;
                    sum += e * q->m[ik] * a->m[3 * c + d];
                }
            }
            out->m[3 * r + s] = sum;
        }
    }
    for (r = 0; r < 3; r++) {
        for (s = 0; s < r; s++) {
            const float v = 0.5f * (out->m[3 * r + s] + out->m[3 * s + r]);
            out->m[3 * r + s] = v;
            out->m[3 * s + r] = v;
        }
    }
}

/*
 * Noise model of child marker i per unit marker variance (docs/joint.md):
 * Sigma(u) = (1 + 1/P) I + [u]x K [u]x^T, u = a + b the sample relative to
 * pb, a = m - pb, b = u - m. From the moments (Ct = (N-1)/N C = E[b b^T],
 * St = (N-1)/N S = E[|b|^2 b]):
 *   cov  = E Sigma = (1 + 1/P) I + E[[u]x K [u]x^T]  (second moment a a^T + Ct),
 *   skew = E[(2 Sigma + tr Sigma I) b] = -2 v + 2 Ct G a + (2/3) tr(K) St,
 * v = E[b x (M b)], v_r = eps_rjk (M Ct)_kj, M = K [a]x, G = tr(K) I - K;
 * E[(b^T K b) b] is replaced by its isotropic part tr(K)/3 St.
 * 0 when the marker has fewer than 2 samples, -1 when its accumulator is
 * corrupted (statistics not finite).
 */
static int prv_marker_noise(const sfit_moments_t *acc, const prv_pose_noise_t *pn, float np,
                            sfit_multi_noise_t *out)
{
    sfit_vec3_t m, s;
    sfit_mat3_t c, q, mk, x;
    float a[3], ga[3], f, trk;
    int r, k;
    const sfit_status_t st = prv_acc_stats(acc, &m, &c, &s);
    if (st != SFIT_OK) {
        return (st == SFIT_E_TOO_FEW) ? 0 : -1;
    }
    f = (float)(prv_acc_count(acc) - 1u) / (float)prv_acc_count(acc);
    for (r = 0; r < 3; r++) {
        a[r] = m.v[r] - pn->pb[r];
    }
    for (r = 0; r < 9; r++) {
        c.m[r] *= f;
        q.m[r] = a[r / 3] * a[r % 3] + c.m[r];
    }
    prv_cross_sandwich(&q, &pn->k, &out->cov);
    for (r = 0; r < 3; r++) {
        out->cov.m[4 * r] += 1.0f + 1.0f / np;
    }
    /* M = K [a]x: column k of [a]x is a x e_k */
    for (r = 0; r < 3; r++) {
        const float *kr = &pn->k.m[3 * r];
        mk.m[3 * r] = kr[1] * a[2] - kr[2] * a[1];
        mk.m[3 * r + 1] = kr[2] * a[0] - kr[0] * a[2];
        mk.m[3 * r + 2] = kr[0] * a[1] - kr[1] * a[0];
    }
    sfit_i_mat3_mul(&mk, &c, &x);
    trk = pn->k.m[0] + pn->k.m[4] + pn->k.m[8];
    sfit_i_mat3_vec(&pn->k, a, ga);
    for (r = 0; r < 3; r++) {
        ga[r] = trk * a[r] - ga[r];
    }
    for (r = 0; r < 3; r++) {
        const int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
        const float v = x.m[3 * r2 + r1] - x.m[3 * r1 + r2];
        float cg = 0.0f;
        for (k = 0; k < 3; k++) {
            cg += c.m[3 * r + k] * ga[k];
        }
        out->skew.v[r] = -2.0f * v + 2.0f * cg + (2.0f / 3.0f) * trk * f * s.v[r];
    }
    return 1;
}

/* Scale a noise model by the marker variance; 0 when not finite. */
static int prv_scale_noise(float var, sfit_multi_noise_t *n)
{
    int i;
    for (i = 0; i < 9; i++) {
        n->cov.m[i] *= var;
    }
    for (i = 0; i < 3; i++) {
        n->skew.v[i] *= var;
    }
    for (i = 0; i < 9; i++) {
        if (!sfit_i_isfinite(n->cov.m[i])) {
            return 0;
        }
    }
    return sfit_i_finite3(n->skew.v);
}

/* Checks shared by the two noise entry points; the pose-noise model. */
static sfit_status_t prv_noise_args(const sfit_joint_t *j, float marker_var, const void *out,
                                    prv_pose_noise_t *pn)
{
    if (j == NULL || out == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(marker_var)) {
        return SFIT_E_NONFINITE;
    }
    if (marker_var < 0.0f || prv_pose_noise(&j->parent, pn) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    return SFIT_OK;
}

/* The models of every child marker into noise[0..n_child-1] (also on
 * failure). */
static sfit_status_t prv_marker_models(const sfit_joint_t *j, float marker_var,
                                       const prv_pose_noise_t *pn, sfit_multi_noise_t *noise)
{
    uint32_t i, used = 0u;
    for (i = 0; i < j->cfg.n_child; i++) {
        int k;
        memset(&noise[i], 0, sizeof noise[i]);
        k = prv_marker_noise(&j->child[i], pn, (float)j->parent.count, &noise[i]);
        if (k < 0) {
            return SFIT_E_RANGE;
        }
        if (k > 0) {
            used++;
            if (!prv_scale_noise(marker_var, &noise[i])) {
                return SFIT_E_RANGE;
            }
        }
    }
    return (used == 0u) ? SFIT_E_TOO_FEW : SFIT_OK;
}

sfit_status_t sfit_joint_marker_noise(const sfit_joint_t *j, float marker_var,
                                      sfit_multi_noise_t *noise)
{
    sfit_multi_noise_t tmp[SFIT_JOINT_MAX_CHILD];
    prv_pose_noise_t pn;
    sfit_status_t st = prv_noise_args(j, marker_var, noise, &pn);
    if (st == SFIT_OK) {
        st = prv_marker_models(j, marker_var, &pn, tmp);
    }
    if (st == SFIT_OK) {
        memcpy(noise, tmp, (size_t)j->cfg.n_child * sizeof tmp[0]);
    }
    return st;
}

sfit_status_t sfit_joint_fit(const sfit_joint_t *j, sfit_joint_result_t *out, float *radii)
{
    sfit_joint_result_t r;
    sfit_multi_cfg_t cfg;
    sfit_multi_noise_t noise[SFIT_JOINT_MAX_CHILD];
    const sfit_multi_noise_t *np = NULL;
    sfit_status_t st;

    if (j == NULL || out == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    memset(&r, 0, sizeof r);
    cfg = j->cfg.solve;
    if (j->cfg.noise_model == SFIT_JOINT_NOISE_MARKER) {
        /* the options were checked by sfit_joint_init(): a corrupted state */
        if (cfg.fit.noise != SFIT_NOISE_ISO || sfit_i_check_multi_cfg(&cfg) != SFIT_OK) {
            return SFIT_E_ARG;
        }
        prv_pose_noise_t pn;
        st = prv_noise_args(j, cfg.fit.noise_var, noise, &pn);
        if (st == SFIT_OK) {
            st = prv_marker_models(j, cfg.fit.noise_var, &pn, noise);
        }
        if (st != SFIT_OK) {
            return st;
        }
        cfg.fit.noise = SFIT_NOISE_NONE;
        np = noise;
    }
    st = prv_multi(j->child, (size_t)j->cfg.n_child, &cfg, np, &r.fit, radii);
    if (st != SFIT_OK) {
        return st;
    }
    r.frames = j->frames;
    r.residual_mean = j->res_mean;
    r.residual_max = j->res_max;
    *out = r;
    return SFIT_OK;
}

sfit_status_t sfit_joint_noise_cov(const sfit_joint_t *j, float marker_var, sfit_mat3_t *cov)
{
    sfit_multi_noise_t one;
    sfit_mat3_t acc;
    prv_pose_noise_t pn;
    uint32_t i, used = 0u;
    int a;
    sfit_status_t st = prv_noise_args(j, marker_var, cov, &pn);
    if (st != SFIT_OK) {
        return st;
    }
    memset(&acc, 0, sizeof acc);
    for (i = 0; i < j->cfg.n_child; i++) {
        const int k = prv_marker_noise(&j->child[i], &pn, (float)j->parent.count, &one);
        if (k < 0) {
            return SFIT_E_RANGE;
        }
        if (k > 0) {
            used++;
            for (a = 0; a < 9; a++) {
                acc.m[a] += one.cov.m[a];
            }
        }
    }
    if (used == 0u) {
        return SFIT_E_TOO_FEW;
    }
    one.cov = acc;
    one.skew.v[0] = one.skew.v[1] = one.skew.v[2] = 0.0f;
    if (!prv_scale_noise(marker_var / (float)used, &one)) {
        return SFIT_E_RANGE;
    }
    *cov = one.cov;
    return SFIT_OK;
}

sfit_status_t sfit_joint_center_at(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                   const sfit_vec3_t *parent, size_t n_parent,
                                   sfit_vec3_t *center, sfit_vec3_t *axis)
{
    sfit_pose_t ps;
    sfit_vec3_t c, a;
    sfit_status_t st;

    if (j == NULL || res == NULL || parent == NULL || center == NULL || !prv_state_ok(j)) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_finite3(res->fit.center.v) || !sfit_i_finite3(res->fit.axis.v)) {
        return SFIT_E_NONFINITE; /* as sfit_joint_center_cov() */
    }
    st = sfit_cluster_register(&j->parent, parent, n_parent, &ps, NULL);
    if (st != SFIT_OK) {
        return st;
    }
    if (sfit_cluster_to_global(&ps, &res->fit.center, &c) != SFIT_OK) {
        return SFIT_E_RANGE;
    }
    sfit_i_mat3_vec(&ps.r, res->fit.axis.v, a.v);
    if (sfit_i_check_sample(c.v) != SFIT_OK || sfit_i_check_sample(a.v) != SFIT_OK) {
        return SFIT_E_RANGE;
    }
    *center = c;
    if (axis != NULL) {
        *axis = a;
    }
    return SFIT_OK;
}

/* Per-marker data of the covariance pass: mean, v_p = w_p / (N_p - 1), and
 * whether the solve used the marker. */
typedef struct prv_cov_marker {
    float m[3];
    float v;
    int used;
} prv_cov_marker_t;

/* A = sum w_p (C_p - Sigma_p) of the solve that gave the result (the noise
 * model of the joint's options), and each marker's mean and v_p. */
static sfit_status_t prv_cov_system(const sfit_joint_t *j, const prv_pose_noise_t *pn,
                                    prv_cov_marker_t *cm, sfit_mat3_t *a)
{
    sfit_multi_noise_t one;
    sfit_mat3_t sg_cfg;
    const sfit_fit_cfg_t *fc = &j->cfg.solve.fit;
    const int marker = (j->cfg.noise_model == SFIT_JOINT_NOISE_MARKER);
    uint64_t sum_n1;
    const uint32_t used = sfit_i_multi_used(j->child, (size_t)j->cfg.n_child, &sum_n1);
    uint32_t i;
    int k;
    if (used == 0u) {
        return SFIT_E_TOO_FEW;
    }
    sfit_i_sigma(fc->noise, fc->noise_var, &fc->noise_cov, &sg_cfg);
    memset(a, 0, sizeof *a);
    for (i = 0; i < j->cfg.n_child; i++) {
        sfit_vec3_t mean;
        sfit_mat3_t c;
        const uint32_t n = prv_acc_count(&j->child[i]);
        float w;
        cm[i].used = (n >= (uint32_t)SFIT_MIN_SAMPLES);
        if (!cm[i].used) {
            continue;
        }
        if (prv_acc_stats(&j->child[i], &mean, &c, NULL) != SFIT_OK) {
            return SFIT_E_RANGE; /* a corrupted accumulator: mean and C unwritten */
        }
        w = sfit_i_multi_weight(&j->cfg.solve, n, used, sum_n1);
        if (marker) {
            if (prv_marker_noise(&j->child[i], pn, (float)j->parent.count, &one) <= 0) {
                return SFIT_E_TOO_FEW; /* not reached: the marker has samples */
            }
            if (!prv_scale_noise(fc->noise_var, &one)) {
                return SFIT_E_RANGE;
            }
        }
        for (k = 0; k < 9; k++) {
            a->m[k] += w * (c.m[k] - (marker ? one.cov.m[k] : sg_cfg.m[k]));
        }
        for (k = 0; k < 3; k++) {
            cm[i].m[k] = mean.v[k];
        }
        cm[i].v = w / (float)(n - 1u);
    }
    return SFIT_OK;
}

/* Add the frame's terms: child sum v_p^2 |a|^2 b b^T (packed, q[0..5]) and
 * W Sigma_eta W^T (q[6..11]), W = sum_p v_p b a^T. */
static void prv_cov_frame(const sfit_joint_t *j, const prv_cov_marker_t *cm, const float c[3],
                          const sfit_mat3_t *seta, const sfit_pose_t *ps,
                          const sfit_vec3_t *child, sfit_i_sum_t *acc)
{
    sfit_mat3_t w, ws, wsw;
    float q[12];
    uint32_t i;
    int k;
    memset(&w, 0, sizeof w);
    memset(q, 0, sizeof q);
    for (i = 0; i < j->cfg.n_child; i++) {
        sfit_vec3_t y;
        float b[3], a[3], f;
        if (!cm[i].used || sfit_i_has_nan3(child[i].v)) {
            continue;
        }
        (void)sfit_cluster_to_segment(ps, &child[i], &y);
        for (k = 0; k < 3; k++) {
            b[k] = y.v[k] - cm[i].m[k];
            a[k] = y.v[k] - c[k];
        }
        f = cm[i].v * cm[i].v * sfit_i_dot3(a, a);
        for (k = 0; k < 9; k++) {
            w.m[k] += cm[i].v * b[k / 3] * a[k % 3];
        }
        q[0] += f * b[0] * b[0];
        q[1] += f * b[1] * b[1];
        q[2] += f * b[2] * b[2];
        q[3] += f * b[0] * b[1];
        q[4] += f * b[0] * b[2];
        q[5] += f * b[1] * b[2];
    }
    sfit_i_mat3_mul(&w, seta, &ws);
    for (k = 0; k < 9; k++) { /* wsw = ws w^T */
        const int r = k / 3, s = k % 3;
        wsw.m[k] = ws.m[3 * r] * w.m[3 * s] + ws.m[3 * r + 1] * w.m[3 * s + 1]
                   + ws.m[3 * r + 2] * w.m[3 * s + 2];
    }
    sfit_i_sym_pack(&wsw, &q[6]);
    sfit_i_sum_add(acc, q, 12);
}

sfit_status_t sfit_joint_center_cov(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                    const sfit_vec3_t *parent, const sfit_vec3_t *child,
                                    size_t nf, float marker_var, sfit_mat3_t *cov)
{
    prv_cov_marker_t cm[SFIT_JOINT_MAX_CHILD];
    prv_pose_noise_t pn;
    sfit_mat3_t a, seta, m, ce;
    sfit_i_sum_t acc;
    float c[3], e[3];
    size_t f;
    int k;
    sfit_status_t st = prv_noise_args(j, marker_var, cov, &pn);
    if (st != SFIT_OK) {
        return st;
    }
    if (res == NULL || parent == NULL || child == NULL) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_finite3(res->fit.center.v) || !sfit_i_finite3(res->fit.axis.v)
        || (res->fit.mode != SFIT_MODE_SPHERE && res->fit.mode != SFIT_MODE_PLANAR)) {
        return SFIT_E_NONFINITE;
    }
    if (nf == 0u) {
        return SFIT_E_TOO_FEW;
    }
    st = prv_cov_system(j, &pn, cm, &a);
    if (st != SFIT_OK) {
        return st;
    }
    /* Sigma_eta / sigma^2 = I/P + [c - pb]x K [c - pb]x^T */
    for (k = 0; k < 3; k++) {
        c[k] = res->fit.center.v[k];
        e[k] = c[k] - pn.pb[k];
    }
    for (k = 0; k < 9; k++) {
        ce.m[k] = e[k / 3] * e[k % 3];
    }
    prv_cross_sandwich(&ce, &pn.k, &seta);
    for (k = 0; k < 3; k++) {
        seta.m[4 * k] += 1.0f / (float)j->parent.count;
    }
    memset(&acc, 0, sizeof acc);
    for (f = 0u; f < nf; f++) {
        sfit_pose_t ps;
        const size_t np = (size_t)j->parent.count, nc = (size_t)j->cfg.n_child;
        sfit_status_t bad = SFIT_OK;
        size_t i;
        uint8_t seen;
        for (i = 0u; i < nc; i++) {
            if (sfit_i_check_marker(child[f * nc + i].v, &seen, &bad) != SFIT_OK) {
                bad = SFIT_E_NONFINITE;
            }
        }
        if (bad != SFIT_OK || sfit_cluster_register(&j->parent, &parent[f * np], np, &ps, NULL) != SFIT_OK) {
            continue; /* a frame sfit_joint_add() rejects */
        }
        prv_cov_frame(j, cm, c, &seta, &ps, &child[f * nc], &acc);
    }
    sfit_i_sum_end(&acc, 12);
    for (k = 0; k < 6; k++) {
        acc.tot[k] += acc.tot[6 + k];
    }
    sfit_i_sym_unpack(acc.tot, &m);
    return sfit_i_center_cov(&a, res->fit.mode, &res->fit.axis, &m, marker_var, cov);
}
