/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_noise.h
 * @brief Noise calibration against a known sphere.
 * @defgroup sfit_noise Noise calibration
 * @{
 *
 * Derivation and notes: docs/api.md#noise
 */
#ifndef SFIT_NOISE_H
#define SFIT_NOISE_H

#include <stdint.h>

#include "sfit_config.h"
#include "sfit_moments.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Result of a noise calibration. Written only on SFIT_OK; finite. */
typedef struct sfit_noise_est {
    uint32_t n;          /**< Samples used. */
    float noise_trace;   /**< Tr(Sigma_hat) (unit^2), unclamped. */
    float noise_var;     /**< sigma_hat^2 = noise_trace / 3 (unit^2), unclamped:
                              may be negative (see ::SFIT_NOISE_FLAG_NEGATIVE). */
    float noise_var_std; /**< Predicted standard deviation of noise_var,
                              evaluated at |noise_var| (plug-in, Gaussian noise). */
    uint32_t flags;      /**< SFIT_NOISE_FLAG_* bits of ::sfit_flag. */
} sfit_noise_est_t;

/**
 * @brief Calibrate the measurement noise from samples of a known sphere
 * and predict the spread of the estimate.
 *
 * Uses the accumulator's exact identity
 * sum |x - c0|^2 = tr(M2) + N |mean - c0|^2 (M2 the centred second moments),
 * with mean - c0 formed as (origin - c0) + offset so that a far-away centre
 * loses no precision.
 * @param[in]  m    Accumulator of the calibration samples (not modified).
 * @param[in]  c0   Known centre.
 * @param[in]  r0   Known radius (>= 0; 0 calibrates on a fixed point).
 * @param[out] out  Estimate; written only on SFIT_OK.
 * @retval SFIT_OK           success (check out->flags)
 * @retval SFIT_E_ARG        NULL pointer, or r0 < 0
 * @retval SFIT_E_NONFINITE  c0 or r0 is NaN or Inf
 * @retval SFIT_E_TOO_FEW    the accumulator holds no sample
 * @retval SFIT_E_RANGE      the result would not be finite
 * @par Cost 30 FLOPs, independent of N (tools/flopcount: noise_calibration).
 */
sfit_status_t sfit_noise_calibrate(const sfit_moments_t *m, const sfit_vec3_t *c0, float r0,
                                   sfit_noise_est_t *out);

/**
 * @brief Predicted standard deviation of a calibration (D = 3):
 * sqrt(2 s2 (3 s2 + 2 r0^2) / (9 N)). A design aid: how many samples, on
 * which radius, give the wanted precision of sigma^2.
 * @param[in]  noise_var  sigma^2 (>= 0).
 * @param[in]  r0         Calibration radius (>= 0).
 * @param[in]  n          Sample count (>= 1).
 * @param[out] sd         Standard deviation of sigma_hat^2; written only on SFIT_OK.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL sd, negative noise_var or r0, or n == 0
 * @retval SFIT_E_NONFINITE  noise_var or r0 is NaN or Inf
 * @retval SFIT_E_RANGE      the result would not be finite
 */
sfit_status_t sfit_noise_calib_std(float noise_var, float r0, uint32_t n, float *sd);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_NOISE_H */
