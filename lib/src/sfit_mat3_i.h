/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_mat3_i.h
 * @brief Internal 3x3 layer: packed symmetric storage and the inverse of a
 * positive-definite matrix from its Cholesky factor (sfit_mat3.c).
 *
 * Packed symmetric storage: p[0..5] = XX, YY, ZZ, XY, XZ, YZ.
 */
#ifndef SFIT_MAT3_I_H
#define SFIT_MAT3_I_H

#include "sfit/sfit_mat3.h"
#include "sfit_float.h"

/** @brief Unpack a packed symmetric matrix into a full row-major one. */
void sfit_i_sym_unpack(const float p[6], sfit_mat3_t *a);

/** @brief A[9] := the symmetric matrix of the lower triangle of a. */
void sfit_i_sym_full(const sfit_mat3_t *a, float A[9]);

/**
 * @brief Jacobi eigen-decomposition in place: A (full symmetric, destroyed)
 * and V (9 floats, or NULL when no eigenvectors are wanted) are working
 * storage; w written on SFIT_OK. Statuses as sfit_mat3_eig_sym().
 */
sfit_status_t sfit_i_eig_sym(float A[9], sfit_vec3_t *w, float *V);

/** @brief Pack the symmetric part of a (mean of each off-diagonal pair). */
void sfit_i_sym_pack(const sfit_mat3_t *a, float p[6]);

/** @brief A^-1 (full, symmetric) from the factor l of sfit_mat3_chol(). */
void sfit_i_chol_inverse(const sfit_mat3_t *l, sfit_mat3_t *inv);

/** @brief x = (L L^T)^-1 b for a factor l of sfit_mat3_chol() (x may alias
 * b; no check: a non-finite x is the caller's to test). */
void sfit_i_chol_solve(const sfit_mat3_t *l, const float b[3], float x[3]);

/** @brief y = L^-1 b (forward substitution with a Cholesky factor). */
void sfit_i_chol_forward(const sfit_mat3_t *l, const float b[3], float y[3]);

/** @brief p = a b (full 3x3). */
void sfit_i_mat3_mul(const sfit_mat3_t *a, const sfit_mat3_t *b, sfit_mat3_t *p);

/** @brief y = a x (full 3x3). */
void sfit_i_mat3_vec(const sfit_mat3_t *a, const float x[3], float y[3]);

/** @brief j = sum_i (|q_i|^2 I - q_i q_i^T), q_i = p_i - c: the spread of
 * count points about c (the inertia tensor of unit masses; a cluster
 * template's, sfit_joint.c and sfit_pair.c). */
void sfit_i_spread(const sfit_vec3_t *p, uint32_t count, const float c[3], sfit_mat3_t *j);

#endif /* SFIT_MAT3_I_H */
