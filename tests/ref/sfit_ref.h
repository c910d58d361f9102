/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref.h
 * @brief Independent double-precision reference (test oracle) for sfit.
 *
 * Written from the mathematics only (DESIGN.md section 1 and chapter 5 of
 * the source thesis, every formula re-derived); it shares no code with
 * lib/. Double precision with long double accumulators, no malloc, no VLA.
 * Points are `const double (*x)[3]` with a count n. A noise covariance is
 * `const double cov[6]` ordered XX, YY, ZZ, XY, XZ, YZ; NULL means none.
 * Every fallible function returns 0 on success and a nonzero value on
 * failure; on failure its outputs are left untouched.
 *
 * Matrices are "not positive definite" here when their smallest eigenvalue
 * is <= REF_PD_RTOL times their largest (or the largest is <= 0).
 */
#ifndef SFIT_REF_H
#define SFIT_REF_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** C99 does not convert `double (*)[3]` to `const double (*)[3]` implicitly
 *  (-Wpedantic): pass NON-const arrays of points or 3x3 matrices through
 *  REF_C3(). The detour through void * keeps gcc's -Wcast-qual quiet (it
 *  does not see array-of-const as adding a qualifier before C2X). */
#define REF_C3(a) ((const double (*)[3])(void *)(a))

/** Relative eigenvalue floor used for every positive-definiteness test. */
#define REF_PD_RTOL 1e-12

/** Symmetric 3x3 eigen-decomposition by cyclic Jacobi run to convergence.
 *  w ascending; eigenvectors are the COLUMNS of v (orthonormal, right-handed
 *  not guaranteed). Only the upper triangle of a is read. */
void ref_sym3_eig(const double a[3][3], double w[3], double v[3][3]);

/** Mean, C = sum y y^T/(n-1), S = sum |y|^2 y/(n-1), y = x - mean
 *  (long double two-pass with a correction pass). Fails if n < 2. */
int ref_moments(const double (*x)[3], size_t n, double mean[3], double C[3][3],
                double S[3]);

typedef struct {
    double center[3];
    double radius;
    double eig[3];      /**< eigenvalues of C (never C'), ascending */
    double axis[3];     /**< unit eigenvector of the smallest eigenvalue
                             (of C' for the circle with cov); sign: largest-
                             magnitude component positive */
    int planar;         /**< 1 for ref_fit_circle, 0 for ref_fit_sphere */
    double trust_ratio; /**< rho(C'^-1 Sigma); 0 when cov is NULL */
} ref_fit_t;

/** GDKE (cov NULL) or UGDK (cov given) sphere. Fails if n < 4 or C or
 *  C' = C - Sigma is not positive definite. */
int ref_fit_sphere(const double (*x)[3], size_t n, const double *cov,
                   ref_fit_t *out);

/** Planar / cylindrical-joint solution: Kasa circle in the best-fit plane
 *  (smallest eigen-direction of C, or of C' with cov, dropped). trust_ratio
 *  is rho of the 2x2 in-plane restriction of C'^-1 Sigma. Fails if n < 3 or
 *  a kept eigenvalue is not positive. */
int ref_fit_circle(const double (*x)[3], size_t n, const double *cov,
                   ref_fit_t *out);

/** 2-D algebraic (Kasa) circle: least squares on x^2+y^2 + D x + E y + F = 0.
 *  For the Gander-Golub-Strebel (1994) points (1,7) (2,6) (5,8) (7,7) (9,5)
 *  (3,7) it gives exactly c = (773/163, 5001/1304), r^2 = 28706289/1700416
 *  (4.742331, 3.835123; r = 4.108762). The "algebraic fit" printed by GGS,
 *  (5.3794, 7.2532), r = 3.0370, normalises the coefficient vector to unit
 *  length instead: it is not Kasa/GDKE. */
int ref_kasa_circle_2d(const double (*p)[2], size_t n, double c[2], double *r);

/** 3-D algebraic sphere: least squares on |x|^2 + a.x + b = 0 (4x4 normal
 *  equations on centred data, Gaussian elimination). */
int ref_kasa_sphere_direct(const double (*x)[3], size_t n, double c[3],
                           double *r);

