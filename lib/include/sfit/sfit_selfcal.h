/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_selfcal.h
 * @brief Self-calibrated UGDK: estimate the noise variance from the samples
 * themselves and apply the bias compensation (no calibration sphere needed).
 * @defgroup sfit_selfcal Self-calibrated noise
 * @{
 *
 * Fixed-point iteration over a caller-owned array (the samples are read,
 * never written):
 *  1. GDKE (sigma^2 = 0) from the moments.
 *  2. Radial residuals d_i = |x_i - c| - r; s^2 = sum (d_i - dbar)^2 / (N - 4).
 *     N - 4: the residuals are orthogonal (to first order) to the 4
 *     directions of the sphere's parameters (3 centre, 1 radius; removing
 *     dbar is the radius' share), so s^2 is unbiased for the radial noise
 *     variance whatever the fit, provided it agrees with the geometric fit
 *     to first order (UGDK does; GDKE does not on a cap, which is why the
 *     iteration continues).
 *  3. Curvature: with e = t v + e_perp (t = v.e),
 *     |r v + e| = (r + t) + |e_perp|^2 / (2 (r + t)) + ..., whose variance
 *     is sigma^2 + sigma^4/r^2 (the |e_perp|^2 term) - 2 sigma^4/r^2 (its
 *     covariance with t through 1/(r + t)): E s^2 = sigma^2 - sigma^4/r^2;
 *     solved for sigma^2: sigma^2 = 2 s^2 / (1 + sqrt(1 - 4 s^2/r^2))
 *     (the root is clamped at 0: sigma^2 <= 2 s^2).
 *  4. Safeguard: sigma^2 is capped at SFIT_SELFCAL_MAX_TRUST * lambda_min(C),
 *     so C' = C - sigma^2 I keeps at least (1 - SFIT_SELFCAL_MAX_TRUST) of
 *     C's smallest eigenvalue (stays positive definite); the result is then
 *     flagged ::SFIT_SELFCAL_FLAG_CAPPED.
 *  5. UGDK with sigma^2; repeat from 2 until sigma^2 changes by less than
 *     SFIT_SELFCAL_REL_TOL (relative), at most SFIT_SELFCAL_MAX_ITERS times.
 *
 * The map converges fast: an error e in sigma^2 moves the centre by
 * ~ r e / lambda_min along the cap axis and raises s^2 only by ~ e^2/lambda_min
 * (quadratic), so 2-4 iterations suffice when the trust ratio is below 1/2.
 *
 * A streaming form from moments alone (a fourth-moment accumulator) was
 * rejected: sigma^2 is then the small difference of terms ~ r^4, and float
 * loses it when sigma/r < ~1e-2 (docs/beyond.md).
 *
 * Cost per iteration: one pass over the samples (3 sub, 3 mul, 2 add,
 * 1 sqrt, 3 add/mul for the sums per sample) plus one sfit_moments_fit().
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
    sfit_result_t fit;   /**< The UGDK fit with the final noise_var (method UGDK). */
    float noise_var;     /**< Estimated isotropic noise variance sigma^2 (unit^2). */
    uint32_t iterations; /**< Residual passes done (1..SFIT_SELFCAL_MAX_ITERS). */
    uint32_t flags;      /**< ::SFIT_SELFCAL_FLAG_CAPPED or 0 (::sfit_flag). */
} sfit_selfcal_result_t;

/**
 * @brief Self-calibrated UGDK sphere fit over a caller-owned array.
 * @param[in]  pts  n samples (read only).
 * @param[in]  n    Sample count (>= 5 and >= SFIT_MIN_SAMPLES).
 * @param[in]  cfg  Options (NULL = defaults); only planar_ratio is used: the
 *                  solution is always the sphere and the noise model is the
 *                  estimated isotropic one. SFIT_MODE_PLANAR is rejected.
 * @param[out] out  Written only on SFIT_OK.
 * @retval SFIT_OK                success
 * @retval SFIT_E_ARG             NULL pointer, invalid cfg, planar mode
 * @retval SFIT_E_TOO_FEW         n < 5 or n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_NONFINITE       a sample holds NaN or Inf
 * @retval SFIT_E_RANGE           a sample out of range, or a result not finite
 * @retval SFIT_E_DEGENERATE      coincident / collinear / planar samples, or a
 *                                sample at the fitted centre
 * @retval SFIT_E_NOT_POSDEF      C - sigma^2 I not positive definite (cannot happen
 *                                with the cap unless rounding; reported, not hidden)
 * @retval SFIT_E_NO_CONVERGENCE  sigma^2 still moving after SFIT_SELFCAL_MAX_ITERS
 *                                (or the eigen-solver hit its bound)
 */
sfit_status_t sfit_points_selfcal(const sfit_vec3_t *pts, size_t n, const sfit_selfcal_cfg_t *cfg,
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
 * @retval SFIT_E_ARG         NULL pointer, non-finite centre, radius <= 0
 * @retval SFIT_E_TOO_FEW     n < 5
 * @retval SFIT_E_NONFINITE   a sample holds NaN or Inf
 * @retval SFIT_E_RANGE       the estimate would not be finite
 * @retval SFIT_E_DEGENERATE  a sample lies at the centre (its radial direction is undefined)
 */
sfit_status_t sfit_points_noise_var(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *center,
                                     float radius, float *noise_var);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_SELFCAL_H */
