/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pair.c
 * @brief A pair of segments (SCoRE / SARA) as a stream: first stub (the
 * API of sfit_pair.h compiles; the solve is being written).
 */
#include "sfit/sfit_pair.h"

#include <string.h>

const sfit_pair_cfg_t sfit_pair_cfg_default = {
    .method = SFIT_PAIR_METHOD_DEFAULT, .mode = SFIT_PAIR_MODE_AUTO,
    .noise = SFIT_PAIR_NOISE_RESIDUAL, .marker_var = 0.0f, .hinge_ratio = 0.0f,
    .max_trust = 0.0f, .max_misfit = 0.0f, .axis_tol = 0.0f, .min_frames = 0u};

sfit_status_t sfit_pair_init(sfit_pair_t *s, const sfit_cluster_t *parent,
                             const sfit_cluster_t *child, const sfit_pair_cfg_t *cfg)
{
    (void)s; (void)parent; (void)child; (void)cfg;
    return SFIT_E_UNSUPPORTED;
}

sfit_status_t sfit_pair_reset(sfit_pair_t *s)
{
    (void)s;
    return SFIT_E_UNSUPPORTED;
}

sfit_status_t sfit_pair_add(sfit_pair_t *s, const sfit_pose_t *pose_p,
                            const sfit_cluster_fit_t *fit_p, const sfit_pose_t *pose_c,
                            const sfit_cluster_fit_t *fit_c)
{
    (void)s; (void)pose_p; (void)fit_p; (void)pose_c; (void)fit_c;
    return SFIT_E_UNSUPPORTED;
}

sfit_status_t sfit_pair_add_markers(sfit_pair_t *s, const sfit_cluster_t *parent,
                                    const sfit_vec3_t *pm, size_t n_pm,
                                    const sfit_cluster_t *child, const sfit_vec3_t *cm,
                                    size_t n_cm)
{
    (void)s; (void)parent; (void)pm; (void)n_pm; (void)child; (void)cm; (void)n_cm;
    return SFIT_E_UNSUPPORTED;
}

sfit_status_t sfit_pair_solve(const sfit_pair_t *s, sfit_pair_result_t *out)
{
    (void)s; (void)out;
    return SFIT_E_UNSUPPORTED;
}
