/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_refine.h
 * @brief Geometric (orthogonal-distance) sphere fit over a caller-owned
 * array: bounded Levenberg-Marquardt in float, started from UGDK.
 * @defgroup sfit_refine Geometric refinement
 * @{
 *
 * Derivation and notes: docs/api.md#refine
 */
#ifndef SFIT_REFINE_H
#define SFIT_REFINE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sfit_selfcal.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Run-time options; start from ::sfit_refine_cfg_default. */
typedef struct sfit_refine_cfg {
    uint32_t max_iters; /**< 0 = SFIT_REFINE_MAX_ITERS; larger values are clamped to it. */
    float tol;          /**< 0 = SFIT_REFINE_TOL; else in [1e-7, 1e-2]. */
    bool accept_unconverged; /**< true: at the iteration bound return the last
                                  accepted centre with converged false (SFIT_OK);
                                  false: SFIT_E_NO_CONVERGENCE there. A byte
                                  other than 0/1: SFIT_E_ARG. */
} sfit_refine_cfg_t;

/** @brief Defaults (compile-time bound and tolerance). */
extern const sfit_refine_cfg_t sfit_refine_cfg_default;

/**
 * @brief The one result of the family: a geometric fit, and with
 * sfit_refine_fit() its covariance and the verdict of its start. One flat
 * record (what a front end prints); written only on SFIT_OK, every value
 * finite. sfit_refine_points() writes the first block and zeros the rest.
 */
typedef struct sfit_refine_result {
    sfit_vec3_t center;  /**< Geometric centre. */
    float radius;        /**< Geometric radius (mean distance from the centre). */
    float rms;           /**< sqrt(sum (d - r)^2 / N): RMS radial residual. */
    float noise_var;     /**< sigma^2 from the residuals: s^2 = sum (d - r)^2/(N - 4)
                              corrected for curvature (as sfit_selfcal.h). */
    uint32_t n;          /**< Samples used. */
    uint32_t iterations; /**< Linearisations done (>= 1). */
    bool converged;      /**< true when the last step was below tol * r; false only with
                              sfit_refine_cfg_t::accept_unconverged at the bound. */
    /* sfit_refine_fit() only (zero from sfit_refine_points()): */
    sfit_mat3_t center_cov;       /**< Mean squared error of the centre (unit^2,
                                       symmetric): the sandwich covariance of
                                       sfit_uncert_geometric() plus b b^T, b = center -
                                       the self-calibrated start's centre (the
                                       geometric fit's bias estimate), widened
                                       (docs/coverage.md). */
    float radius_var;             /**< Var(r) of the sandwich (unit^2). */
    float center_radius_cov[3];   /**< Cov(c, r) of the sandwich (unit^2). */
    float cov_noise_var;          /**< The residual variance the sandwich used
                                       (sfit_uncert_t::noise_var). */
    /* the self-calibrated UGDK start (sfit_selfcal_points()): */
    sfit_vec3_t eigenvalues;      /**< Of the start fit (sfit_result_t::eigenvalues). */
    sfit_vec3_t axis;             /**< Of the start fit (sfit_result_t::axis). */
    float trust_ratio;            /**< Of the start fit (sfit_result_t::trust_ratio). */
    float leontief_ratio;         /**< Of the start fit (sfit_result_t::leontief_ratio). */
    uint32_t flags;               /**< The verdict: the start fit's ::sfit_flag bits
                                       (SFIT_FLAG_UNTRUSTED, SFIT_SELFCAL_FLAG_CAPPED, ...). */
} sfit_refine_result_t;

/**
 * @brief Refine a sphere fit geometrically.
 * @param[in]  pts     n samples (read only).
 * @param[in]  n       Sample count (>= 5 and >= SFIT_MIN_SAMPLES).
 * @param[in]  c0      Start centre (e.g. the UGDK / self-calibrated centre).
 * @param[in]  cfg     Options; NULL = defaults.
 * @param[out] out     Written only on SFIT_OK: the geometric fit (center ..
 *                     converged); the fields of sfit_refine_fit() zero.
 * @retval SFIT_OK                converged
 * @retval SFIT_E_ARG             NULL pointer, invalid cfg (tol outside its range or
 *                                not finite, accept_unconverged's byte not 0 or 1)
 * @retval SFIT_E_TOO_FEW         n < 5 or n < SFIT_MIN_SAMPLES
 * @retval SFIT_E_NONFINITE       a sample or c0 holds NaN or Inf
 * @retval SFIT_E_RANGE           n > UINT32_MAX, a sample out of range, or a value
 *                                would not be finite
 * @retval SFIT_E_DEGENERATE      a sample at the centre, or the directions do
 *                                not span 3-D (A singular: planar / collinear data)
 * @retval SFIT_E_NO_CONVERGENCE  the step is still above tol after max_iters, or
 *                                no damping made the cost decrease
 */
sfit_status_t sfit_refine_points(const sfit_vec3_t *pts, size_t n, const sfit_vec3_t *c0,
                              const sfit_refine_cfg_t *cfg, sfit_refine_result_t *out);

/** @brief Options of sfit_refine_fit(). */
typedef struct sfit_refined_cfg {
    sfit_selfcal_cfg_t selfcal; /**< Options of the self-calibrated start. */
    sfit_refine_cfg_t refine;   /**< Options of the refinement. */
} sfit_refined_cfg_t;

/** @brief Defaults of both steps. */
extern const sfit_refined_cfg_t sfit_refined_cfg_default;

/**
 * @brief The combined recipe over a caller's array: noise estimate and
 * start (sfit_selfcal_points()), geometric refinement (sfit_refine_points())
 * and its covariance (sfit_uncert_geometric()).
 * @param[in]  pts  n samples (read only).
 * @param[in]  n    Sample count (>= 5 and >= SFIT_MIN_SAMPLES).
 * @param[in]  cfg  Options; NULL = ::sfit_refined_cfg_default.
 * @param[out] out  Every field; written only on SFIT_OK.
 * @retval SFIT_OK  every step succeeded
 * @retval other    the status of the first step that failed (see those functions)
 * @par Cost  the sum of the three steps.
 */
sfit_status_t sfit_refine_fit(const sfit_vec3_t *pts, size_t n,
                              const sfit_refined_cfg_t *cfg, sfit_refine_result_t *out);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_REFINE_H */