/** Chapter eq. 177: mean |x - c0|^2 - r0^2 (estimate of Tr Sigma). */
double ref_noise_trace(const double (*x)[3], size_t n, const double c0[3],
                       double r0);

/** Var(sigma_hat^2), sigma_hat^2 = ref_noise_trace / dim, for isotropic
 *  Gaussian noise of variance sigma2 on exact sphere points (eq. 190):
 *  2 sigma2 (dim sigma2 + 2 r0^2) / (n dim^2). */
double ref_noise_trace_var(double sigma2, double r0, size_t n, int dim);

/** Multi-marker MGDK (eq. 220/221; eq. 222/223 with cov):
 *  c = (sum_p C_p)^-1 sum_p (C_p m_p + S_p/2), every marker weighted 1.
 *  xs[p] points to ns[p] points stored as 3*ns[p] doubles. radii[m]. */
int ref_fit_multi(const double *const *xs, const size_t *ns, size_t m,
                  const double *cov, double center[3], double *radii);

/** Same with weights (n_p - 1): the exact joint Kasa least squares. */
int ref_fit_multi_weighted(const double *const *xs, const size_t *ns, size_t m,
                           const double *cov, double center[3], double *radii);

/** Orthogonal-distance sphere fit (Levenberg-Marquardt). iters may be NULL.
 *  Fails on no convergence within the iteration bound or degenerate data. */
int ref_fit_geometric(const double (*x)[3], size_t n, const double c_init[3],
                      double r_init, double c[3], double *r, int *iters);

/** Cramer-Rao bound of (cx, cy, cz, r), isotropic Gaussian noise sigma2,
 *  given the true sample positions. All zero if the information is
 *  singular. */
void ref_crlb_sphere(const double (*x_true)[3], size_t n, const double c[3],
                     double r, double sigma2, double crlb[4][4]);

/** Sandwich covariance of the geometric fit at centre c (radius = mean
 *  distance), full 4x4 in (cx, cy, cz, r): A^-1 (s^2 J^T J) A^-1 with J rows
 *  [-u^T, -1], A = J^T J + sum f_i diag((I - u u^T)/d_i, 0), s^2 =
 *  sum f^2 / (n - 4). Returns -1 on a singular A or a sample at c. */
int ref_sandwich_geometric(const double (*x)[3], size_t n, const double c[3],
                           double cov[4][4]);

/** K of the widening of docs/coverage.md rule 7 (issue 28), written here
 *  independently of the library's SFIT_I_COV_WIDEN_K: the tests that use it
 *  fail if the two differ. */
#define REF_COV_WIDEN_K 3.5

/** Sandwich covariance of the self-calibrated UGDK centre (5 x 5 stacked
 *  M-estimator, not eliminated): parameters theta = (c, rho = r^2, v =
 *  sigma^2), per-sample estimating functions (z = x - c, k = (n-1)/n,
 *  d = |z|, dbar = mean d at c)
 *    psi_c   = (|z|^2 - rho - 5 k v) z          (unbiased Kasa, centre)
 *    psi_rho = |z|^2 - rho - 3 k v              (UGDK radius)
 *    psi_v   = (d - dbar)^2 - (n-4)/n (v - v^2/rho)   (residual noise with
 *                                                the curvature correction)
 *  A = sum d psi / d theta by central differences, B = sum psi psi^T,
 *  cov = n/(n-13) [A^-1 B A^-T]_cc (small-sample factor of sfit_uncert.h),
 *  times the widening 1 + K (v/r^2) sqrt(96/(n-4)), K = REF_COV_WIDEN_K
 *  (docs/coverage.md rule 7; n - 4 taken at least 10).
 *  Returns -1 on n < 14, a singular A or a sample at c. */
int ref_sandwich_selfcal(const double (*x)[3], size_t n, const double c[3], double r,
                         double v, double cov[3][3]);

/** Population covariance eigenvalues (numerical quadrature) of the uniform
 *  distribution on a spherical cap of half-angle theta, radius r. */
void ref_cap_eigs_numeric(double theta, double r, double *lmin, double *lmax);

/** Same for the uniform distribution on a circular arc of half-angle theta
 *  (the two in-plane eigenvalues). */
void ref_arc_eigs_numeric(double theta, double r, double *lmin, double *lmax);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_REF_H */
