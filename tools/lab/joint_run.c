/* SPDX-License-Identifier: MIT */
/** @file joint_run.c  The joint centre over loaded trajectories (joint_run.h). */
#include "joint_run.h"

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
    o->method = CLI_JOINT_DEFAULT;
}

const char *cli_joint_method_opt(void *dst, const char *v)
{
    static const char *const names[] = {"default", "score", "sara", "mgdk"};
    cli_joint_opts_t *o = (cli_joint_opts_t *)dst;
    int k;
    for (k = 0; k < 4; k++) {
        if (strcmp(v, names[k]) == 0) {
            o->method = k;
            return NULL;
        }
    }
    return "--method is default, score, sara or mgdk";
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

/* The pair of segments (sfit_pair.h) over the frames the joint accepted:
 * a child template from the child markers, both clusters registered per
 * frame; the result replaces res.fit's centre, axis and mode (so the lab
 * centre, the trajectory and the skeleton use it). */
static sfit_status_t run_pair(const cli_frames_t *fr, int np, int nc, long first, long last,
                              const cli_joint_opts_t *o, cli_joint_out_t *out)
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
            blk[(size_t)(f - first) * (size_t)nc + (size_t)k] = *cli_frames_at(fr, f, np + k);
        }
    }
    st = sfit_cluster_from_frames(&ccl, blk, (size_t)(last - first + 1), (size_t)nc, &used_tpl);
    free(blk);
    if (st != SFIT_OK) {
        free(pr);
        return st;
    }
    cfg.method = (o->method == CLI_JOINT_DEFAULT) ? SFIT_PAIR_METHOD_DEFAULT : SFIT_PAIR_METHOD_SCORE;
    cfg.mode = (o->method == CLI_JOINT_SARA || o->mode == SFIT_MODE_PLANAR) ? SFIT_PAIR_MODE_HINGE
               : (o->mode == SFIT_MODE_SPHERE || o->method == CLI_JOINT_SCORE) ? SFIT_PAIR_MODE_BALL
                                                                              : SFIT_PAIR_MODE_AUTO;
    if (o->noise == 1) {
        cfg.noise = SFIT_PAIR_NOISE_GIVEN;
        cfg.marker_var = o->noise_var;
    }
    out->stage = "pair";
    st = sfit_pair_init(pr, &out->j.parent, &ccl, &cfg);
    out->pair_rejected = 0;
    for (f = first; f <= last && st == SFIT_OK; f++) {
        const sfit_vec3_t *row = cli_frames_at(fr, f, 0);
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

sfit_status_t cli_joint_mgdk_cov(const sfit_joint_t *j, const sfit_joint_result_t *res,
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
 * (cli_joint_mgdk_cov). */
static void mgdk_cov(const cli_frames_t *fr, int np, int nc, long first, long last,
                     const cli_joint_opts_t *o, cli_joint_out_t *out)
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
        const sfit_vec3_t *row = cli_frames_at(fr, f, 0);
        for (k = 0; k < np; k++) {
            pb[(size_t)(f - first) * (size_t)np + (size_t)k] = row[k];
        }
        for (k = 0; k < nc; k++) {
            cb[(size_t)(f - first) * (size_t)nc + (size_t)k] = row[np + k];
        }
    }
    out->mgdk_cov_ok = cli_joint_mgdk_cov(&out->j, &out->res, pb, cb, nf,
                                          out->mgdk_var_given ? o->noise_var : -1.0f,
                                          &out->mgdk_cov, &out->mgdk_var)
                       == SFIT_OK;
    free(pb);
    free(cb);
}

void cli_joint_print_flags_json(const cli_joint_out_t *out)
{
    if (!out->pair_used) {
        names_flags_json(stdout, NAMES_FIT, out->res.fit.flags);
        return;
    }
    names_flags_json(stdout, NAMES_PAIR, out->pair.flags);
}

