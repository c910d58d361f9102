/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_multi.h
 * @brief Double-precision oracle for the planar (hinge) multi-marker
 * centre; complements ref_fit_multi / ref_fit_multi_weighted (sfit_ref.h),
 * which cover the sphere case. Independent of lib/.
 */
#ifndef SFIT_REF_MULTI_H
#define SFIT_REF_MULTI_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Several markers turning about one axis. With weights w_p (1, or n_p - 1
 * when `weighted`), A = sum w_p (C_p - Sigma), b = sum w_p ((C_p - Sigma)
 * (m_p - o) + S_p/2): the centre is o + A^+ b, A^+ the pseudo-inverse over
 * A's two largest eigen-directions, moved along the dropped direction (the
 * axis) to the weighted mean of the marker means. Per-marker radius: the
 * distance from the axis, r_p^2 = (n_p-1)/n_p tr(P C'_p P) + |P (m_p - c)|^2,
 * P = I - a a^T. xs[p] holds 3*ns[p] doubles; cov as in sfit_ref.h (NULL =
 * none). axis: unit, largest-magnitude component positive. radii may be
 * NULL. Returns 0, or nonzero (outputs untouched) on bad input or when a
 * kept eigenvalue of A is not positive or some r_p^2 <= 0.
 */
int ref_fit_multi_planar(const double *const *xs, const size_t *ns, size_t m,
                         const double *cov, int weighted, double center[3],
                         double axis[3], double *radii);

/**
 * Several markers with a noise model each (the unbiased solve for noise that
 * differs between markers and along their paths): equal weights,
 * A = sum_p (C_p - Sigma_p), b = sum_p ((C_p - Sigma_p)(m_p - o) + (S_p - t_p)/2),
 * o the first marker's mean. Sphere: c = o + A^-1 b, r_p^2 =
 * (n_p-1)/n_p tr(C_p - Sigma_p) + |m_p - c|^2. planar != 0: as
 * ref_fit_multi_planar with these A, b and C_p - Sigma_p. cov9[9 p..] is
 * Sigma_p (row-major), skew[3 p..] is t_p. axis (may be NULL for the
 * sphere) is then the smallest eigen-direction of A. Returns 0, or nonzero
 * (outputs untouched) on bad input, a non-positive (kept) eigenvalue of A or
 * some r_p^2 <= 0.
 */
int ref_fit_multi_noise(const double *const *xs, const size_t *ns, size_t m,
                        const double *cov9, const double *skew, int planar,
                        double center[3], double axis[3], double *radii);

/**
 * Covariance of a multi-marker centre c for independent isotropic noise of
 * variance var on every coordinate (known var), with weights w_p (1, or
 * (n_p - 1) m / sum_q (n_q - 1) when `weighted`), v_p = w_p / (n_p - 1):
 * A^-1 M A^-1 with A = sum w_p C'_p, C'_p = C_p - Sigma (cov as in
 * sfit_ref.h, NULL = none), r_p^2 = (n_p-1)/n_p tr C'_p + |m_p - c|^2,
 * a_p = m_p - c and
 *   M = var sum_p w_p^2 [(r_p^2 + 7.5 var order2) / (n_p - 1) C'_p
 *       + order2 var n_p / (n_p - 1)^2 (r_p^2 I + a_p a_p^T)]
 * (order2 = 0: first order; 1: with the second-order term of the
 * single-marker formula, docs/multi.md#centre-covariance). Moments sample
 * by sample in long double. axis != NULL: planar, the pseudo-inverse of A
 * normal to the unit axis. Returns 0, or nonzero on bad input or a
 * singular A.
 */
int ref_multi_center_cov(const double *const *xs, const size_t *ns, size_t m,
                         const double *cov, int weighted, const double c[3],
                         const double *axis, double var, int order2, double out[9]);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_REF_MULTI_H */
