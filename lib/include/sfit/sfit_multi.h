/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_multi.h
 * @brief Several markers, one centre: MGDK and unbiased MGDK (chapter
 * section 5.3, eq. 219-223), with the planar (hinge) solution.
 * @defgroup sfit_multi Multi-marker common centre
 * @{
 *
 * M markers p = 1..M ride on one rigid segment and turn about one joint
 * centre c; each draws its own sphere (radius r_p). With each marker's mean
 * m_p, C_p = sum y y^T/(N_p-1), S_p = sum |y|^2 y/(N_p-1) (its accumulator),
 * minimising the summed Kasa cost
 *   J(c, r_1..r_M) = sum_p w_p/(N_p-1) sum_i (|x_pi - c|^2 - r_p^2)^2
 * over every r_p (r_p^2 = mean_i |x_pi - c|^2, eq. 221) and then over c
 * gives the normal equations
 *   (sum_p w_p C'_p) c = sum_p w_p (C'_p m_p + S_p/2),   C'_p = C_p - Sigma_hat.
 * - Equal weights w_p = 1 are eq. 220 (GDKE, Sigma_hat = 0) and eq. 222
 *   (unbiased, C'_p) as printed: each marker's covariance counts once
 *   whatever its sample count. This is the default (::SFIT_MULTI_WEIGHT_EQUAL).
 * - Weights w_p proportional to N_p - 1 (::SFIT_MULTI_WEIGHT_SAMPLES) make J
 *   the plain joint least squares of all samples (the gradient of that cost
 *   is sum_p 4 (N_p-1) (2 C_p (c - m_p) - S_p); eq. 219 drops the N_p - 1).
 *   The weights are normalised to sum to M, so the two options coincide
 *   exactly when every marker has the same count.
 * - Radii (eq. 221/223): r_p^2 = (N_p-1)/N_p tr C'_p + |m_p - c|^2.
 *
 * Planar (hinge) case: when sum w_p C_p is near-planar (rank 2: every
 * marker circles the same axis), the inverse is replaced by the
 * pseudo-inverse over its two largest eigen-directions, as for one marker,
 * and the dropped direction is reported as the axis. The position of the
 * centre along the axis is then not determined by the data; sfit puts it
 * in the plane through the weighted mean of the marker means (normal to the
 * axis), i.e. the mean of the markers' circle planes. Each marker draws a
 * circle in its own plane normal to the axis, so its radius is the distance
 * from the axis within that plane:
 *   r_p^2 = (N_p-1)/N_p tr(P C'_p P) + |P (m_p - c)|^2,  P = I - a a^T,
 * (the same minimisation with every residual projected on the plane).
 * With one marker all of this is the single-marker fit of sfit_moments_fit()
 * (the same numbers, rounding aside).
 *
 * Markers with fewer than SFIT_MIN_SAMPLES samples (an occluded marker) are
 * skipped: the result carries ::SFIT_MULTI_FLAG_SKIPPED, `markers` counts
 * the markers used and their radius is reported as 0. If no marker is left
 * the solve fails with ::SFIT_E_TOO_FEW.
 *
 * Float: every marker's mean is taken relative to the first used marker's
 * mean (m_p - m_1 = (origin_p - origin_1) + (d_p - d_1)), so no far-away
 * coordinate enters a product; it is added once, at the end.
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
    SFIT_MULTI_WEIGHT_EQUAL = 0,  /**< w_p = 1: eq. 220/222 as printed (default). */
    SFIT_MULTI_WEIGHT_SAMPLES = 1 /**< w_p ~ N_p - 1: joint least squares of all samples. */
} sfit_multi_weight_t;

/** @brief Options of a multi-marker fit. Start from ::sfit_multi_cfg_default. */
typedef struct sfit_multi_cfg {
    sfit_fit_cfg_t fit;          /**< Mode, noise model (Sigma_hat per sample), planar ratio. */
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
