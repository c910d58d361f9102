/* SPDX-License-Identifier: MIT */
/*
 * A user configuration (SFIT_USER_CONFIG) that sets every knob of
 * lib/include/sfit/sfit_config.h to a valid value other than its default.
 * The defines are unconditional on purpose: a header that defined a knob
 * before this file is read would trigger a redefinition warning (an error
 * under -Werror). tests/config/header_alone.c checks the integer values.
 */
#ifndef SFIT_TEST_USER_CONFIG_ALL_H
#define SFIT_TEST_USER_CONFIG_ALL_H

#define SFIT_JACOBI_MAX_SWEEPS 20
#define SFIT_FULL_SOLVER 0
#define SFIT_CHOL_PIVOT_EPS 1e-5f
#define SFIT_SUM_BLOCK 128u
#define SFIT_COORD_MAX_EXP 26
#define SFIT_MIN_SAMPLES 6u
#define SFIT_FEW_SAMPLES 30u
#define SFIT_PLANAR_RATIO 4e-3f
#define SFIT_COLLINEAR_RATIO 2e-5f
#define SFIT_COINCIDENT_ULPS 32.0f
#define SFIT_MIN_SPREAD 2e-9f
#define SFIT_ENABLE_ASSERT 1
#define SFIT_INCR_BLOCK 512u
#define SFIT_COVERAGE_BISECT_ITERS 48
#define SFIT_SELFCAL_MAX_ITERS 20
#define SFIT_SELFCAL_REL_TOL 2e-4f
#define SFIT_SELFCAL_MAX_TRUST 0.4f
#define SFIT_COV_MAX_TRUST 0.3f
#define SFIT_COV_MIN_SAMPLES 40u
#define SFIT_REFINE_MAX_ITERS 50
#define SFIT_REFINE_MAX_TRIALS 10
#define SFIT_REFINE_TOL 2e-5f
#define SFIT_GATE_WARMUP 32
#define SFIT_GATE_K 3.5f
#define SFIT_GATE_MIN_WINDOW 20u
#define SFIT_GATE_MAX_REJECT_PCT 30u
#define SFIT_CLUSTER_MAX_MARKERS 12
#define SFIT_CLUSTER_COLLINEAR_RATIO 3e-3f
#define SFIT_CLUSTER_TRACK_STEPS 4
#define SFIT_JOINT_MAX_CHILD 6
#define SFIT_IMU_KEEP 64
#define SFIT_IMU_DIFF_MAX 4
#define SFIT_IMU_GN_ITERS 15

#endif /* SFIT_TEST_USER_CONFIG_ALL_H */
