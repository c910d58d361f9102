/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_config.h
 * @brief Every compile-time tunable of sfit, with its default and range.
 *
 * Override a knob by defining it on the command line (-DSFIT_X=...) or in a
 * user header named by SFIT_USER_CONFIG (e.g. -DSFIT_USER_CONFIG=my_sfit.h).
 * Every public header includes this one (through sfit_types.h) before it
 * uses any knob, and the user header is read here before any default, so a
 * program sees the same values whichever sfit header it includes first.
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
 * bound makes the loop's worst case a compile-time constant. Below 8 the
 * screened solve of sfit_fit_moments() is off (every fit runs the full
 * solver, which may then stop with SFIT_E_NO_CONVERGENCE). Range 1..64.
 */
#ifndef SFIT_JACOBI_MAX_SWEEPS
#define SFIT_JACOBI_MAX_SWEEPS 12
#endif
#if (SFIT_JACOBI_MAX_SWEEPS < 1) || (SFIT_JACOBI_MAX_SWEEPS > 64)
#error "SFIT_JACOBI_MAX_SWEEPS must be in 1..64"
#endif

/**
 * @brief 1 (default): sfit_fit_moments() and sfit_fit_points() fall back to
 * the full solver (the Jacobi eigen-decomposition) whenever the screened
 * solve cannot prove its answer, and serve cfg.eigen = true, ::SFIT_MODE_PLANAR
 * and ::SFIT_NOISE_COV. 0: a firmware build without that fallback (an
 * application that only accumulates and fits then links about 2.6 KB less
 * code, tools/flopcount/footprint.sh record minimal_app_lean): the fit
 * returns ::SFIT_E_UNSUPPORTED, output untouched, where the full solver
 * would have run (the screen trips: near-planar, collinear, coincident or
 * ill-conditioned samples, a trust bound above SFIT_COV_MAX_TRUST, the
 * rounding flag; or one of those options). Below SFIT_COV_MIN_SAMPLES
 * samples such a build still fits (the flags are then decided by the count
 * alone: UNTRUSTED | COV_LIMIT). Modules built on sfit_fit_moments() (gate,
 * self-calibration, the incremental start) inherit the status (the
 * incremental start checks a full noise covariance with its own solve);
 * self-calibration takes its noise cap from the screen's lower bound of
 * lambda_min(C) and returns ::SFIT_E_UNSUPPORTED where the noise estimate
 * reaches it, and, as any fit, where the screen cannot prove one of its fits
 * (e.g. a trust ratio above SFIT_COV_MAX_TRUST, which the default build
 * fits and flags UNTRUSTED | COV_LIMIT: a 30-degree cap, r = 100, sigma = 3,
 * N = 1000); elsewhere its result is the default build's (exact false). The
 * others (multi, joint) keep the full solver. Range 0..1.
 */
#ifndef SFIT_FULL_SOLVER
#define SFIT_FULL_SOLVER 1
#endif
#if (SFIT_FULL_SOLVER != 0) && (SFIT_FULL_SOLVER != 1)
#error "SFIT_FULL_SOLVER must be 0 or 1"
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
 * @brief Terms in the inner level of every two-level sum (the moments
 * accumulator's blocks and the sample passes of self-calibration,
 * refinement and uncertainty) before it is folded into the outer level.
 * Larger blocks save a little work per sample, smaller ones bound the
 * rounding error inside a block. Range 2..65536.
 */
