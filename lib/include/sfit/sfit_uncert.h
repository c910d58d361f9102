/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_uncert.h
 * @brief How sure a sphere fit is: covariance of the centre, variance of the
 * radius (and their coupling), from the moments or from the samples.
 * @defgroup sfit_uncert Fit uncertainty
 * @{
 *
 * Derivation and notes: docs/api.md#uncert
 */
#ifndef SFIT_UNCERT_H
#define SFIT_UNCERT_H

#include <stddef.h>

#include "sfit_moments.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Where the noise variance given to the uncertainty comes from. */
typedef enum sfit_uncert_noise {
    SFIT_UNCERT_NOISE_KNOWN = 0,    /**< A constant known beforehand (calibration). */
    SFIT_UNCERT_NOISE_ESTIMATED = 1 /**< Estimated from the same samples (self-calibration,
                                         refinement residuals). */
} sfit_uncert_noise_t;

/** @brief Uncertainty of a sphere fit. Written only on SFIT_OK; always finite. */
typedef struct sfit_uncert {
    sfit_mat3_t center_cov;     /**< Cov(c) (unit^2), symmetric, row-major. */
    float radius_var;           /**< Var(r) (unit^2), first order. */
    float center_radius_cov[3]; /**< Cov(c, r) (unit^2), first order. */
    float noise_var;            /**< The sigma^2 used. */
} sfit_uncert_t;

/**
 * @brief Uncertainty of a fit from the accumulator alone (O(1); no samples
 * kept): first- plus second-order centre covariance, first-order radius.
 * @param[in]  m          Accumulator of the samples that were fitted.
 * @param[in]  center     Fitted centre (UGDK, self-calibrated or refined).
 * @param[in]  radius     Fitted radius (> 0).
 * @param[in]  noise_var  sigma^2 (>= 0; 0 gives an all-zero covariance).
 * @param[in]  kind       Where sigma^2 comes from (sign s of the a a^T term).
 * @param[out] out        Written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer, bad kind, negative noise_var or radius <= 0
 * @retval SFIT_E_NONFINITE   non-finite centre, radius or noise_var
 * @retval SFIT_E_TOO_FEW     fewer than SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_NOT_POSDEF  C - sigma^2 I is not positive definite (sphere
 *                            ill-posed: near-planar samples, or the noise too large)
 * @retval SFIT_E_RANGE       a result would not be finite, or a corrupted
 *                            accumulator (statistics not finite: sfit_moments_stats())
 */
sfit_status_t sfit_uncert_moments(const sfit_moments_t *m, const sfit_vec3_t *center,
                                  float radius, float noise_var, sfit_uncert_noise_t kind,
                                  sfit_uncert_t *out);

/**
 * @brief First-order uncertainty sigma^2 (J^T J)^-1 of a fit, from the
 * samples (one pass for the mean direction, one for the centred sums; the
 * centre block is formed as sum (u - u_mean)(u - u_mean)^T, no cancellation).
 * @param[in]  pts        n samples (caller-owned).
 * @param[in]  n          Sample count (>= SFIT_MIN_SAMPLES).
 * @param[in]  center     Fitted centre.
 * @param[in]  radius     Fitted radius (> 0; only checked, the directions carry r).
 * @param[in]  noise_var  sigma^2 (>= 0).
 * @param[out] out        Written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer, noise_var < 0 or radius <= 0
 * @retval SFIT_E_TOO_FEW     n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_NONFINITE   a sample, the centre, radius or noise_var holds NaN or Inf
 * @retval SFIT_E_DEGENERATE  a sample at the centre, or the directions span
 *                            less than 3 dimensions (J^T J singular)
 * @retval SFIT_E_RANGE       n > UINT32_MAX, a sample out of range, or a result
 *                            would not be finite
 */
sfit_status_t sfit_uncert_points(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                 float radius, float noise_var, sfit_uncert_t *out);

/**
 * @brief Covariance of the geometric (orthogonal-distance) fit at its
 * centre, from the samples: the sandwich estimate A^-1 B A^-1.
 *
 * With d_i = |x_i - c|, u_i = (x_i - c)/d_i, dbar and ubar their means,
 * f_i = d_i - dbar (the radius is the mean distance):
 *   Mu = sum (u - ubar)(u - ubar)^T            (J^T J, radius profiled out)
 *   A  = Mu + sum f_i (I - u_i u_i^T) / d_i    (the cost's full Hessian)
 *   B  = s^2 Mu, s^2 = sum f_i^2 / (N - 4)     (the residual variance)
 *   Cov(c) = s^2 A^-1 Mu A^-1, Var(r) = s^2 (1/N + ubar^T A^-1 Mu A^-1 ubar),
 *   Cov(c, r) = -s^2 A^-1 Mu A^-1 ubar.
 * The second term of A (the curvature of the distances times the residuals)
 * and the noise in u_i are what first-order formulas leave out; both grow
 * with sigma / r. No noise level is needed: s^2 comes from the residuals
 * (and is returned in noise_var, without the curvature correction of
 * sfit_refine_result_t::noise_var, because the sandwich needs the residual
 * variance itself).
 * @param[in]  pts     n samples (caller-owned, read only).
 * @param[in]  n       Sample count (>= 5 and >= SFIT_MIN_SAMPLES).
 * @param[in]  center  Centre of the geometric fit (sfit_refine_result_t::center).
 * @param[out] out     Written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer
 * @retval SFIT_E_TOO_FEW     n < 5 or n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_NONFINITE   a sample or the centre holds NaN or Inf
 * @retval SFIT_E_DEGENERATE  a sample at the centre, or the directions span
 *                            less than 3 dimensions
 * @retval SFIT_E_NOT_POSDEF  A is not positive definite: the centre is not a
 *                            minimum of the geometric cost, or the noise
 *                            swamps the curvature of the data
 * @retval SFIT_E_RANGE       n > UINT32_MAX, a sample out of range, or a result
 *                            would not be finite
 */
sfit_status_t sfit_uncert_geometric(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                    sfit_uncert_t *out);

/**
 * @brief Covariance of the self-calibrated UGDK fit (sfit_selfcal_points())
 * from the samples: the sandwich G^-1 B G^-T of its estimating equations
 * (centre, radius and the noise variance estimated together), so the
 * coupling of the estimated sigma^2 with the centre and the second-order
 * terms are measured, not modelled. Derivation: docs/api.md#uncert.
 * Centre covariance only; radius_var and center_radius_cov are the first-
 * order values of sfit_uncert_moments().
 * @param[in]  pts        n samples (caller-owned, read only), the ones fitted.
 * @param[in]  n          Sample count (>= 14 and >= SFIT_MIN_SAMPLES).
 * @param[in]  center     The self-calibrated centre (sfit_selfcal_result_t::fit).
 * @param[in]  radius     Its radius (> 0).
 * @param[in]  noise_var  Its noise variance (sfit_selfcal_result_t::noise_var, >= 0).
 * @param[out] out        Written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer, radius <= 0, negative noise_var
 * @retval SFIT_E_NONFINITE   non-finite centre, radius, noise_var or sample
 * @retval SFIT_E_TOO_FEW     n < 14 or n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_DEGENERATE  a sample at the centre
 * @retval SFIT_E_NOT_POSDEF  C - sigma^2 I not positive definite, or the
 *                            linearised self-calibration singular (noise and
 *                            geometry not separable)
 * @retval SFIT_E_RANGE       n > UINT32_MAX, a sample out of range, or a
 *                            result would not be finite
 * @par Cost  three passes over the samples (moments, distances, sandwich terms)
 *            plus a fixed 3x3 tail (tools/flopcount: uncert_selfcal).
 */
sfit_status_t sfit_uncert_selfcal(const sfit_vec3_t *pts, size_t n,
                                  const sfit_vec3_t *center, float radius,
                                  float noise_var, sfit_uncert_t *out);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_UNCERT_H */
