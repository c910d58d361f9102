/* SPDX-License-Identifier: MIT */
/** @file joint_run.c  The joint centre over loaded trajectories (joint_run.h). */
#include "joint_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "names.h"
#include "sfit/sfit_selfcal.h"

void joint_run_opts_default(joint_run_opts_t *o)
{
    o->first = 0;
    o->last = -1; /* to the end */
    o->mode = SFIT_MODE_AUTO;
    o->noise = 0;
    o->noise_var = 0.0f;
    o->no_repair_swaps = 0;
    o->method = JOINT_RUN_DEFAULT;
}




void joint_run_free(joint_run_out_t *out)
{
    free(out->ok);
    out->ok = NULL;
}

/* Copy the parent markers of frames first..last into one frame-major array. */
static sfit_vec3_t *parent_block(const frames_data_t *fr, int np, long first, long last)
{
    const size_t nf = (size_t)(last - first + 1);
    sfit_vec3_t *b = malloc(nf * (size_t)np * sizeof *b);
    long f;
    int k;
    if (b == NULL) {
        return NULL;
    }
    for (f = first; f <= last; f++) {
        for (k = 0; k < np; k++) {
            b[(size_t)(f - first) * (size_t)np + (size_t)k] = *frames_at(fr, f, k);
        }
    }
    return b;
}

static int all_finite(const sfit_vec3_t *p, int n)
{
    int k, i;
    for (k = 0; k < n; k++) {
        for (i = 0; i < 3; i++) {
            if (!isfinite(p[k].v[i])) {
                return 0;
            }
        }
    }
    return 1;
}

/* One pass over the frames: feed the joint; optionally keep the child
 * markers mapped into the parent frame (for the noise estimate). */
static sfit_status_t feed(const frames_data_t *fr, int np, int nc, long first, long last,
                          joint_run_out_t *out, sfit_vec3_t *keep, size_t *nkeep)
{
    long f;
    out->used = 0;
    out->rejected = 0;
    memset(out->child_n, 0, sizeof out->child_n);
    for (f = first; f <= last; f++) {
        const sfit_vec3_t *row = frames_at(fr, f, 0);
        sfit_pose_t pose;
        const sfit_status_t st =
            sfit_joint_add(&out->j, row, (size_t)np, row + np, (size_t)nc, &pose);
        int k;
        out->ok[f] = (unsigned char)(st == SFIT_OK);
        if (st != SFIT_OK) {
            out->rejected++;
            continue;
        }
        out->used++;
        for (k = 0; k < nc; k++) {
            if (all_finite(row + np + k, 1)) {
                out->child_n[k]++;
                if (keep != NULL) {
                    sfit_vec3_t xs;
                    (void)sfit_cluster_to_segment(&pose, row + np + k, &xs);
                    keep[(size_t)k * (size_t)(last - first + 1) + nkeep[k]++] = xs;
                }
            }
        }
    }
    return SFIT_OK;
}

/* Pooled self-calibrated noise of the child markers (sphere fits). */
static sfit_status_t estimate_noise(const sfit_vec3_t *keep, const size_t *nkeep, int nc,
                                    size_t stride, float *noise_var)
{
    double sum = 0.0, w = 0.0;
    int k;
    for (k = 0; k < nc; k++) {
        sfit_selfcal_result_t sc;
        if (sfit_selfcal_points(keep + (size_t)k * stride, nkeep[k], NULL, &sc) == SFIT_OK
            && (sc.flags & SFIT_SELFCAL_FLAG_CAPPED) == 0u) {
            sum += (double)sc.noise_var * (double)nkeep[k];
            w += (double)nkeep[k];
        }
    }
    if (!(w > 0.0)) {
        return SFIT_E_DEGENERATE;
    }
    *noise_var = (float)(sum / w);
    return SFIT_OK;
}

/* The pair of segments (sfit_pair.h) over the frames the joint accepted:
 * a child template from the child markers, both clusters registered per
 * frame; the result replaces res.fit's centre, axis and mode (so the lab
 * centre, the trajectory and the skeleton use it). */
