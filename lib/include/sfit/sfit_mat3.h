/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_mat3.h
 * @brief Symmetric 3x3 kernels: Cholesky factor/solve, Jacobi eigen-decomposition.
 * @defgroup sfit_mat3 3x3 kernels
 * @{
 */
#ifndef SFIT_MAT3_H
#define SFIT_MAT3_H

#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Factor a symmetric positive definite A = L * L^T.
 * @param[in]  a  Symmetric matrix; only the lower triangle is read.
 * @param[out] l  Lower-triangular factor (upper part set to 0); written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         a or l is NULL
 * @retval SFIT_E_NOT_POSDEF  a pivot <= SFIT_CHOL_PIVOT_EPS * max diagonal, or not finite
 * @par Cost 3 sqrt, 3 div, 5 mul, 5 add/sub.
 * @note a and l may alias.
 */
sfit_status_t sfit_mat3_chol(const sfit_mat3_t *a, sfit_mat3_t *l);

/**
 * @brief Solve L * L^T x = b with a factor from sfit_mat3_chol().
 * @param[in]  l  Cholesky factor (lower triangle read).
 * @param[in]  b  Right-hand side.
 * @param[out] x  Solution; may alias b. Written only on SFIT_OK.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  a NULL pointer
 * @retval SFIT_E_RANGE  the solution is not finite (a factor with a zero or
 *                     non-finite entry, not from sfit_mat3_chol(); a non-finite b;
 *                     or overflow)
 */
sfit_status_t sfit_mat3_chol_solve(const sfit_mat3_t *l, const sfit_vec3_t *b, sfit_vec3_t *x);

/**
 * @brief Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations.
 *
 * A = V diag(w) V^T with w ascending and V orthonormal (eigenvectors are the
 * columns of V). At most SFIT_JACOBI_MAX_SWEEPS sweeps of 3 rotations.
 * @param[in]  a  Symmetric matrix (lower triangle read).
 * @param[out] w  Eigenvalues, ascending; written only on SFIT_OK.
 * @param[out] v  Eigenvectors as columns (may be NULL if not wanted).
 * @retval SFIT_OK                success
 * @retval SFIT_E_ARG             a or w is NULL
 * @retval SFIT_E_NONFINITE       a holds NaN or Inf
 * @retval SFIT_E_RANGE           a rotation overflowed (entries near FLT_MAX)
 * @retval SFIT_E_NO_CONVERGENCE  off-diagonal not negligible after the sweep bound
 */
sfit_status_t sfit_mat3_eig_sym(const sfit_mat3_t *a, sfit_vec3_t *w, sfit_mat3_t *v);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_MAT3_H */
