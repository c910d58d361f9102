/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_incr.h
 * @brief Incremental estimator: a new
 * sphere centre and radius after every sample, in constant memory.
 * @defgroup sfit_incr Incremental estimator
 * @{
 *
 * Derivation and notes: docs/api.md#incr
 */
#ifndef SFIT_INCR_H
#define SFIT_INCR_H

#include <stddef.h>
#include <stdint.h>

#include "sfit_config.h"
#include "sfit_fit.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Incremental state. Caller-owned, fixed size; members are private.
 * Initialise with sfit_incr_init().
 *
 * Mean = p + d. M2 = sum y y^T (y = x - mean) and the raw sums about p,
 * T = sum |z|^2 z and Q = sum |z|^2 (z = x - p), are each held as an outer
 * value plus an inner (`_lo`) value summed since the last fold.
 */
typedef struct sfit_incr {
    uint32_t n;           /**< Samples added. */
    uint32_t nb;          /**< Samples in the inner level. */
    float inv_n;          /**< 1 / n (0 when n == 0). */
    float p[3];           /**< Frame origin (absolute); moved to the mean at each fold. */
    float d[3];           /**< Mean minus p. */
    float m2[6];          /**< Outer M2, packed XX,YY,ZZ,XY,XZ,YZ. */
    float m2_lo[6];       /**< Inner M2. */
    float t[3];           /**< Outer T. */
    float t_lo[3];        /**< Inner T. */
    float q;              /**< Outer Q. */
    float q_lo;           /**< Inner Q. */
    sfit_noise_kind_t noise; /**< Noise model (GDKE when SFIT_NOISE_NONE). */
    float sig[6];         /**< Sigma_hat, packed (isotropic: variance on the diagonal). */
    float sig_tr;         /**< trace(Sigma_hat). */
} sfit_incr_t;

/** @brief Options of an incremental estimator: its noise model only. */
typedef struct sfit_incr_cfg {
    sfit_noise_kind_t noise; /**< SFIT_NOISE_NONE (GDKE), _ISO or _COV (UGDK). */
    float noise_var;         /**< sigma^2 for SFIT_NOISE_ISO (>= 0, finite). */
    sfit_mat3_t noise_cov;   /**< Sigma for SFIT_NOISE_COV (as sfit_fit_cfg_t::noise_cov). */
} sfit_incr_cfg_t;

/** @brief Defaults: no noise model (GDKE). */
extern const sfit_incr_cfg_t sfit_incr_cfg_default;


/**
 * @brief Initialise (or clear) the state and choose the estimator.
 * @param[out] s    State.
 * @param[in]  cfg  Options; NULL = GDKE. The noise model (noise, noise_var,
 *                  noise_cov: SFIT_NOISE_ISO / _COV give UGDK); the estimator
 *                  is always a sphere fit.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  s is NULL, or an invalid noise model (kind, a negative or
 *                     non-finite variance, a covariance that is not finite or not
 *                     positive semi-definite); s unchanged
 */
sfit_status_t sfit_incr_init(sfit_incr_t *s, const sfit_incr_cfg_t *cfg);

/**
 * @brief Forget every sample, keep the noise model.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  s is NULL
 */
sfit_status_t sfit_incr_reset(sfit_incr_t *s);

/**
 * @brief (Re)start from a batch of samples: the "batch fit of the
 * first few samples". Replaces any samples the state held by pts[0..n-1]
 * and checks the batch fit with sfit_fit_moments() (sphere mode, the state's
 * noise model), which also rejects coincident, collinear and planar sets.
 * On any failure the state is left bit for bit unchanged.
 * @param[in,out] s    Initialised state.
 * @param[in]     pts  n samples.
 * @param[in]     n    Sample count (>= SFIT_MIN_SAMPLES).
 * @param[out]    out  Estimate after the batch (may be NULL); written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL s, or NULL pts with n > 0
 * @retval SFIT_E_NONFINITE   a sample holds NaN or Inf
 * @retval SFIT_E_RANGE       a coordinate >= 2^SFIT_COORD_MAX_EXP, n > UINT32_MAX,
 *                            or a result would not be finite
 * @retval SFIT_E_TOO_FEW     n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_DEGENERATE  coincident, collinear or planar samples
 * @retval SFIT_E_NOT_POSDEF  C - Sigma_hat is not positive definite (UGDK)
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver of the batch check hit its bound
 * @retval SFIT_E_UNSUPPORTED the batch check as sfit_fit_moments() (SFIT_FULL_SOLVER 0
 *                            only; a full covariance, SFIT_NOISE_COV, which that
 *                            build's sfit_fit_moments() does not serve, is checked by
 *                            this estimator's own solve instead)
 */
sfit_status_t sfit_incr_start(sfit_incr_t *s, const sfit_vec3_t *pts, size_t n,
                              sfit_sphere_t *out);

/**
 * @brief Add one sample (O(1); every SFIT_INCR_BLOCK-th call also folds).
 * @par Cost 40 FLOPs (tools/flopcount: incremental_add).
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL pointer
 * @retval SFIT_E_NONFINITE  a coordinate is NaN or Inf; s unchanged (bit for bit)
 * @retval SFIT_E_RANGE      |coordinate| >= 2^SFIT_COORD_MAX_EXP, or n is at
 *                           UINT32_MAX; s unchanged
 */
sfit_status_t sfit_incr_add(sfit_incr_t *s, const sfit_vec3_t *x);

/**
 * @brief The estimate for the samples added so far (s is not modified).
 * GDKE: centre = mean + C^-1 S / 2, r^2 = (N-1)/N tr C + |centre - mean|^2;
 * UGDK: the same with C' = C - Sigma_hat 
 * @par Cost 65 FLOPs for GDKE (tools/flopcount: incremental_solve).
 * @param[in]  s    State.
 * @param[out] out  Estimate; written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer
 * @retval SFIT_E_TOO_FEW     fewer than SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_DEGENERATE  the samples are coincident, collinear or planar
 *                            (an LDL^T pivot of sum y y^T <= SFIT_CHOL_PIVOT_EPS
 *                            times its largest diagonal entry), or their largest
 *                            per-axis spread is below SFIT_MIN_SPREAD (too small
 *                            for float, as in sfit_fit_moments(): rescale the data)
 * @retval SFIT_E_NOT_POSDEF  UGDK: C - Sigma_hat is not positive definite (GDKE: only
 *                            for a state not written by this API, e.g. garbage bytes)
 * @retval SFIT_E_RANGE       the result would not be finite
 */
sfit_status_t sfit_incr_fit(const sfit_incr_t *s, sfit_sphere_t *out);

/**
 * @brief sfit_incr_add() then sfit_incr_fit(): the per-sample recursion
 * .
 * @par Cost 105 FLOPs for GDKE, 111 for UGDK (tools/flopcount:
 * incremental_update, incremental_update_ugdk).
 *
 * A sample that sfit_incr_add() rejects leaves s unchanged and its status
 * is returned. A valid sample is always kept; if the solve then fails
 * (::SFIT_E_TOO_FEW, ::SFIT_E_DEGENERATE, ::SFIT_E_NOT_POSDEF,
 * ::SFIT_E_RANGE) that status is returned and out is not written.
 * @retval SFIT_OK            the sample was added and a new estimate written
 * @retval SFIT_E_ARG         NULL pointer
 * @retval SFIT_E_NONFINITE   NaN / Inf coordinate: s unchanged
 * @retval SFIT_E_RANGE       coordinate out of range or counter full (s unchanged),
 *                            or the estimate would not be finite
 * @retval SFIT_E_TOO_FEW     fewer than SFIT_MIN_SAMPLES samples (sample kept)
 * @retval SFIT_E_DEGENERATE  coincident, collinear or planar samples, or a spread
 *                            below SFIT_MIN_SPREAD (sample kept)
 * @retval SFIT_E_NOT_POSDEF  UGDK: C - Sigma_hat not positive definite (sample kept)
 */
sfit_status_t sfit_incr_update(sfit_incr_t *s, const sfit_vec3_t *x, sfit_sphere_t *out);

/** @brief Number of samples added (0 for NULL). */
uint32_t sfit_incr_count(const sfit_incr_t *s);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_INCR_H */
