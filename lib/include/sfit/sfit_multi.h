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
                                  N_p < SFIT_FEW_SAMPLES) | ::SFIT_MULTI_FLAG_SKIPPED;
                                  UNTRUSTED + COV_LIMIT when trust_ratio >
                                  SFIT_COV_MAX_TRUST or n_total < SFIT_COV_MIN_SAMPLES,
                                  as for single fits. */
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

/**
 * @brief Noise of one marker's samples, for sfit_multi_fit_noise(): the
 * unbiased solve with a noise model per marker (docs/multi.md#per-marker-noise).
 */
typedef struct sfit_multi_noise {
    sfit_mat3_t cov;  /**< Sigma_p: mean over the marker's samples of their noise
                           covariance (symmetric; the lower triangle is read). */
    sfit_vec3_t skew; /**< t_p = mean_i (2 Sigma_i + tr(Sigma_i) I) (x_i - m_p): the
                           bias of S_p when the noise covariance Sigma_i changes
                           along the marker's path; zero when it does not. */
} sfit_multi_noise_t;

/**
 * @brief Common centre of several markers, unbiased for noise that differs
 * from marker to marker (and along each marker's path): as sfit_multi_fit()
 * with A = sum w_p (C_p - Sigma_p) and
 * b = sum w_p ((C_p - Sigma_p)(m_p - o) + (S_p - t_p)/2). The trust ratio is
 * that of sum w_p Sigma_p against A. With every noise[p] equal to
 * {Sigma_hat, 0} the centre is the one of sfit_multi_fit() with Sigma_hat (up to
 * float rounding).
 * @param[in]  markers  Array of @p count accumulators, one per marker.
 * @param[in]  count    Number of markers (>= 1).
 * @param[in]  cfg      Options; NULL = ::sfit_multi_cfg_default. cfg->fit.noise
 *                      must be SFIT_NOISE_NONE (the noise is @p noise).
 * @param[in]  noise    Array of @p count noise models, one per marker.
 * @param[out] out      Result (method SFIT_METHOD_UGDK); written only on SFIT_OK.
 * @param[out] radii    NULL, or @p count floats, as sfit_multi_fit().
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL markers/noise/out, an invalid option, cfg->fit.noise
 *                            not SFIT_NOISE_NONE, a non-finite entry of a noise model or
 *                            a covariance that is not positive semi-definite (a negative
 *                            principal minor, as sfit_fit_cfg_t::noise_cov)
 * @retval SFIT_E_TOO_FEW     as sfit_multi_fit()
 * @retval SFIT_E_DEGENERATE  as sfit_multi_fit()
 * @retval SFIT_E_NOT_POSDEF  as sfit_multi_fit()
 * @retval SFIT_E_NO_CONVERGENCE  as sfit_multi_fit()
 * @retval SFIT_E_RANGE       as sfit_multi_fit()
 * @par Cost 8 markers: 2107 FLOPs (tools/flopcount "multi_solve_noise_total";
 * sfit_multi_fit() on them: 1607).
 */
sfit_status_t sfit_multi_fit_noise(const sfit_moments_t *markers, size_t count,
                                   const sfit_multi_cfg_t *cfg, const sfit_multi_noise_t *noise,
                                   sfit_multi_result_t *out, float *radii);

/**
 * @brief Covariance of a common centre, to second order, for independent
 * isotropic noise of known variance @p noise_var (s2) on every coordinate
 * of every sample (no noise shared between markers: for a joint, whose
 * parent pose error is shared, use sfit_joint_center_cov()):
 * Cov = A^-1 M A^-1, A = sum w_p C'_p,
 * M = s2 sum_p w_p^2 [(r_p^2 + 7.5 s2) / (N_p - 1) C'_p
 * + s2 N_p / (N_p - 1)^2 (r_p^2 I + a_p a_p^T)], a_p = m_p - c, r_p^2 the
 * marker's squared distance from the centre ((N_p - 1)/N_p tr C'_p +
 * |m_p - c|^2): the first-order term plus, per marker, the second-order
 * term of sfit_uncert_moments() (SFIT_UNCERT_NOISE_KNOWN), which it equals
 * for one marker.
 * Planar result: the pseudo-inverse normal to the axis (the covariance of
 * the centre's part normal to the axis). Derivation: docs/multi.md#centre-covariance.
 * @param[in]  markers    The accumulators that gave @p res.
 * @param[in]  count      Number of markers.
 * @param[in]  cfg        The options that gave @p res; NULL = ::sfit_multi_cfg_default.
 * @param[in]  res        Result of sfit_multi_fit().
 * @param[in]  noise_var  sigma^2 per coordinate (>= 0, finite).
 * @param[out] cov        Centre covariance (symmetric); written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL markers/res/cov, an invalid option, noise_var < 0
 * @retval SFIT_E_NONFINITE   noise_var NaN or Inf, a non-finite centre or axis in
 *                            res, or an unknown mode
 * @retval SFIT_E_TOO_FEW     no marker has SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_NOT_POSDEF  sum w_p C'_p is not positive definite
 * @retval SFIT_E_RANGE       the result would not be finite
 * @par Cost 8 markers: 941 FLOPs (tools/flopcount "multi_center_cov").
 */
sfit_status_t sfit_multi_center_cov(const sfit_moments_t *markers, size_t count,
                                    const sfit_multi_cfg_t *cfg, const sfit_multi_result_t *res,
                                    float noise_var, sfit_mat3_t *cov);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_MULTI_H */
