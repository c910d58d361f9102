/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_noise.h
 * @brief Noise calibration against a known sphere, and coverage design aids.
 * @defgroup sfit_noise Noise calibration and coverage
 * @{
 *
 * Calibration (chapter eq. 177, 189, 190). Measure a sphere of known centre
 * c0 and radius r0 (a calibration jig, or a fixed point with r0 = 0). Then
 *   T = Tr(Sigma_hat) = (1/N) sum |x_i - c0|^2 - r0^2
 * is an unbiased estimate of Tr(Sigma) for any noise covariance Sigma and
 * any N >= 1 (x = p + e with |p - c0| = r0 gives
 * |x - c0|^2 = r0^2 + 2 (p - c0).e + |e|^2, of mean r0^2 + Tr Sigma). For
 * isotropic noise sigma^2 I in D = 3 dimensions, sigma_hat^2 = T / 3 and,
 * for Gaussian noise,
 *   Var(sigma_hat^2) = 2 sigma^2 (D sigma^2 + 2 r0^2) / (N D^2)   (eq. 190),
 * exact for every N (no O(1/N^2) term). The 2 r0^2 term dominates: a
 * calibration sphere of radius r0 estimates sigma^2 with a standard deviation
 * of about (2/3) sigma r0 / sqrt(N), so a small r0 calibrates better.
 *
 * Coverage (eq. 198-213). For samples spread uniformly over a spherical cap
 * (sphere fits) or a circular arc (hinge fits) of half-angle theta on a
 * sphere / circle of radius r, the covariance C tends to (N -> infinity)
 *  - cap, eq. 210/211:  lambda_axial   = r^2 sin^4(theta/2) / 3,
 *                       lambda_lateral = r^2 (2 + cos theta) sin^2(theta/2) / 3
 *                       (twice);
 *  - arc, eq. 203/204:  lambda_radial     = r^2 [theta (2 theta + sin 2 theta)
 *                                            - 4 sin^2 theta] / (4 theta^2),
 *                       lambda_tangential = r^2 (theta - sin theta cos theta)
 *                                            / (2 theta).
 * For every theta in (0, pi) the axial (cap) and the radial (arc) eigenvalue
 * is the strictly smaller one; at theta = pi (whole sphere / circle) the two
 * coincide (r^2/3 and r^2/2). They never swap, so the trust-limiting
 * eigenvalue is always the axial / radial one and there is no crossover
 * angle. The Leontief (trust) condition rho = sigma^2 / lambda_min < 1
 * (eq. 197) then reads sigma < sqrt(lambda_min(theta)), which is eq. 212
 * (cap) and eq. 213 (arc) exactly as printed.
 *
 * Float notes: every function is evaluated from power series in theta (no
 * trigonometric library call, no cancellation for small theta: the arc's
 * radial eigenvalue is r^2 theta^4/45 (1 + O(theta^2)), which the closed form
 * of eq. 203 would lose to rounding in float below ~20 degrees). Inverses are
 * bisections bounded by ::SFIT_COVERAGE_BISECT_ITERS.
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
    float noise_trace;   /**< Tr(Sigma_hat), eq. 177 (unit^2), unclamped. */
    float noise_var;     /**< sigma_hat^2 = noise_trace / 3 (unit^2), unclamped:
                              may be negative (see ::SFIT_NOISE_FLAG_NEGATIVE). */
    float noise_var_std; /**< Predicted standard deviation of noise_var, eq. 190
                              evaluated at |noise_var| (plug-in, Gaussian noise). */
    uint32_t flags;      /**< SFIT_NOISE_FLAG_* bits of ::sfit_flag. */
} sfit_noise_est_t;

/**
 * @brief Calibrate the measurement noise from samples of a known sphere
 * (eq. 177) and predict the spread of the estimate (eq. 190).
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
 * @par Cost  about 25 FLOPs and 1 square root (independent of N).
 */
sfit_status_t sfit_moments_calibrate(const sfit_moments_t *m, const sfit_vec3_t *c0, float r0,
                                   sfit_noise_est_t *out);

/**
 * @brief Predicted standard deviation of a calibration (eq. 190, D = 3):
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

/** @brief Coverage geometry. */
typedef enum sfit_coverage_kind {
    SFIT_COVERAGE_CAP = 0, /**< Spherical cap (ball joint, sphere fit). */
    SFIT_COVERAGE_ARC = 1  /**< Circular arc (hinge, planar fit). */
} sfit_coverage_kind_t;

/**
 * @brief Asymptotic covariance eigenvalues of a uniformly covered cap or arc
 * of half-angle theta and radius r.
 *
 * Cap (eq. 210/211): lmin = axial, lmax = lateral (double). Arc
 * (eq. 203/204): lmin = radial, lmax = tangential (in the circle's plane).
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

/** @brief sfit_coverage_eigs() for a cap (eq. 210/211); same statuses. */
sfit_status_t sfit_coverage_cap_eigs(float theta, float r, float *lmin, float *lmax);

/** @brief sfit_coverage_eigs() for an arc (eq. 203/204); same statuses. */
sfit_status_t sfit_coverage_arc_eigs(float theta, float r, float *lmin, float *lmax);

/**
 * @brief Largest noise standard deviation a coverage tolerates:
 * sigma_max = sqrt(lmin(theta)) (eq. 212 cap, eq. 213 arc), the sigma at
 * which rho = sigma^2 / lambda_min reaches 1. Multiply by sqrt(rho_target)
 * for a safety margin rho <= rho_target.
 * @param[in]  kind       Cap or arc.
 * @param[in]  theta      Half-angle in radians, 0 < theta <= pi.
 * @param[in]  r          Radius (> 0).
 * @param[out] sigma_max  Written only on SFIT_OK (same unit as r).
 * @retval as sfit_coverage_eigs(); SFIT_E_ARG also for a NULL sigma_max
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
#endif /* SFIT_NOISE_H */
