/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_config.h
 * @brief Every compile-time tunable of sfit, with its default and range.
 *
 * Override a knob by defining it on the command line (-DSFIT_X=...) or in a
 * user header named by SFIT_USER_CONFIG (e.g. -DSFIT_USER_CONFIG=my_sfit.h),
 * which is included first.
 */
#ifndef SFIT_CONFIG_H
#define SFIT_CONFIG_H

#define SFIT_STR_(x) #x
#define SFIT_STR(x) SFIT_STR_(x)

#ifdef SFIT_USER_CONFIG
#include SFIT_STR(SFIT_USER_CONFIG)
#endif

/**
 * @brief Upper bound on cyclic Jacobi sweeps (each sweep = 3 rotations).
 * A symmetric 3x3 matrix converges to float precision in 4-6 sweeps; the
 * bound makes the loop's worst case a compile-time constant. Range 1..64.
 */
#ifndef SFIT_JACOBI_MAX_SWEEPS
#define SFIT_JACOBI_MAX_SWEEPS 12
#endif
#if (SFIT_JACOBI_MAX_SWEEPS < 1) || (SFIT_JACOBI_MAX_SWEEPS > 64)
#error "SFIT_JACOBI_MAX_SWEEPS must be in 1..64"
#endif

/**
 * @brief Cholesky pivot threshold, relative to the largest diagonal entry.
 * A pivot <= SFIT_CHOL_PIVOT_EPS * max(diag) is reported as not positive
 * definite. Range (0, 1e-2].
 */
#ifndef SFIT_CHOL_PIVOT_EPS
#define SFIT_CHOL_PIVOT_EPS 1e-6f
#endif

/**
 * @brief Samples folded into the inner level of the moments accumulator
 * before the block is merged into the running total (two-level summation,
 * DESIGN.md section 2). Larger blocks save a little work per sample, smaller
 * ones bound the rounding error inside a block. Range 2..65536.
 */
#ifndef SFIT_MOMENTS_BLOCK
#define SFIT_MOMENTS_BLOCK 64u
#endif
#if (SFIT_MOMENTS_BLOCK < 2) || (SFIT_MOMENTS_BLOCK > 65536)
#error "SFIT_MOMENTS_BLOCK must be in 2..65536"
#endif

/**
 * @brief Largest accepted magnitude of a coordinate, as a power of two.
 * A sample with |x_i| >= 2^SFIT_COORD_MAX_EXP is rejected with
 * ::SFIT_E_RANGE so that cubes of differences summed over 2^32 samples stay
 * finite in float. The default 2^27 (~1.3e8) is 134 km in millimetres.
 * Range 1..30.
 */
#ifndef SFIT_COORD_MAX_EXP
#define SFIT_COORD_MAX_EXP 27
#endif
#if (SFIT_COORD_MAX_EXP < 1) || (SFIT_COORD_MAX_EXP > 30)
#error "SFIT_COORD_MAX_EXP must be in 1..30"
#endif

/** @brief Fewest samples a sphere or circle solution accepts (>= 4). */
#ifndef SFIT_MIN_SAMPLES
#define SFIT_MIN_SAMPLES 4u
#endif
#if SFIT_MIN_SAMPLES < 4
#error "SFIT_MIN_SAMPLES must be >= 4"
#endif

/**
 * @brief Below this many samples a result carries ::SFIT_FLAG_FEW_SAMPLES:
 * the O(1/N) terms the estimators neglect are no longer small.
 */
#ifndef SFIT_FEW_SAMPLES
#define SFIT_FEW_SAMPLES 20u
#endif

/**
 * @brief Default planar threshold: lambda_min(C) / lambda_max(C) below this
 * means "near-planar" (a hinge / cylindrical joint). In auto mode the planar
 * solution is used; in sphere mode the result is flagged. Real knee markers
 * measure 1/450..1/2300, hip markers 1/100..1/40. Range (0, 0.5).
 */
#ifndef SFIT_PLANAR_RATIO
#define SFIT_PLANAR_RATIO 5e-3f
#endif

/**
 * @brief lambda_mid(C) / lambda_max(C) below this means the samples are
 * collinear (an arc of about 0.7 degrees or less): ::SFIT_E_DEGENERATE.
 */
#ifndef SFIT_COLLINEAR_RATIO
#define SFIT_COLLINEAR_RATIO 1e-5f
#endif

/**
 * @brief The samples are coincident when the spread sqrt(lambda_max(C)) is
 * no more than this many float epsilons of the largest coordinate of the
 * mean (rounding noise): ::SFIT_E_DEGENERATE.
 */
#ifndef SFIT_COINCIDENT_ULPS
#define SFIT_COINCIDENT_ULPS 64.0f
#endif

/**
 * @brief Most markers in one rigid cluster (sfit_cluster.h). Sets the size
 * of ::sfit_cluster_t (12 B per marker) and bounds the loops over markers.
 * Range 3..64.
 */
#ifndef SFIT_CLUSTER_MAX_MARKERS
#define SFIT_CLUSTER_MAX_MARKERS 8
#endif
#if (SFIT_CLUSTER_MAX_MARKERS < 3) || (SFIT_CLUSTER_MAX_MARKERS > 64)
#error "SFIT_CLUSTER_MAX_MARKERS must be in 3..64"
#endif

/**
 * @brief A cluster whose markers are within this fraction of its size from
 * a line is collinear: the rotation about that line is not determined and
 * the registration returns ::SFIT_E_DEGENERATE. Tested on s2/s1, the ratio
 * of the two largest singular values of the cross-covariance (for a rigid
 * motion, lambda_mid/lambda_max of the template's scatter). The float
 * resolution of s2/s1 is about 3e-4. Range [1e-3, 0.5).
 */
#ifndef SFIT_CLUSTER_COLLINEAR_RATIO
#define SFIT_CLUSTER_COLLINEAR_RATIO 2e-3f
#endif

/**
 * @brief Most child markers of one joint (sfit_joint.h). Sets the size of
 * ::sfit_joint_t (one moments accumulator, about 140 B, per marker).
 * Range 1..64.
 */
#ifndef SFIT_JOINT_MAX_CHILD
#define SFIT_JOINT_MAX_CHILD 8
#endif
#if (SFIT_JOINT_MAX_CHILD < 1) || (SFIT_JOINT_MAX_CHILD > 64)
#error "SFIT_JOINT_MAX_CHILD must be in 1..64"
#endif

/** @brief 1 enables internal invariant checks through SFIT_ASSERT. */
#ifndef SFIT_ENABLE_ASSERT
#define SFIT_ENABLE_ASSERT 0
#endif

#endif /* SFIT_CONFIG_H */
