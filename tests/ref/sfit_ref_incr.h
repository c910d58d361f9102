/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_incr.h
 * @brief Double-precision references for the incremental estimator
 * (chapter 5.4, eq. 224-232): the chapter's recursion as re-derived, and
 * the library's reformulation. Both are checked against the batch
 * ref_fit_sphere() in tests/test_incr.c; they share no code with lib/.
 *
 * A noise covariance is `const double cov[6]` (XX, YY, ZZ, XY, XZ, YZ) or
 * NULL (GDKE). Fallible functions return 0 on success, nonzero on failure
 * (outputs untouched).
 */
#ifndef SFIT_REF_INCR_H
#define SFIT_REF_INCR_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The chapter's recursion (eq. 224-230), absolute frame, double. */
typedef struct {
    size_t n;           /**< samples so far */
    double m[3];        /**< mean, eq. 224 */
    double C[3][3];     /**< C = sum y y^T/(n-1), eq. 227 */
    double Cp[3][3];    /**< C' = C - Sigma, eq. 228 */
    double Ci[3][3];    /**< C^-1, eq. 229 (Sherman-Morrison) */
    double S[3];        /**< S = sum |y|^2 y/(n-1), eq. 230 */
    double sig[3][3];   /**< Sigma_hat (zero for GDKE) */
    int ugdk;           /**< 1 when a covariance was given */
    int printed_229;    /**< 1: eq. 229 with the printed '+' sign (wrong) */
} ref_incr_chapter_t;

/** Start from a batch (ref_moments of the first n0 >= 4 samples, C^-1 by an
 *  explicit inverse). printed_229 selects the sign of eq. 229 as printed
 *  (to show that it is wrong) instead of the derived one. */
int ref_incr_chapter_start(ref_incr_chapter_t *s, const double (*x)[3], size_t n0,
                           const double *cov, int printed_229);

/** One step of eq. 224-230 with sample x. */
void ref_incr_chapter_add(ref_incr_chapter_t *s, const double x[3]);

/** Eq. 231/232: c = m + C^-1 S/2 (GDKE, C^-1 from the recursion) or
 *  m + C'^-1 S/2 (UGDK, C' from eq. 228, solved directly: C'^-1 has no
 *  rank-one recursion); r^2 = (n-1)/n tr C(') + |m - c|^2. */
int ref_incr_chapter_estimate(const ref_incr_chapter_t *s, double c[3], double *r);

/** The library's reformulation (lib/src/sfit_incr.c) in double: mean as
 *  p + d, Welford M2, raw T = sum |z|^2 z and Q = sum |z|^2 about p,
 *  p moved to the mean every n/8 samples while n < 8 block, then every
 *  `block` samples. */
typedef struct {
    size_t n, nb, block;
    double p[3], d[3], M2[3][3], T[3], Q;
    double sig[3][3];
} ref_incr_lib_t;

/** Empty state; cov NULL = GDKE; block >= 2. */
void ref_incr_lib_init(ref_incr_lib_t *s, const double *cov, size_t block);

/** Add one sample. */
void ref_incr_lib_add(ref_incr_lib_t *s, const double x[3]);

/** (M2 - (n-1) Sigma) a = (T - Q d)/2 - (n-1) Sigma d, c = p + a,
 *  r^2 = tr(M2 - (n-1) Sigma)/n + |a - d|^2. Fails for n < 4 or a
 *  singular system. */
int ref_incr_lib_estimate(const ref_incr_lib_t *s, double c[3], double *r);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_REF_INCR_H */
