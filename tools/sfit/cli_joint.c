/* SPDX-License-Identifier: MIT */
/** @file cli_joint.c  A joint run's options and printing (cli_joint.h). */
#include "cli_joint.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

const char *cli_joint_method_opt(void *dst, const char *v)
{
    static const char *const names[] = {"default", "score", "sara", "mgdk"};
    joint_run_opts_t *o = (joint_run_opts_t *)dst;
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
    joint_run_opts_t *o = (joint_run_opts_t *)dst;
    if (frames_parse_range(v, &o->first, &o->last) != 0) {
        return "--frames needs F:L, whole numbers with 0 <= F <= L";
    }
    return NULL;
}

const char *cli_joint_noise_opt(void *dst, const char *v)
{
    joint_run_opts_t *o = (joint_run_opts_t *)dst;
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

void cli_joint_print_flags_json(const joint_run_out_t *out)
{
    if (!out->pair_used) {
        names_flags_json(stdout, NAMES_FIT, out->res.fit.flags);
        return;
    }
    names_flags_json(stdout, NAMES_PAIR, out->pair.flags);
}

void cli_joint_print_pair_json(const joint_run_out_t *out)
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

void cli_joint_print_pair_text(const joint_run_out_t *out, const char *units, const char *indent)
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
