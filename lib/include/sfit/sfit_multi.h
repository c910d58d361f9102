/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_multi.h
 * @brief Several markers, one centre: MGDK and unbiased MGDK, with the planar (hinge) solution.
 * @defgroup sfit_multi Multi-marker common centre
 * @{
 *
 * Derivation and notes: docs/api.md#multi
 */
#ifndef SFIT_MULTI_H
#define SFIT_MULTI_H

#include <stddef.h>
#include <stdint.h>

#include "sfit_fit.h"
#include "sfit_moments.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief How the markers' equations are weighted. */
typedef enum sfit_multi_weight {
    SFIT_MULTI_WEIGHT_EQUAL = 0,  /**< w_p = 1: every marker counts once (default). */
    SFIT_MULTI_WEIGHT_SAMPLES = 1 /**< w_p ~ N_p - 1: joint least squares of all samples. */
} sfit_multi_weight_t;

/** @brief Options of a multi-marker fit. Start from ::sfit_multi_cfg_default. */
typedef struct sfit_multi_cfg {
    sfit_fit_cfg_t fit;          /**< Mode, noise model (Sigma_hat per sample), planar ratio;
                                      fit.eigen must be 0 or 1 but has no effect (the
                                      multi-marker solve always runs the full solver). */
    sfit_multi_weight_t weight;  /**< Weighting of the markers. */
} sfit_multi_cfg_t;

/** @brief Defaults: ::sfit_fit_cfg_default (auto, GDKE) and equal weights. */
extern const sfit_multi_cfg_t sfit_multi_cfg_default;

/** @brief A common centre. Written only when the solve returns SFIT_OK; always finite. */
typedef struct sfit_multi_result {
    sfit_vec3_t center;      /**< Common centre (on the axis, planar mode). */
    uint32_t n_total;        /**< Samples of the markers used. */
    uint32_t markers;        /**< Markers used. */
    uint32_t skipped;        /**< Markers skipped (fewer than SFIT_MIN_SAMPLES samples). */
    sfit_vec3_t eigenvalues; /**< Eigenvalues of sum_p w_p C_p, ascending. */
    sfit_vec3_t axis;        /**< Hinge axis (planar) or smallest eigen-direction
                                  (sphere); unit, largest component positive. */
    float trust_ratio;       /**< rho(A^-1 (sum w_p) Sigma_hat), A = sum w_p C_p: as
                                  sfit_result_t::trust_ratio for the summed system
                                  (0 for GDKE). */
    float leontief_ratio;    /**< rho(A'^-1 (sum w_p) Sigma_hat), A' = sum w_p C'_p
                                  = trust/(1 - trust); SFIT_FLAG_UNTRUSTED when >= 1. */
    uint32_t flags;          /**< ::sfit_flag bits (FEW_SAMPLES: some marker used has
                                  N_p < SFIT_FEW_SAMPLES) | ::SFIT_MULTI_FLAG_SKIPPED. */
    sfit_method_t method;    /**< MGDK (SFIT_METHOD_GDKE) or unbiased (SFIT_METHOD_UGDK). */
    sfit_mode_t mode;        /**< SFIT_MODE_SPHERE or SFIT_MODE_PLANAR. */
} sfit_multi_result_t;

/**
 * @brief Common centre of several markers from their accumulators (none is
 * modified). Work and stack are O(1) per marker; the only loop over
 * markers is bounded by @p count.
 * @param[in]  markers  Array of @p count accumulators, one per marker.
 * @param[in]  count    Number of markers (>= 1).
 * @param[in]  cfg      Options; NULL = ::sfit_multi_cfg_default.
 * @param[out] out      Result; written only on SFIT_OK.
 * @param[out] radii    NULL, or @p count floats: radius of each marker
 *                      (0 for a skipped marker); written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL markers/out, or an invalid option
 * @retval SFIT_E_TOO_FEW     count is 0, or every marker has fewer than
 *                            SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_DEGENERATE  the summed covariance is coincident or collinear,
 *                            or singular in sphere mode (GDKE)
 * @retval SFIT_E_NOT_POSDEF  sum C'_p is not positive definite (on the kept
 *                            directions in planar mode), or a marker's r_p^2 <= 0
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @retval SFIT_E_RANGE       the result would not be finite, or the total
 *                            sample count exceeds UINT32_MAX
 */
sfit_status_t sfit_multi_fit(const sfit_moments_t *markers, size_t count,
                               const sfit_multi_cfg_t *cfg, sfit_multi_result_t *out,
                               float *radii);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_MULTI_H */