#ifndef SFIT_SUM_BLOCK
#define SFIT_SUM_BLOCK 64u
#endif
#if (SFIT_SUM_BLOCK < 2) || (SFIT_SUM_BLOCK > 65536)
#error "SFIT_SUM_BLOCK must be in 2..65536"
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
 * @brief Above this trust ratio a fit carries ::SFIT_FLAG_UNTRUSTED and
 * ::SFIT_FLAG_COV_LIMIT: the second-order terms of the centre error (bias
 * and skew along the weakest direction) are no longer small against its
 * covariance, and the reported 95 % ellipsoid was measured to cover less
 * than 92 % of the truth (docs/coverage.md). The cut is made on the fit's
 * own (estimated) trust ratio: where the true ratio lies around it, the
 * fits that pass are those whose ratio came out low, and they were
 * measured to cover 82-92 % (docs/coverage.md, "Where it still falls
 * short"). Range (0, 0.5].
 */
#ifndef SFIT_COV_MAX_TRUST
#define SFIT_COV_MAX_TRUST 0.35f
#endif

/**
 * @brief Below this many samples a fit carries ::SFIT_FLAG_UNTRUSTED and
 * ::SFIT_FLAG_COV_LIMIT: the 95 % ellipsoid of its reported covariance was
 * measured to cover 60-90 % at N = 10-30 (an estimated noise level or
 * trust ratio from this few samples is too rough; docs/coverage.md).
 * Range [6, 100000].
 */
#ifndef SFIT_COV_MIN_SAMPLES
#define SFIT_COV_MIN_SAMPLES 50u
#endif
#if (SFIT_COV_MIN_SAMPLES < 6) || (SFIT_COV_MIN_SAMPLES > 100000)
#error "SFIT_COV_MIN_SAMPLES must be in 6..100000"
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
 * @brief Smallest spread sqrt(lambda_max(C)) a fit accepts, in the units of
 * the samples: below it ::SFIT_E_DEGENERATE. The third moments are cubes of
 * the spread; much below 1e-9 they approach float's smallest normal number
 * (1.2e-38) and lose their digits, and the centre is then silently wrong
 * (seven exact points on a sphere of radius 1e-14 at the origin: 3e-3 r
 * off). Rescale the data (e.g. metres to micrometres) rather than lower
 * this. Range: > 0, at least 1e-12.
 */
#ifndef SFIT_MIN_SPREAD
#define SFIT_MIN_SPREAD 1e-9f
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
 * @brief Newton steps sfit_cluster_track() takes from the previous frame's
 * rotation before it gives up and runs the full solve
 * (sfit_cluster_register()). Each step costs a fraction of the full solve
 * (per call: docs/cost.md, "cluster_track" and "cluster_track_first"); a
 * step's convergence test is in docs/tracking.md. At 200 Hz two steps
 * converge for rotations up to several degrees per frame. Range 1..8.
 */
#ifndef SFIT_CLUSTER_TRACK_STEPS
#define SFIT_CLUSTER_TRACK_STEPS 3
#endif
#if (SFIT_CLUSTER_TRACK_STEPS < 1) || (SFIT_CLUSTER_TRACK_STEPS > 8)
#error "SFIT_CLUSTER_TRACK_STEPS must be in 1..8"
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


/* ---- Incremental estimator (sfit_incr.h) ---- */

/**
 * @brief Samples summed in the inner level of the incremental state before
 * it is folded into the outer level and the frame origin is moved to the
 * current mean (every n/8 samples while n < 8 SFIT_INCR_BLOCK, then every
 * SFIT_INCR_BLOCK samples). The rounding error of the centre grows like
 * sqrt(SFIT_INCR_BLOCK) + sqrt(N / SFIT_INCR_BLOCK); 256..4096 measure alike
 * (within 1e-5 r at N = 10^6). Range 2..65536.
 */
#ifndef SFIT_INCR_BLOCK
#define SFIT_INCR_BLOCK 1024u
#endif
#if (SFIT_INCR_BLOCK < 2) || (SFIT_INCR_BLOCK > 65536)
#error "SFIT_INCR_BLOCK must be in 2..65536"
#endif

/* ---- Coverage aids (sfit_coverage.h) ---- */

/**
 * @brief Iteration bound of the coverage inverses (bisection on theta in
 * [0, pi]). Each step halves the bracket; the loop also stops as soon as the
 * bracket no longer shrinks in float, which happens after at most ~40 steps
 * for any theta > 1e-5 rad. Range 8..128.
 */
#ifndef SFIT_COVERAGE_BISECT_ITERS
#define SFIT_COVERAGE_BISECT_ITERS 64
#endif
#if (SFIT_COVERAGE_BISECT_ITERS < 8) || (SFIT_COVERAGE_BISECT_ITERS > 128)
#error "SFIT_COVERAGE_BISECT_ITERS must be in 8..128"
#endif

/* ---- Self-calibration (sfit_selfcal.h) ---- */

/**
 * @brief Iteration bound of the self-calibration (each iteration = one pass
 * over the samples + one solve). The convergence test compares two
 * successive noise estimates, the first one against nothing (0): with 1
 * or 2 passes every noisy fit ended in SFIT_E_NO_CONVERGENCE; caps of 30 to
 * 120 degrees converge in 3. Range 3..100.
 */
#ifndef SFIT_SELFCAL_MAX_ITERS
#define SFIT_SELFCAL_MAX_ITERS 12
#endif
#if (SFIT_SELFCAL_MAX_ITERS < 3) || (SFIT_SELFCAL_MAX_ITERS > 100)
#error "SFIT_SELFCAL_MAX_ITERS must be in 3..100"
#endif

/**
 * @brief Convergence: stop when |sigma^2_new - sigma^2_old| <= this times
 * sigma^2_new. Much below the estimate's own spread (sqrt(2/N)). Range
 * (0, 0.1].
 */
#ifndef SFIT_SELFCAL_REL_TOL
#define SFIT_SELFCAL_REL_TOL 1e-4f
#endif

/**
 * @brief Cap on the estimated noise: sigma^2 <= SFIT_SELFCAL_MAX_TRUST *
 * lambda_min(C), i.e. a trust ratio of at most this (0.5 = the Leontief
 * bound; C' keeps half of C's smallest eigenvalue). Range (0, 0.9].
 */
#ifndef SFIT_SELFCAL_MAX_TRUST
#define SFIT_SELFCAL_MAX_TRUST 0.5f
#endif

/* ---- Geometric refinement (sfit_refine.h) ---- */

/** @brief Iteration bound (linearisations) of the refinement. Range 1..200. */
#ifndef SFIT_REFINE_MAX_ITERS
#define SFIT_REFINE_MAX_ITERS 30
#endif
#if (SFIT_REFINE_MAX_ITERS < 1) || (SFIT_REFINE_MAX_ITERS > 200)
#error "SFIT_REFINE_MAX_ITERS must be in 1..200"
#endif

/** @brief Damping trials per iteration (lambda x10 each). Range 1..20. */
#ifndef SFIT_REFINE_MAX_TRIALS
#define SFIT_REFINE_MAX_TRIALS 8
#endif
#if (SFIT_REFINE_MAX_TRIALS < 1) || (SFIT_REFINE_MAX_TRIALS > 20)
#error "SFIT_REFINE_MAX_TRIALS must be in 1..20"
#endif

/**
 * @brief Default convergence threshold: the centre step, relative to the
 * radius. 1e-5 is ~ 170 float epsilons: above the rounding noise of the
 * steps, below any statistical error worth reporting. Range [1e-7, 1e-2].
 */
#ifndef SFIT_REFINE_TOL
#define SFIT_REFINE_TOL 1e-5f
#endif

/* ---- Outlier gate (sfit_gate.h) ---- */

/**
 * @brief Samples buffered in the gate for the robust start.
 * More samples give a safer start on small caps, fewer save RAM. The
 * buffer must span the motion: at 100 Hz, 64 samples are 0.64 s. With 5 %
 * gross outliers, 32 let about one stream in 100 start on a wrong sphere
 * (measured, docs/beyond.md), 64 about one in 1000. Range 16..256, a
 * multiple of 8.
 */
#ifndef SFIT_GATE_WARMUP
#define SFIT_GATE_WARMUP 64
#endif
#if (SFIT_GATE_WARMUP < 16) || (SFIT_GATE_WARMUP > 256) || (SFIT_GATE_WARMUP % 8 != 0)
#error "SFIT_GATE_WARMUP must be a multiple of 8 in 16..256"
#endif

/** @brief Default gate width in sigmas (cfg.k = 0). Float; not range-checked. */
#ifndef SFIT_GATE_K
#define SFIT_GATE_K 4.0f
#endif

/** @brief Residuals needed in a window before sigma^2 is re-estimated. Range >= 5. */
#ifndef SFIT_GATE_MIN_WINDOW
#define SFIT_GATE_MIN_WINDOW 16u
#endif
#if SFIT_GATE_MIN_WINDOW < 5
#error "SFIT_GATE_MIN_WINDOW must be >= 5"
#endif

/**
 * @brief Rejection rate (percent of the samples offered between two
 * refreshes) above which the gate widens (sigma^2 x 4) instead of trusting
 * its noise estimate. Gross outliers above this rate cannot be told from a
 * wrong noise level. Range 1..99.
 */
#ifndef SFIT_GATE_MAX_REJECT_PCT
#define SFIT_GATE_MAX_REJECT_PCT 25u
#endif
#if (SFIT_GATE_MAX_REJECT_PCT < 1) || (SFIT_GATE_MAX_REJECT_PCT > 99)
#error "SFIT_GATE_MAX_REJECT_PCT must be in 1..99"
#endif

/**
 * @brief Samples the IMU joint keeps for its solve (sfit_imu.h): each one
 * the most rotating sample of a window of the stream, the windows doubling
 * as the stream grows. State: 76 bytes per sample. Range 32..254, even.
 */
#ifndef SFIT_IMU_KEEP
#define SFIT_IMU_KEEP 128
#endif
#if (SFIT_IMU_KEEP < 32) || (SFIT_IMU_KEEP > 254) || (SFIT_IMU_KEEP % 2 != 0)
#error "SFIT_IMU_KEEP must be even, in 32..254"
#endif

/**
 * @brief Largest half-width, in samples, of the IMU joint's central
 * difference of the angular rate (its ring holds 2 h + 1 samples). Range 1..16.
 */
#ifndef SFIT_IMU_DIFF_MAX
#define SFIT_IMU_DIFF_MAX 8
#endif
#if (SFIT_IMU_DIFF_MAX < 1) || (SFIT_IMU_DIFF_MAX > 16)
#error "SFIT_IMU_DIFF_MAX must be in 1..16"
#endif

/** @brief Gauss-Newton iterations of each IMU joint solve. Range 8..60. */
#ifndef SFIT_IMU_GN_ITERS
#define SFIT_IMU_GN_ITERS 30
#endif
#if (SFIT_IMU_GN_ITERS < 8) || (SFIT_IMU_GN_ITERS > 60)
#error "SFIT_IMU_GN_ITERS must be in 8..60"
#endif

#endif /* SFIT_CONFIG_H */
