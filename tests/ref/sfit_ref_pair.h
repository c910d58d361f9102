/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_ref_pair.h
 * @brief Double-precision oracle for the pair of segments (sfit_pair.h).
 * Independent of lib/: it keeps every frame's poses and works with the full
 * 6x6 system of SCoRE (Gaussian elimination with partial pivoting), the 6x6
 * eigen-problem for SARA (cyclic Jacobi), raw sums in double (no shift, no
 * Schur complement in float) and the sandwich covariance of the 6x6
 * estimating equations frame by frame.
 */
#ifndef SFIT_REF_PAIR_H
#define SFIT_REF_PAIR_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** One frame: parent and child poses, x_global = R x_segment + t (R row-major). */
typedef struct ref_pair_frame {
    double rp[9], tp[3], rc[9], tc[3];
} ref_pair_frame_t;

/** What the reference needs of a cluster template: centroid, J^-1 with
 *  J = sum (|q|^2 I - q q^T) about the centroid, marker count. */
typedef struct ref_pair_tpl {
    double cen[3];
    double jinv[9];
    double m;
} ref_pair_tpl_t;

/** Fill a ref_pair_tpl_t from n template points. Returns 0, nonzero if J is singular. */
int ref_pair_tpl(const double (*p)[3], size_t n, ref_pair_tpl_t *t);

/**
 * SCoRE by the full 6x6 normal equations, min sum |R_p c_p + t_p - R_c c_c - t_c|^2.
 * With var_p, var_c > 0 (and the templates): the errors-in-variables
 * correction of docs/pair.md in its 6x6 form, in centroid coordinates:
 * [[N (I - K_p), -M], [-M^T, N (I - K_c)]] (u, v) = (sum d', -sum A^T d'),
 * K = var (tr J^-1 I - J^-1), then c_p = cen_p + (I - K_p / 2) u,
 * c_c = cen_c + (I - K_c / 2) v. var_p = var_c = 0: plain SCoRE.
 * Returns 0, nonzero when the system is singular.
 */
int ref_pair_score(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                   const ref_pair_tpl_t *tc, double var_p, double var_c, double cp[3],
                   double cc[3]);

/**
 * SARA: the hinge axis in the parent frame, the parent part of the
 * eigenvector of the smallest eigenvalue of the 6x6 matrix
 * [[N I, -M], [-M^T, N I]] (var = 0), normalised, largest component
 * positive. With var_p, var_c > 0: the smallest eigenvector of the 3x3
 * Schur complement of the corrected 6x6 matrix, formed in double from raw
 * sums. eig3 (may be NULL): the eigenvalues of that Schur complement / N,
 * ascending. Returns 0 or nonzero.
 */
int ref_pair_sara(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                  const ref_pair_tpl_t *tc, double var_p, double var_c, double axis[3],
                  double eig3[3]);

/**
 * The hinge point: the least-squares centre of the (corrected) 6x6 system
 * with c_p's component along the axis fixed to that of the mid-point of
 * the two cluster centroids (parent frame, mean over frames). Returns 0 or nonzero.
 */
int ref_pair_hinge_point(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                         const ref_pair_tpl_t *tc, double var_p, double var_c,
                         const double axis[3], double cp[3]);

/**
 * First-order covariance of c_p (parent frame): the c_p block of
 * H^-1 (sum_f J_f Cov(eps_f) J_f^T) H^-1, H the (corrected) 6x6 matrix,
 * eps_f = c_p - A_f c_c - d_f, J_f = [I; -A_f^T],
 * Cov(eps_f) = P + A_f C A_f^T, P = var_p ([x] J_p^-1 [x]^T + I / M_p) at
 * x = c_p - cen_p, C likewise at c_c - cen_c. Also the SCoRE cost
 * sum |eps_f|^2 at (cp, cc) and its expectation (N - 2)(tr P + tr C).
 * Returns 0 or nonzero.
 */
int ref_pair_cov(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                 const ref_pair_tpl_t *tc, double var_p, double var_c, const double cp[3],
                 const double cc[3], double cov[9], double *cost, double *expect);

/**
 * The size quantiles of the skin term, by quadrature (docs/pair.md#model-error).
 * The visible sum vis estimates the total scale s^2 den + noise from nu dof
 * (vis ~ (s^2 den + noise) chi^2(nu) / nu); with a Jeffreys prior on that
 * scale, s^2 den / noise = rho nu / X - 1, rho = vis / noise, X ~ chi^2(nu).
 * ref_pair_sta_coverage: the probability that the centre's error, N(0, s^2 Q),
 * lies in the 95 % ellipsoid of the reported s^2 = kfq (vis - knc noise) / den
 * (chi^2(3) quantile), averaged over that spread of s^2.
 * ref_pair_sta_quantiles: kfq, the limit of much skin (3 F(3, nu)'s 95 %
 * quantile over chi^2(3)'s), and knc, the share of the noise for which the
 * coverage is 95 % at rho = 20. nu is 1, 3 or 6. Returns 0 on success.
 */
double ref_pair_sta_coverage(int nu, double rho, double kfq, double knc);
int ref_pair_sta_quantiles(int nu, double *kfq, double *knc);

/**
 * Skin motion linear in the joint angle (docs/pair.md#model-error), frame
 * by frame: the regression of the ball's residual r_f = A_f^T cp - g_f on
 * theta_f = vee(skew(Abar^T (A_f - Abar))) over the directions theta
 * excites (spread >= 3 % of the largest), less the part a centre shift
 * absorbs; its expectation under the marker noise (mean A^T P A + C at
 * (cp, cc)); when above its 95 % noise quantile, the model covariance of
 * the absorbed centre shift (parent frame). ratio: visible / noise;
 * excess: visible - noise when used (else 0). Returns 0, nonzero when
 * degenerate.
 */
int ref_pair_sta(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                 const ref_pair_tpl_t *tc, double var_p, double var_c, const double cp[3],
                 const double cc[3], double model[9], double *ratio, double *excess);

/**
 * The weighted default of a ball (SFIT_PAIR_METHOD_DEFAULT,
 * docs/pair.md#weighting), by the full 6x6 normal equations frame by frame:
 * the residual eps_f = A_f^T c_p - c_c - g_f (child frame) weighted by the
 * constant W = (mean_f A_f^T P A_f + C)^-1, P and C the point noises at the
 * first estimate (cp0, cc0); errors-in-variables corrected exactly in the
 * second-order noise model: with D(Z) = E[exp([w]x) Z exp([w]x)^T]
 * (a 9x9 operator, inverted), V = D_c^-1(W), P = I - K_p / 2, C = I - K_c / 2,
 * H = [[D_p^-1(sum A V A^T), -P^-1 (sum A) C^-1 W], [., N W]],
 * rhs = (P^-1 sum A V g', -W C^-1 sum g') in centroid coordinates.
 * cov (may be NULL): the first-order sandwich of c_p with each frame's
 * exact residual covariance A_f^T P A_f + C at the solution.
 * Returns 0 or nonzero.
 */
int ref_pair_score_wls(const ref_pair_frame_t *f, size_t n, const ref_pair_tpl_t *tp,
                       const ref_pair_tpl_t *tc, double var_p, double var_c, const double cp0[3],
                       const double cc0[3], double cp[3], double cc[3], double cov[9]);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_REF_PAIR_H */
