/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_selfcal.h
 * @brief Self-calibrated UGDK: estimate the noise variance from the samples
 * themselves and apply the bias compensation (no calibration sphere needed).
 * @defgroup sfit_selfcal Self-calibrated noise
 * @{
 *
 * Derivation and notes: docs/api.md#selfcal
 */
#ifndef SFIT_SELFCAL_H
#define SFIT_SELFCAL_H

#include <stddef.h>
#include <stdint.h>

#include "sfit_fit.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Options of a self-calibration. */
typedef struct sfit_selfcal_cfg {
    float planar_ratio; /**< lambda_min/lambda_max threshold of SFIT_FLAG_NEAR_PLANAR;
                             0 = SFIT_PLANAR_RATIO. */
} sfit_selfcal_cfg_t;

/** @brief Defaults: planar_ratio = SFIT_PLANAR_RATIO. */
extern const sfit_selfcal_cfg_t sfit_selfcal_cfg_default;

/** @brief A self-calibrated fit. Written only on SFIT_OK. */
typedef struct sfit_selfcal_result {
    sfit_result_t fit;   /**< The UGDK fit with the final noise_var (method UGDK); when
                              capped its flags carry SFIT_FLAG_UNTRUSTED and
                              SFIT_SELFCAL_FLAG_CAPPED. Its covariance:
                              sfit_uncert_selfcal(). */
    float noise_var;     /**< Estimated isotropic noise variance sigma^2 (unit^2). */
    uint32_t iterations; /**< Residual passes done (1..SFIT_SELFCAL_MAX_ITERS). */
    uint32_t flags;      /**< ::SFIT_SELFCAL_FLAG_CAPPED or 0 (::sfit_flag). */
} sfit_selfcal_result_t;

/**
 * @brief Self-calibrated UGDK sphere fit over a caller-owned array.
 * @param[in]  pts  n samples (read only).
 * @param[in]  n    Sample count (>= 5 and >= SFIT_MIN_SAMPLES).
 * @param[in]  cfg  Options (NULL = defaults): planar_ratio; the solution is
 *                  always the sphere and the noise model is the estimated
 *                  isotropic one.
 * @param[out] out  Written only on SFIT_OK.
 * @retval SFIT_OK                success
 * @retval SFIT_E_ARG             NULL pointer, invalid cfg (planar_ratio not finite
 *                                or outside [0, 1))
 * @retval SFIT_E_TOO_FEW         n < 5 or n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_NONFINITE       a sample holds NaN or Inf
 * @retval SFIT_E_RANGE           a sample out of range, n > UINT32_MAX, or a result
 *                                not finite
 * @retval SFIT_E_DEGENERATE      coincident / collinear / planar samples, or a
 *                                sample at the fitted centre
 * @retval SFIT_E_NOT_POSDEF      C - sigma^2 I not positive definite (cannot happen
 *                                with the cap unless rounding; reported, not hidden)
 * @retval SFIT_E_NO_CONVERGENCE  sigma^2 still moving after SFIT_SELFCAL_MAX_ITERS
 *                                (or the eigen-solver hit its bound)
 * @retval SFIT_E_UNSUPPORTED     a GDKE/UGDK step as sfit_fit_moments()
 *                                (SFIT_FULL_SOLVER 0 only)
 */
sfit_status_t sfit_selfcal_points(const sfit_vec3_t *pts, size_t n, const sfit_selfcal_cfg_t *cfg,
                               sfit_selfcal_result_t *out);

/**
 * @brief Noise variance from the radial residuals of any fit that agrees
 * with the geometric fit to first order (steps 2-3 above): one pass.
 * @param[in]  pts     n samples.
 * @param[in]  n       Sample count (>= 5).
 * @param[in]  center  Fitted centre.
 * @param[in]  radius  Fitted radius (> 0).
 * @param[out] noise_var  sigma^2 estimate; written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer, radius <= 0
 * @retval SFIT_E_TOO_FEW     n < 5 or n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_NONFINITE   a sample, the centre or the radius holds NaN or Inf
 * @retval SFIT_E_RANGE       a sample out of range, n > UINT32_MAX, or the
 *                            estimate would not be finite
 * @retval SFIT_E_DEGENERATE  a sample lies at the centre (its radial direction is undefined)
 */
sfit_status_t sfit_selfcal_noise_var(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                     float radius, float *noise_var);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_SELFCAL_H */