static sfit_status_t run_pair(const frames_data_t *fr, int np, int nc, long first, long last,
                              const joint_run_opts_t *o, joint_run_out_t *out)
{
    static const char *const names[] = {"default", "score", "sara", "mgdk"};
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_cluster_t ccl;
    sfit_pair_t *pr;
    sfit_vec3_t *blk;
    size_t used_tpl = 0;
    long f;
    sfit_status_t st;
    int k;

    out->stage = "child template";
    blk = malloc((size_t)(last - first + 1) * (size_t)nc * sizeof *blk);
    pr = malloc(sizeof *pr);
    if (blk == NULL || pr == NULL) {
        free(blk);
        free(pr);
        return SFIT_E_RANGE;
    }
    for (f = first; f <= last; f++) {
        for (k = 0; k < nc; k++) {
            blk[(size_t)(f - first) * (size_t)nc + (size_t)k] = *frames_at(fr, f, np + k);
        }
    }
    st = sfit_cluster_from_frames(&ccl, blk, (size_t)(last - first + 1), (size_t)nc, &used_tpl);
    free(blk);
    if (st != SFIT_OK) {
        free(pr);
        return st;
    }
    cfg.method = (o->method == JOINT_RUN_DEFAULT) ? SFIT_PAIR_METHOD_DEFAULT : SFIT_PAIR_METHOD_SCORE;
    cfg.mode = (o->method == JOINT_RUN_SARA || o->mode == SFIT_MODE_PLANAR) ? SFIT_PAIR_MODE_HINGE
               : (o->mode == SFIT_MODE_SPHERE || o->method == JOINT_RUN_SCORE) ? SFIT_PAIR_MODE_BALL
                                                                              : SFIT_PAIR_MODE_AUTO;
    if (o->noise == 1) {
        cfg.noise = SFIT_PAIR_NOISE_GIVEN;
        cfg.marker_var = o->noise_var;
    }
    out->stage = "pair";
    st = sfit_pair_init(pr, &out->j.parent, &ccl, &cfg);
    out->pair_rejected = 0;
    for (f = first; f <= last && st == SFIT_OK; f++) {
        const sfit_vec3_t *row = frames_at(fr, f, 0);
        if (out->ok[f] == 0u) {
            continue;
        }
        if (sfit_pair_add_markers(pr, &out->j.parent, row, (size_t)np, &ccl, row + np,
                                  (size_t)nc) != SFIT_OK) {
            out->pair_rejected++;
        }
    }
    if (st == SFIT_OK) {
        out->stage = "solve";
        st = sfit_pair_solve(pr, &out->pair);
    }
    free(pr);
    if (st != SFIT_OK) {
        return st;
    }
    out->pair_used = 1;
    out->method_name = names[o->method];
    out->res.fit.center = out->pair.center_p;
    out->res.fit.axis = out->pair.axis_p;
    out->res.fit.mode = (out->pair.mode == SFIT_PAIR_MODE_HINGE) ? SFIT_MODE_PLANAR : SFIT_MODE_SPHERE;
    out->res.fit.eigenvalues = out->pair.eigenvalues;
    out->res.fit.trust_ratio = out->pair.trust_ratio;
    return SFIT_OK;
}

sfit_status_t joint_run_mgdk_cov(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                 const sfit_vec3_t *parent, const sfit_vec3_t *child, size_t nf,
                                 float var_given, sfit_mat3_t *cov, float *var)
{
    double ssr = 0.0, dof = 0.0;
    const size_t np = (size_t)j->parent.count;
    size_t f;
    if (var_given >= 0.0f) {
        *var = var_given;
    } else {
        for (f = 0; f < nf; f++) {
            sfit_pose_t pose;
            sfit_cluster_fit_t fit;
            if (sfit_cluster_register(&j->parent, parent + f * np, np, &pose, &fit) == SFIT_OK
                && fit.used > 2u) {
                ssr += (double)fit.rms * (double)fit.rms * (double)fit.used;
                dof += 3.0 * (double)fit.used - 6.0;
            }
        }
        if (!(dof > 0.0)) {
            *var = 0.0f;
            return SFIT_E_TOO_FEW;
        }
        *var = (float)(ssr / dof);
    }
    return sfit_joint_center_cov(j, res, parent, child, nf, *var, cov);
}

/* The multi-marker fit's centre covariance over the frames it was fed
 * (joint_run_mgdk_cov). */
static void mgdk_cov(const frames_data_t *fr, int np, int nc, long first, long last,
                     const joint_run_opts_t *o, joint_run_out_t *out)
{
    const size_t nf = (size_t)(last - first + 1);
    sfit_vec3_t *pb = malloc(nf * (size_t)np * sizeof *pb);
    sfit_vec3_t *cb = malloc(nf * (size_t)nc * sizeof *cb);
    long f;
    int k;
    out->mgdk_cov_ok = 0;
    out->mgdk_var_given = (o->noise == 1);
    out->mgdk_var = out->mgdk_var_given ? o->noise_var : 0.0f;
    if (pb == NULL || cb == NULL) {
        free(pb);
        free(cb);
        return;
    }
    for (f = first; f <= last; f++) {
        const sfit_vec3_t *row = frames_at(fr, f, 0);
        for (k = 0; k < np; k++) {
            pb[(size_t)(f - first) * (size_t)np + (size_t)k] = row[k];
        }
        for (k = 0; k < nc; k++) {
            cb[(size_t)(f - first) * (size_t)nc + (size_t)k] = row[np + k];
        }
    }
    out->mgdk_cov_ok = joint_run_mgdk_cov(&out->j, &out->res, pb, cb, nf,
                                          out->mgdk_var_given ? o->noise_var : -1.0f,
                                          &out->mgdk_cov, &out->mgdk_var)
                       == SFIT_OK;
    free(pb);
    free(cb);
}




