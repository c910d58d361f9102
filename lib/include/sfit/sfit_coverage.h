/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_coverage.h
 * @brief Coverage design aids: covariance eigenvalues of a covered cap or
 * arc, the noise a coverage tolerates, the coverage a noise level needs.
 * @defgroup sfit_coverage Coverage design aids
 * @{
 *
 * Derivation and notes: docs/api.md#coverage
 */
#ifndef SFIT_COVERAGE_H
#define SFIT_COVERAGE_H

#include "sfit_config.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Coverage geometry. */
typedef enum sfit_coverage_kind {
    SFIT_COVERAGE_CAP = 0, /**< Spherical cap (ball joint, sphere fit). */
    SFIT_COVERAGE_ARC = 1  /**< Circular arc (hinge, planar fit). */
} sfit_coverage_kind_t;

/**
 * @brief Asymptotic covariance eigenvalues of a uniformly covered cap or arc
 * of half-angle theta and radius r.
 *
 * Cap: lmin = axial, lmax = lateral (double). Arc:
 * lmin = radial, lmax = tangential (in the circle's plane).
 * lmin <= lmax for every theta in (0, pi] (equality at pi). Note that the
 * arc's lmax is not monotone: it peaks near theta = 2.247 rad (0.6086 r^2)
 * and falls back to r^2 / 2 at pi; lmin is increasing for both kinds.
 * @param[in]  kind   Cap or arc.
 * @param[in]  theta  Half-angle in radians, 0 < theta <= pi.
 * @param[in]  r      Radius (> 0).
 * @param[out] lmin   Smaller eigenvalue (may be NULL); written only on SFIT_OK.
 * @param[out] lmax   Larger eigenvalue (may be NULL); written only on SFIT_OK.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        invalid kind, theta outside (0, pi], or r <= 0
 * @retval SFIT_E_NONFINITE  theta or r is NaN or Inf
 * @retval SFIT_E_RANGE      r^2 overflows float
 */
sfit_status_t sfit_coverage_eigs(sfit_coverage_kind_t kind, float theta, float r, float *lmin,
                                 float *lmax);

/**
 * @brief sfit_coverage_eigs() for a cap.
 * @retval SFIT_OK, SFIT_E_ARG, SFIT_E_NONFINITE, SFIT_E_RANGE  as sfit_coverage_eigs()
 */
sfit_status_t sfit_coverage_cap_eigs(float theta, float r, float *lmin, float *lmax);

/**
 * @brief sfit_coverage_eigs() for an arc.
 * @retval SFIT_OK, SFIT_E_ARG, SFIT_E_NONFINITE, SFIT_E_RANGE  as sfit_coverage_eigs()
 */
sfit_status_t sfit_coverage_arc_eigs(float theta, float r, float *lmin, float *lmax);

/**
 * @brief Largest noise standard deviation a coverage tolerates:
 * sigma_max = sqrt(lmin(theta)) the sigma at
 * which rho = sigma^2 / lambda_min reaches 1. Multiply by sqrt(rho_target)
 * for a safety margin rho <= rho_target.
 * @param[in]  kind       Cap or arc.
 * @param[in]  theta      Half-angle in radians, 0 < theta <= pi.
 * @param[in]  r          Radius (> 0).
 * @param[out] sigma_max  Written only on SFIT_OK (same unit as r).
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL sigma_max, invalid kind, theta outside (0, pi], r <= 0
 * @retval SFIT_E_NONFINITE  theta or r is NaN or Inf
 */
sfit_status_t sfit_coverage_max_sigma(sfit_coverage_kind_t kind, float theta, float r,
                                      float *sigma_max);

/**
 * @brief Smallest half-angle a noise level needs: the theta at which
 * sqrt(lmin(theta)) / r = sigma_over_r (the inverse of
 * sfit_coverage_max_sigma()); any larger coverage gives rho < 1.
 * @param[in]  kind          Cap or arc.
 * @param[in]  sigma_over_r  sigma / r (>= 0); 0 gives theta = 0.
 * @param[out] theta         Radians in [0, pi]; written only on SFIT_OK.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL theta, invalid kind, or sigma_over_r < 0
 * @retval SFIT_E_NONFINITE  sigma_over_r is NaN or Inf
 * @retval SFIT_E_RANGE      no coverage suffices: sigma_over_r >= 1/sqrt(3)
 *                           (cap) or >= 1/sqrt(2) (arc)
 * @par Cost  bisection, at most ::SFIT_COVERAGE_BISECT_ITERS evaluations.
 */
sfit_status_t sfit_coverage_min_theta(sfit_coverage_kind_t kind, float sigma_over_r,
                                      float *theta);

/**
 * @brief Estimate the covered half-angle from measured covariance
 * eigenvalues, through a ratio that does not depend on the radius.
 *
 *  - Cap: q = lambda0 / ((lambda1 + lambda2) / 2), the axial eigenvalue over
 *    the mean of the two lateral ones (equal for a circular cap; their mean
 *    keeps an elliptical coverage, e.g. more flexion than abduction, from
 *    being judged by one direction only). The model ratio
 *    sin^2(theta/2) / (2 + cos theta) increases from 0 to 1 on (0, pi].
 *  - Arc: q = lambda1 / lambda2, radial over tangential (lambda0 is the
 *    out-of-plane noise); the model ratio also increases from 0 to 1.
 *
 * The measured eigenvalues include the noise, lambda = lambda0 + sigma^2:
 * subtract a known sigma^2 first (else small coverages are overestimated,
 * since noise inflates the small eigenvalue most). The result is the
 * half-angle of the uniformly covered cap / arc with the same ratio.
 * @param[in]  kind  Cap or arc.
 * @param[in]  eig   Eigenvalues, ascending (as in sfit_result_t).
 * @param[out] theta Radians in (0, pi]; written only on SFIT_OK.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL pointer, invalid kind, eigenvalues not
 *                           ascending, or lambda2 <= 0
 * @retval SFIT_E_NONFINITE  an eigenvalue is NaN or Inf
 * @retval SFIT_E_DEGENERATE the ratio's numerator is <= 0 (no measurable
 *                           coverage, e.g. after subtracting too much noise)
 */
sfit_status_t sfit_coverage_estimate_theta(sfit_coverage_kind_t kind, const sfit_vec3_t *eig,
                                           float *theta);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_COVERAGE_H */
