/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_joint.h
 * @brief Double-precision oracle for rigid-cluster registration and the
 * functional joint centre. Independent of lib/: the rotation comes from
 * Horn's unit-quaternion method (the largest eigenvector of a 4x4 symmetric
 * matrix, cyclic Jacobi in double), not from an SVD of the 3x3
 * cross-covariance as in the library.
 */
#ifndef SFIT_REF_JOINT_H
#define SFIT_REF_JOINT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Eigen-decomposition of a symmetric n x n matrix (n <= 4) by cyclic
 *  Jacobi in double: a (row-major, n*n) -> w (unsorted) and the columns of
 *  v (row-major, n*n). */
void ref_jacobi_n(const double *a, int n, double *w, double *v);

/**
 * Least-squares proper rotation and translation x ~ R p + t (Horn 1987:
 * quaternion = largest eigenvector of N(S), S = sum p q^T of the centred
 * sets). seen[i] != 0 selects the markers (NULL = all). R row-major.
 * rms = sqrt(mean |R p + t - x|^2) over the markers used (may be NULL).
 * Returns 0, or nonzero when fewer than 3 markers are used.
 */
int ref_horn_pose(const double (*tpl)[3], const double (*x)[3], const int *seen, size_t n,
                  double r[9], double t[3], double *rms);

/** R^T (x - t) */
void ref_pose_to_segment(const double r[9], const double t[3], const double x[3], double out[3]);

/** R x + t */
void ref_pose_to_global(const double r[9], const double t[3], const double x[3], double out[3]);

/**
 * Per-sample noise model of a child marker seen through a parent cluster
 * (np template points tpl, each marker coordinate of variance var): the
 * first-order covariance of a mapped sample u (parent frame),
 * Sigma(u) = var ((1 + 1/np) I + [u - pb]x J^-1 [u - pb]x^T), pb the template
 * centroid, J = sum (|p - pb|^2 I - (p - pb)(p - pb)^T). Over the n samples
 * xs (3 n doubles) of one marker: cov9 = mean Sigma(u_i) (row-major) and
 * skew = mean (2 Sigma(u_i) + tr Sigma(u_i) I)(u_i - mean u), sample by
 * sample (no moment shortcut). Returns 0, or nonzero for n < 2 or a singular J.
 */
int ref_joint_marker_noise(const double (*tpl)[3], size_t np, const double *xs, size_t n,
                           double var, double cov9[9], double skew[3]);

/**
 * First-order covariance of a joint centre c (equal marker weights, every
 * marker coordinate of variance var, parent and child): A^-1 M A^-1 with
 * A = sum_p (C_p - Sigma_p) (cov9: 9 per marker, row-major, or NULL for
 * none), M = var sum_f [sum_p v_p^2 |y - c|^2 (y - m_p)(y - m_p)^T
 * + W_f E W_f^T], W_f = sum_p v_p (y - m_p)(y - c)^T, v_p = 1/(n - 1),
 * E = I/np + [c - pb]x J^-1 [c - pb]x^T. xs[p] holds the n mapped samples
 * of marker p (parent frame, frame f at 3 f). axis != NULL: planar, the
 * pseudo-inverse of A normal to the unit axis. tpl == NULL: no parent (E = 0,
 * independent markers: the multi-marker centre's covariance). Returns 0, or
 * nonzero on bad input or a singular J or A.
 */
int ref_joint_center_cov(const double (*tpl)[3], size_t np, const double *const *xs, size_t m,
                         size_t n, const double *cov9, const double c[3], const double *axis,
                         double var, double cov[9]);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_REF_JOINT_H */