sfit_status_t joint_run(const frames_data_t *fr, int np, int nc, const joint_run_opts_t *o,
                            joint_run_out_t *out)
{
    sfit_cluster_t cl;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_vec3_t *blk, *keep = NULL;
    size_t nkeep[SFIT_JOINT_MAX_CHILD];
    size_t used_tpl = 0;
    long first = o->first, last = o->last, f;
    sfit_status_t st;

    memset(out, 0, sizeof *out);
    out->ref_frame = -1;
    out->stage = "frames";
    if (last < 0 || last >= fr->nframes) {
        last = fr->nframes - 1;
    }
    if (np < 3 || np > SFIT_CLUSTER_MAX_MARKERS || nc < 1 || nc > SFIT_JOINT_MAX_CHILD) {
        return out->st = SFIT_E_ARG;
    }
    if (first > last) {
        return out->st = SFIT_E_TOO_FEW;
    }
    out->ok = calloc((size_t)fr->nframes, 1u);
    blk = parent_block(fr, np, first, last);
    if (out->ok == NULL || blk == NULL) {
        free(blk);
        return out->st = SFIT_E_RANGE;
    }
    for (f = first; f <= last && out->ref_frame < 0; f++) {
        if (all_finite(frames_at(fr, f, 0), np)) {
            out->ref_frame = f;
        }
    }
    out->stage = "template";
    st = sfit_cluster_from_frames(&cl, blk, (size_t)(last - first + 1), (size_t)np, &used_tpl);
    free(blk);
    if (st != SFIT_OK) {
        return out->st = st;
    }
    out->template_frames = (unsigned long)used_tpl;
    cfg.n_child = (uint32_t)nc;
    cfg.solve.fit.mode = o->mode;
    if (o->noise == 1 && o->method == JOINT_RUN_MGDK) { /* the measured markers' noise, propagated by the library */
        cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
        cfg.solve.fit.noise = SFIT_NOISE_ISO;
        cfg.solve.fit.noise_var = o->noise_var;
        out->has_noise = 1;
        out->noise_var = o->noise_var;
    }
    out->stage = "frames";
    st = sfit_joint_init(&out->j, &cl, &cfg);
    if (st != SFIT_OK) {
        return out->st = st;
    }
    if (o->noise == 2 && o->method == JOINT_RUN_MGDK) {
        const size_t stride = (size_t)(last - first + 1);
        keep = malloc(stride * (size_t)nc * sizeof *keep);
        if (keep == NULL) {
            return out->st = SFIT_E_RANGE;
        }
        memset(nkeep, 0, sizeof nkeep);
        (void)feed(fr, np, nc, first, last, out, keep, nkeep);
        out->stage = "noise estimate";
        st = estimate_noise(keep, nkeep, nc, stride, &out->noise_var);
        free(keep);
        if (st != SFIT_OK) {
            return out->st = st;
        }
        out->has_noise = 1;
        out->noise_estimated = 1;
        cfg.solve.fit.noise = SFIT_NOISE_ISO;
        cfg.solve.fit.noise_var = out->noise_var;
        out->stage = "frames";
        st = sfit_joint_init(&out->j, &cl, &cfg);
        if (st != SFIT_OK) {
            return out->st = st;
        }
    }
    (void)feed(fr, np, nc, first, last, out, NULL, NULL);
    out->stage = "solve";
    st = sfit_joint_fit(&out->j, &out->res, out->radii);
    out->method_name = "mgdk";
    if (o->method == JOINT_RUN_MGDK) {
        if (st == SFIT_OK) {
            mgdk_cov(fr, np, nc, first, last, o, out);
        }
        return out->st = st;
    }
    if (nc < 3) {
        if (o->method != JOINT_RUN_DEFAULT) {
            out->stage = "child cluster";
            return out->st = SFIT_E_TOO_FEW;
        }
        out->note = "fewer than 3 child markers: no child cluster, the multi-marker fit (mgdk)";
        if (st == SFIT_OK) {
            mgdk_cov(fr, np, nc, first, last, o, out);
        }
        return out->st = st;
    }
    {
        const sfit_status_t pst = run_pair(fr, np, nc, first, last, o, out);
        if (pst != SFIT_OK) {
            return out->st = pst;
        }
    }
    return out->st = SFIT_OK;
}

sfit_status_t joint_run_lab(const frames_data_t *fr, int np, const joint_run_out_t *out, long f,
                            sfit_vec3_t *center, sfit_vec3_t *axis)
{
    return sfit_joint_center_at(&out->j, &out->res, frames_at(fr, f, 0), (size_t)np, center,
                                axis);
}