void cli_joint_print_pair_json(const cli_joint_out_t *out)
{
    const sfit_pair_result_t *p = &out->pair;
    if (out->note != NULL) {
        printf(",\"note\":");
        json_out_str(stdout, out->note, 0);
    }
    if (!out->pair_used) {
        /* the multi-marker fit: its covariance (null when it has none) */
        const int untrusted = (out->res.fit.flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u;
        printf(",\"center_cov\":");
        if (out->mgdk_cov_ok) {
            json_out_mat(stdout, &out->mgdk_cov);
        } else {
            printf("null");
        }
        printf(",\"center_cov_bias\":\"not_included\",\"untrusted\":%s,\"reason\":\"%s\","
               "\"marker_noise\":{\"var\":%.9g,\"source\":\"%s\"}",
               untrusted ? "true" : "false", untrusted ? "leontief_ratio" : "none",
               (double)out->mgdk_var, out->mgdk_var_given ? "given" : "registration_residuals");
        return;
    }
    printf(",\"center_cov\":");
    json_out_mat(stdout, &p->center_cov);
    if (p->mode == SFIT_PAIR_MODE_HINGE) {
        printf(",\"axis_cov\":");
        json_out_mat(stdout, &p->axis_cov);
    }
    printf(",\"center_cov_model\":");
    json_out_mat(stdout, &p->center_cov_model);
    if (p->mode == SFIT_PAIR_MODE_HINGE) {
        printf(",\"axis_cov_model\":");
        json_out_mat(stdout, &p->axis_cov_model);
    }
    printf(",\"skin\":{\"rms\":%.9g,\"ratio\":%.9g},\"wobble_rms\":%.9g,\"info\":[",
           (double)p->sta_rms, (double)p->sta_ratio, (double)p->wobble_rms);
    {
        const char *sep = "";
        if ((p->info & (uint32_t)SFIT_PAIR_INFO_AXIS_FREE) != 0u) {
            printf("\"axis_free\"");
            sep = ",";
        }
        if ((p->info & (uint32_t)SFIT_PAIR_INFO_SKIN) != 0u) {
            printf("%s\"skin_motion\"", sep);
        }
    }
    printf("]");
    printf(",\"center_child\":");
    json_out_vec(stdout, p->center_c.v);
    printf(",\"untrusted\":%s,\"reason\":\"%s\",\"marker_noise\":{\"var\":%.9g,"
           "\"parent\":%.9g,\"child\":%.9g,\"source\":\"%s\"},\"misfit\":%.9g,"
           "\"model_rms\":%.9g,\"frames_pair\":%lu,\"frames_pair_rejected\":%ld",
           (p->flags & (uint32_t)SFIT_FLAG_UNTRUSTED) ? "true" : "false",
           names_pair_reason(p->reason),
           (double)p->marker_var, (double)p->marker_var_p, (double)p->marker_var_c,
           p->noise == SFIT_PAIR_NOISE_GIVEN ? "given" : "registration_residuals",
           (double)p->misfit, (double)p->rms, (unsigned long)p->frames, out->pair_rejected);
}

void cli_joint_print_pair_text(const cli_joint_out_t *out, const char *units, const char *indent)
{
    const sfit_pair_result_t *p = &out->pair;
    sfit_vec3_t w;
    if (out->note != NULL) {
        printf("%snote         %s\n", indent, out->note);
    }
    if (!out->pair_used) {
        if (out->mgdk_cov_ok && sfit_mat3_eig_sym(&out->mgdk_cov, &w, NULL) == SFIT_OK) {
            printf("%s95%% ellipse  semi-axes %.3g %.3g %.3g %s (centre; MGDK's bias at a small\n"
                   "%s             range of motion is not in it)\n",
                   indent, sqrt(7.8147 * (double)(w.v[2] > 0.0f ? w.v[2] : 0.0f)),
                   sqrt(7.8147 * (double)(w.v[1] > 0.0f ? w.v[1] : 0.0f)),
                   sqrt(7.8147 * (double)(w.v[0] > 0.0f ? w.v[0] : 0.0f)), units, indent);
        }
        printf("%smarker noise sigma %.4g %s (%s)\n", indent, sqrt((double)out->mgdk_var), units,
               out->mgdk_var_given ? "given" : "from the parent's registration residuals");
        return;
    }
    if (sfit_mat3_eig_sym(&p->center_cov, &w, NULL) == SFIT_OK) {
        /* 95 % ellipsoid: chi-square 3 dof quantile 7.815 */
        printf("%s95%% ellipse  semi-axes %.3g %.3g %.3g %s (centre; %s)\n", indent,
               sqrt(7.8147 * (double)(w.v[2] > 0.0f ? w.v[2] : 0.0f)),
               sqrt(7.8147 * (double)(w.v[1] > 0.0f ? w.v[1] : 0.0f)),
               sqrt(7.8147 * (double)(w.v[0] > 0.0f ? w.v[0] : 0.0f)), units,
               p->mode == SFIT_PAIR_MODE_HINGE ? "normal to the axis and along it" : "ball");
    }
    if (p->sta_rms > 0.0f && sfit_mat3_eig_sym(&p->center_cov_model, &w, NULL) == SFIT_OK) {
        printf("%sskin motion  the clusters move on the skin with the joint angle by about %.3g %s\n"
               "%s             at the joint; the centre is uncertain by %.3g %s from it alone\n"
               "%s             (95 %%, largest semi-axis; included above)\n",
               indent, (double)p->sta_rms, units, indent,
               sqrt(7.8147 * (double)(w.v[2] > 0.0f ? w.v[2] : 0.0f)), units, indent);
    }
    if (p->mode == SFIT_PAIR_MODE_HINGE) {
        const double t = (double)(p->axis_cov.m[0] + p->axis_cov.m[4] + p->axis_cov.m[8]);
        const double tm = (double)(p->axis_cov_model.m[0] + p->axis_cov_model.m[4]
                                   + p->axis_cov_model.m[8]);
        printf("%saxis 95%%     cone half-angle %.3g degrees (%.3g of it from an out-of-axis\n"
               "%s             rotation in step with the flexion; %.3g degrees rms seen)\n",
               indent, sqrt(5.9915 * (t > 0.0 ? t : 0.0)) * 57.29578,
               sqrt(5.9915 * (tm > 0.0 ? tm : 0.0)) * 57.29578, indent,
               (double)p->wobble_rms * 57.29578);
    }
    printf("%smarker noise sigma %.4g %s (parent %.4g, child %.4g; %s)\n", indent,
           sqrt((double)p->marker_var), units, sqrt((double)p->marker_var_p),
           sqrt((double)p->marker_var_c),
           p->noise == SFIT_PAIR_NOISE_GIVEN ? "given" : "from the registration residuals");
    if ((p->flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u) {
        printf("%swarning      untrusted: %s (docs/pair.md)\n", indent,
               names_pair_reason(p->reason));
    }
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
    if (o->noise == 1 && o->method == CLI_JOINT_MGDK) { /* the measured markers' noise, propagated by the library */
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
    if (o->noise == 2 && o->method == CLI_JOINT_MGDK) {
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
    if (o->method == CLI_JOINT_MGDK) {
        if (st == SFIT_OK) {
            mgdk_cov(fr, np, nc, first, last, o, out);
        }
        return out->st = st;
    }
    if (nc < 3) {
        if (o->method != CLI_JOINT_DEFAULT) {
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

sfit_status_t cli_joint_lab(const cli_frames_t *fr, int np, const cli_joint_out_t *out, long f,
                            sfit_vec3_t *center, sfit_vec3_t *axis)
{
    return sfit_joint_center_at(&out->j, &out->res, cli_frames_at(fr, f, 0), (size_t)np, center,
                                axis);
}
