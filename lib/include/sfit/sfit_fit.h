/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_fit.h
 * @brief Sphere and circle estimators: GDKE, UGDK, planar (cylindrical joint).
 * @defgroup sfit_fit Sphere / circle fit
 * @{
 *
 * Derivation and notes: docs/api.md#fit
 */
#ifndef SFIT_FIT_H
#define SFIT_FIT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sfit_moments.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Which solution to compute. */
typedef enum sfit_mode {
    SFIT_MODE_AUTO = 0,   /**< Sphere when well conditioned, planar when near-planar. */
    SFIT_MODE_SPHERE = 1, /**< Always the sphere solution (flagged if near-planar). */
    SFIT_MODE_PLANAR = 2  /**< Always the planar (circle) solution. */
} sfit_mode_t;

/** @brief Measurement-noise model for the bias compensation. */
typedef enum sfit_noise_kind {
    SFIT_NOISE_NONE = 0, /**< No compensation: GDKE. */
    SFIT_NOISE_ISO = 1,  /**< Sigma_hat = noise_var * I: UGDK. */
    SFIT_NOISE_COV = 2   /**< Sigma_hat = noise_cov (symmetric 3x3): UGDK. */
} sfit_noise_kind_t;

/** @brief Options of a fit. Start from ::sfit_fit_cfg_default. */
typedef struct sfit_fit_cfg {
    sfit_mode_t mode;            /**< Solution to compute. */
    sfit_noise_kind_t noise;     /**< Noise model. */
    bool eigen;                  /**< false (default): the screened solve, which skips the
                                      eigen-decomposition when a cheap bound proves the
                                      sphere well conditioned, not near-planar,
                                      trusted and inside the coverage limit
                                      (SFIT_COV_MAX_TRUST, SFIT_COV_MIN_SAMPLES)
                                      (result: exact false). true: always the full
                                      solver (eigenvalues, axis, exact trust ratio).
                                      A byte other than 0/1: SFIT_E_ARG. */
    float noise_var;             /**< sigma^2 for SFIT_NOISE_ISO (>= 0, finite). */
    sfit_mat3_t noise_cov;       /**< Sigma for SFIT_NOISE_COV: symmetric positive
                                      semi-definite; the lower triangle is read.
                                      A matrix that is not PSD (a negative principal
                                      minor, the determinant included, beyond 16 ulps
                                      of rounding) is rejected with SFIT_E_ARG. */
    float planar_ratio;          /**< lambda_min/lambda_max threshold; 0 = SFIT_PLANAR_RATIO.
                                      The ratio is taken on C' = C - Sigma_hat when a
                                      noise model is given (the noise-corrected
                                      covariance UGDK solves), on C otherwise. */
} sfit_fit_cfg_t;

/** @brief Defaults: auto mode, no noise compensation (GDKE), screened solve. */
extern const sfit_fit_cfg_t sfit_fit_cfg_default;

/** @brief Which estimator produced a result. */
typedef enum sfit_method {
    SFIT_METHOD_GDKE = 0, /**< No noise compensation. */
    SFIT_METHOD_UGDK = 1  /**< Noise-compensated (C' = C - Sigma_hat). */
} sfit_method_t;

/** @brief A fit. Written only when the solve returns SFIT_OK; always finite. */
typedef struct sfit_result {
    sfit_vec3_t center;      /**< Sphere centre, or circle centre in planar mode. */
    float radius;            /**< Sphere or circle radius. */
    uint32_t n;              /**< Samples used. */
    sfit_vec3_t eigenvalues; /**< Eigenvalues of C, ascending (zero when exact is false). */
    sfit_vec3_t axis;        /**< (Zero when exact is false.) Unit eigenvector of the dropped (planar) or smallest
                                  (sphere) eigenvalue: the hinge axis / cap axis line;
                                  sign: largest-magnitude component positive. */
    float trust_ratio;       /**< rho(C^-1 Sigma_hat), C the measured sample covariance
                                  (0 for GDKE); when exact is false, an upper bound of it
                                  (below 1/2: the screen passed only for a trusted fit). It is also the factor by which
                                  GDKE shrinks the centre offset along the weakest
                                  direction: GDKE's cap bias ~ trust_ratio * |c - m|. */
    float leontief_ratio;    /**< rho(C'^-1 Sigma_hat) = trust/(1 - trust): the estimate of
                                  the Leontief ratio rho(C0^-1 Sigma) (C0 = noise-free covariance,
                                  estimated by C'); SFIT_FLAG_UNTRUSTED when >= 1 (and
                                  with SFIT_FLAG_COV_LIMIT when trust_ratio >
                                  SFIT_COV_MAX_TRUST or n < SFIT_COV_MIN_SAMPLES). */
    uint32_t flags;          /**< Bit mask of ::sfit_flag. */
    sfit_method_t method;    /**< GDKE or UGDK. */
    sfit_mode_t mode;        /**< Solution used: SFIT_MODE_SPHERE or SFIT_MODE_PLANAR. */
    bool exact;              /**< true: the full solver ran (eigenvalues, axis, exact trust
                                  ratios); false: the screened solve (same centre, radius,
                                  status and flags; eigenvalues and axis zero, trust
                                  ratios are upper bounds). */
} sfit_result_t;

/**
 * @brief Solve from an accumulator (the accumulator is not modified; solve
 * can be called again after more samples).
 * @param[in]  m    Accumulator.
 * @param[in]  cfg  Options; NULL = ::sfit_fit_cfg_default.
 * @param[out] out  Result; written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL m/out, or an invalid option (mode, noise kind, eigen's byte not 0/1,
 *                            negative/non-finite variance, a covariance that is not
 *                            finite or fails the semi-definiteness checks)
 * @retval SFIT_E_TOO_FEW     fewer than SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_DEGENERATE  coincident or collinear samples; a spread
 *                            sqrt(lambda_max(C)) below SFIT_MIN_SPREAD (too small
 *                            for float: rescale the data); or near-planar
 *                            samples whose sphere system is singular (GDKE)
 * @retval SFIT_E_NOT_POSDEF  C' = C - Sigma_hat is not positive definite
 *                            (on the kept directions in planar mode)
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @retval SFIT_E_RANGE       the result would not be finite
 * @retval SFIT_E_UNSUPPORTED built with SFIT_FULL_SOLVER 0 only: the screened
 *                            solve cannot prove this fit (or cfg asks for
 *                            eigen, planar mode or a full covariance)
 * @par Cost  222 FLOPs (GDKE), 224 (UGDK, sigma^2 I) when the screen passes
 *            (cfg.eigen false); 445 / 458 with the full solver, the same at
 *            any N (tools/flopcount: solve_gdke, solve_gdke_500, solve_ugdk,
 *            solve_gdke_eigen, solve_ugdk_eigen).
 * @par Range  An OK result without SFIT_FLAG_ROUNDING is within 1e-4 r of the
 *             double-precision fit of the same samples, for a spread >=
 *             SFIT_MIN_SPREAD and coordinates below 2^27 (docs/api.md#fit).
 *             SFIT_FLAG_ROUNDING: FLT_EPSILON (cond(C') K(N) + max|c_i| / r)
 *             > 1e-4, K(N)^2 = 0.25 (N/SFIT_SUM_BLOCK + 1) + 4 g(N), g = N up
 *             to SFIT_SUM_BLOCK, SFIT_SUM_BLOCK^3 / N^2 above: small caps at
 *             any N (cond(C') above ~50 at N = 64, ~200 at N = 4), many
 *             samples on larger caps, or |c|/r above ~840 (issue 32).
 */
sfit_status_t sfit_fit_moments(const sfit_moments_t *m, const sfit_fit_cfg_t *cfg,
                             sfit_result_t *out);

/**
 * @brief The fit with the default options (::sfit_fit_cfg_default) by the
 * full solver alone, for the smallest firmware: it links neither the screen
 * nor the noise models (an accumulator and this fit: 4034 B of sfit code
 * at -Os on Cortex-M4F, against 6470 B with sfit_fit_moments(); docs/cost.md,
 * tools/flopcount/footprint.sh records minimal_app and minimal_app_screened). The result is that of
 * sfit_fit_moments(m, &cfg, out) with cfg the defaults and cfg.eigen true,
 * bit for bit: the same centre, radius, status and flags as
 * sfit_fit_moments(m, NULL, out), with exact always true (eigenvalues and
 * axis filled).
 * @param[in]  m    Accumulator (not modified).
 * @param[out] out  Result; written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL m or out
 * @retval SFIT_E_TOO_FEW     fewer than SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_DEGENERATE  coincident or collinear samples, a spread below
 *                            SFIT_MIN_SPREAD, or a singular sphere system
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @retval SFIT_E_RANGE       the result would not be finite
 * @par Cost  444 FLOPs (tools/flopcount: solve_default), the full solver's
 *            path; also in a build with SFIT_FULL_SOLVER 0 (it is the plain
 *            solver, not the screen's fallback).
 * @par Range  As sfit_fit_moments().
 */
sfit_status_t sfit_fit_moments_default(const sfit_moments_t *m, sfit_result_t *out);

/**
 * @brief Fit a caller-owned array of samples (accumulates, then solves).
 * @param[in]  pts  Array of n samples.
 * @param[in]  n    Sample count.
 * @param[in]  cfg  Options; NULL = defaults.
 * @param[out] out  Result; written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL out, NULL pts with n > 0, or an invalid option
 * @retval SFIT_E_NONFINITE   a sample holds NaN or Inf
 * @retval SFIT_E_RANGE       a coordinate out of range, or the result not finite
 * @retval SFIT_E_UNSUPPORTED as sfit_fit_moments() (SFIT_FULL_SOLVER 0 only)
 * @retval SFIT_E_TOO_FEW     n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_DEGENERATE  coincident, collinear or (sphere) planar samples
 * @retval SFIT_E_NOT_POSDEF  C - Sigma_hat not positive definite
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @par Cost  n moments_add plus one sfit_fit_moments() (tools/flopcount: batch_total).
 */
sfit_status_t sfit_fit_points(const sfit_vec3_t *pts, size_t n, const sfit_fit_cfg_t *cfg,
                             sfit_result_t *out);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_FIT_H */
