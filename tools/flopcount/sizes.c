/* SPDX-License-Identifier: MIT */
/**
 * @file sizes.c
 * @brief sizeof() of every public state / result / option struct, for the
 * footprint report, without running anything: each FC_SIZE(T) defines an
 * array `fc_sizeof_T` of sizeof(T) bytes; `arm-none-eabi-nm -S` on the
 * object prints the sizes (tools/flopcount/footprint.sh). This object is
 * never linked into anything.
 * Adding a struct = one FC_SIZE() line.
 */
#include "sfit/sfit.h"

#define FC_SIZE(T)                                                                                 \
    extern unsigned char fc_sizeof_##T[sizeof(T)];                                                 \
    unsigned char fc_sizeof_##T[sizeof(T)]

FC_SIZE(sfit_moments_t);
FC_SIZE(sfit_fit_cfg_t);
FC_SIZE(sfit_result_t);
FC_SIZE(sfit_vec3_t);
FC_SIZE(sfit_mat3_t);

FC_SIZE(sfit_multi_cfg_t);
FC_SIZE(sfit_multi_result_t);
FC_SIZE(sfit_noise_est_t);
FC_SIZE(sfit_incr_t);
FC_SIZE(sfit_sphere_t);
FC_SIZE(sfit_gate_t);
FC_SIZE(sfit_gate_cfg_t);
FC_SIZE(sfit_selfcal_result_t);
FC_SIZE(sfit_refine_result_t);
FC_SIZE(sfit_uncert_t);
FC_SIZE(sfit_cluster_t);
FC_SIZE(sfit_pose_t);
FC_SIZE(sfit_cluster_track_t);
FC_SIZE(sfit_joint_t);
FC_SIZE(sfit_joint_cfg_t);
FC_SIZE(sfit_joint_result_t);
FC_SIZE(sfit_pair_t);
FC_SIZE(sfit_pair_cfg_t);
FC_SIZE(sfit_pair_result_t);
FC_SIZE(sfit_imu_t);
FC_SIZE(sfit_imu_cfg_t);
FC_SIZE(sfit_imu_result_t);
