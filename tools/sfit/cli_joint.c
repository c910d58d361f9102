/* SPDX-License-Identifier: MIT */
/** @file cli_joint.c  The joint centre over loaded trajectories (cli_joint.h). */
#include "cli_joint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "sfit/sfit_selfcal.h"

void cli_joint_opts_default(cli_joint_opts_t *o)
{
    o->first = 0;
    o->last = -1; /* to the end */
    o->mode = SFIT_MODE_AUTO;
    o->noise = 0;
    o->noise_var = 0.0f;
    o->no_repair_swaps = 0;
}

const char *cli_joint_frames_opt(void *dst, const char *v)
{
    cli_joint_opts_t *o = (cli_joint_opts_t *)dst;
    if (cli_parse_frames(v, &o->first, &o->last) != 0) {
        return "--frames needs F:L, whole numbers with 0 <= F <= L";
    }
    return NULL;
}

const char *cli_joint_noise_opt(void *dst, const char *v)
{
    cli_joint_opts_t *o = (cli_joint_opts_t *)dst;
    if (o->noise != 0) {
        return "--noise-var given twice";
    }
    if (strcmp(v, "auto") == 0) {
        o->noise = 2;
    } else if (cli_parse_floats(v, &o->noise_var, 1) != 0 || !(o->noise_var >= 0.0f)
               || !(o->noise_var < 3.0e38f)) {
        return "--noise-var needs auto or one finite value >= 0";
    } else {
        o->noise = 1;
    }
    return NULL;
}

void cli_joint_free(cli_joint_out_t *out)
{
    free(out->ok);
    out->ok = NULL;
}

/* Copy the parent markers of frames first..last into one frame-major array. */
static sfit_vec3_t *parent_block(const cli_frames_t *fr, int np, long first, long last)
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
            b[(size_t)(f - first) * (size_t)np + (size_t)k] = *cli_frames_at(fr, f, k);
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
static sfit_status_t feed(const cli_frames_t *fr, int np, int nc, long first, long last,
                          cli_joint_out_t *out, sfit_vec3_t *keep, size_t *nkeep)
{
    long f;
    out->used = 0;
    out->rejected = 0;
    memset(out->child_n, 0, sizeof out->child_n);
    for (f = first; f <= last; f++) {
        const sfit_vec3_t *row = cli_frames_at(fr, f, 0);
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

sfit_status_t cli_joint_run(const cli_frames_t *fr, int np, int nc, const cli_joint_opts_t *o,
                            cli_joint_out_t *out)
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
        if (all_finite(cli_frames_at(fr, f, 0), np)) {
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
    if (o->noise == 1) { /* the measured markers' noise, propagated by the library */
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
    if (o->noise == 2) {
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
    return out->st = st;
}

sfit_status_t cli_joint_lab(const cli_frames_t *fr, int np, const cli_joint_out_t *out, long f,
                            sfit_vec3_t *center, sfit_vec3_t *axis)
{
    return sfit_joint_center_at(&out->j, &out->res, cli_frames_at(fr, f, 0), (size_t)np, center,
                                axis);
}
