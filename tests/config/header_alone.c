/* SPDX-License-Identifier: MIT */
/*
 * Compiled once per public header (SFIT_TEST_HEADER) and once per library
 * source (SFIT_TEST_SOURCE), alone, with SFIT_USER_CONFIG =
 * tests/config/user_config_all.h, -Werror and the project warning set
 * (ctest sfit.config.*). It fails to compile when the header does not
 * stand alone, when a knob is defined before the user configuration is
 * read (redefinition warning), or when the header sees a default instead
 * of the user's value.
 */
#ifdef SFIT_TEST_SOURCE
#include SFIT_TEST_SOURCE
#else
#include SFIT_TEST_HEADER
#endif

#if SFIT_JACOBI_MAX_SWEEPS != 20 || SFIT_FULL_SOLVER != 0 || SFIT_SUM_BLOCK != 128u || SFIT_COORD_MAX_EXP != 26
#error "user configuration not seen (core knobs)"
#endif
#if SFIT_MIN_SAMPLES != 6u || SFIT_FEW_SAMPLES != 30u || SFIT_ENABLE_ASSERT != 1 || SFIT_COV_MIN_SAMPLES != 40u
#error "user configuration not seen (sample knobs)"
#endif
#if SFIT_INCR_BLOCK != 512u || SFIT_COVERAGE_BISECT_ITERS != 48
#error "user configuration not seen (incr / coverage knobs)"
#endif
#if SFIT_SELFCAL_MAX_ITERS != 20 || SFIT_REFINE_MAX_ITERS != 50 || SFIT_REFINE_MAX_TRIALS != 10
#error "user configuration not seen (iteration knobs)"
#endif
#if SFIT_GATE_WARMUP != 32 || SFIT_GATE_MIN_WINDOW != 20u || SFIT_GATE_MAX_REJECT_PCT != 30u
#error "user configuration not seen (gate knobs)"
#endif
#if SFIT_CLUSTER_MAX_MARKERS != 12 || SFIT_JOINT_MAX_CHILD != 6 || SFIT_CLUSTER_TRACK_STEPS != 4
#error "user configuration not seen (cluster / joint knobs)"
#endif
#if SFIT_IMU_KEEP != 64 || SFIT_IMU_DIFF_MAX != 4 || SFIT_IMU_GN_ITERS != 15
#error "user configuration not seen (IMU joint knobs)"
#endif

/* The float knobs, read once so that a typo in a default is compiled. */
float sfit_test_float_knobs(void);
float sfit_test_float_knobs(void)
{
    return SFIT_CHOL_PIVOT_EPS + SFIT_PLANAR_RATIO + SFIT_COLLINEAR_RATIO + SFIT_COINCIDENT_ULPS
           + SFIT_SELFCAL_REL_TOL + SFIT_SELFCAL_MAX_TRUST + SFIT_COV_MAX_TRUST + SFIT_REFINE_TOL + SFIT_GATE_K
           + SFIT_CLUSTER_COLLINEAR_RATIO;
}
