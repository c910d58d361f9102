/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pair.h
 * @brief A pair of segments: joint centre (SCoRE) and hinge axis (SARA)
 * from the poses of a parent and a child cluster, as a stream, with the
 * errors-in-variables bias removed and a covariance on every result.
 * @defgroup sfit_pair Pair of segments (SCoRE / SARA)
 * @{
 *
 * Each frame gives the parent's pose (R_p, t_p) and the child's (R_c, t_c)
 * (sfit_cluster_register() of each cluster). The joint centre is the point
 * fixed in both segments, c_p in the parent's template frame and c_c in the
 * child's:
 *   min over (c_p, c_c) of sum_f |R_p c_p + t_p - R_c c_c - t_c|^2   (SCoRE).
 * sfit_pair_add() accumulates, in O(1) memory, the relative rotation
 * A = R_p^T R_c, the child-frame vector g = R_c^T (t_c - t_p), their sums and
 * second moments (shifted by the first frame), and the registration
 * residuals of both clusters (the marker variance: E sum|res|^2 =
 * (3M - 6) sigma^2 per frame). sfit_pair_solve() eliminates c_c (Schur
 * complement S = sum (A - mean A)(A - mean A)^T, symmetric 3x3), removes the
 * errors-in-variables bias that noisy rotations put into S and the
 * right-hand side (with the marker variance from the residuals: no user
 * figure needed), decides ball or hinge from the eigenvalues of S, and gives
 * the centre (ball), or the axis (eigenvector of the smallest eigenvalue,
 * SARA) and a point on it (hinge), with their covariance and flags.
 *
 * The default ball centre is then weighted, in the same solve: the noise
 * covariance of each frame's residual at that first estimate (from the
 * templates' spreads and the marker variance), averaged over the frames,
 * is a constant weight W in the child frame; the 9x9 moment of A and the
 * 9x3 moment of (A, g) give the weighted, bias-corrected normal equations
 * for any W after the frames (one pass: no frame is kept). Not when the
 * first estimate fails the misfit test (its residual is not that noise).
 * SFIT_PAIR_METHOD_UNWEIGHTED gives the first estimate. docs/pair.md#weighting
 *
 * Every covariance has a model part: a ball's residual regressed on the
 * relative rotation (the same 9x9 and 9x3 moments) shows skin motion that
 * moves with the joint angle, and the centre shift such motion causes is
 * added (center_cov_model); a hinge's axis carries the tilt an out-of-axis
 * rotation in step with the flexion can cause (axis_cov_model).
 * docs/pair.md#model-error
 *
 * A rejected frame leaves the state bit for bit unchanged. Maths, the
 * default and why, flags: docs/pair.md
 */
#ifndef SFIT_PAIR_H
#define SFIT_PAIR_H

#include <stddef.h>
#include <stdint.h>

#include "sfit_cluster.h"
#include "sfit_config.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Which estimator sfit_pair_solve() gives. */
typedef enum sfit_pair_method {
    SFIT_PAIR_METHOD_DEFAULT = 0,   /**< SCoRE / SARA with the errors-in-variables bias
                                         removed using the marker variance; a ball centre
                                         weighted by the inverse noise covariance of the
                                         residual at a first estimate (default). */
    SFIT_PAIR_METHOD_SCORE = 1,     /**< Plain SCoRE (ball) / SARA (hinge), as published:
                                         biased at small range of motion. */
    SFIT_PAIR_METHOD_UNWEIGHTED = 2 /**< The default without the weighting (bias removed,
                                         every frame's residual weighted alike): the
                                         default of sfit 0.3. */
} sfit_pair_method_t;

/** @brief Ball or hinge. */
typedef enum sfit_pair_mode {
    SFIT_PAIR_MODE_AUTO = 0,  /**< cfg only: decide from the data (default). */
    SFIT_PAIR_MODE_BALL = 1,  /**< A centre fixed in both segments. */
    SFIT_PAIR_MODE_HINGE = 2  /**< An axis fixed in both segments; a point on it. */
} sfit_pair_mode_t;

/** @brief Where the marker variance of the solve comes from. */
typedef enum sfit_pair_noise {
    SFIT_PAIR_NOISE_RESIDUAL = 0, /**< Each cluster's registration residuals (default). */
    SFIT_PAIR_NOISE_GIVEN = 1     /**< cfg.marker_var for both clusters. */
} sfit_pair_noise_t;

/** @brief The main reason a result carries ::SFIT_FLAG_UNTRUSTED. */
typedef enum sfit_pair_reason {
    SFIT_PAIR_REASON_NONE = 0,        /**< Trusted. */
    SFIT_PAIR_REASON_FEW_FRAMES = 1,  /**< Fewer than cfg.min_frames frames. */
    SFIT_PAIR_REASON_SMALL_MOTION = 2,/**< The motion is too small for the noise: the bias
                                           correction and the covariance are not valid
                                           (trust_ratio > cfg.max_trust). */
    SFIT_PAIR_REASON_AXIS_FREE = 3,   /**< Hinge: the motion does not fix the axis (the two
                                           largest eigenvalues of S are not both above the
                                           noise). */
    SFIT_PAIR_REASON_AMBIGUOUS = 4,   /**< Auto mode: the data cannot tell ball from hinge. */
    SFIT_PAIR_REASON_MISFIT = 5,      /**< The residual of the joint model is far above what
                                           the marker noise explains (soft-tissue motion,
                                           a joint that is neither ball nor hinge, swapped
                                           labels): no noise model covers it. */
    SFIT_PAIR_REASON_NO_NOISE = 6     /**< No marker variance (no residuals and none given). */
} sfit_pair_reason_t;

/** @brief Result flags of the pair module (besides ::SFIT_FLAG_UNTRUSTED and
 * ::SFIT_FLAG_FEW_SAMPLES of ::sfit_flag; distinct bits). */
enum sfit_pair_flag {
    SFIT_PAIR_FLAG_SMALL_MOTION = 0x200u, /**< See ::SFIT_PAIR_REASON_SMALL_MOTION. */
    SFIT_PAIR_FLAG_AXIS_FREE = 0x400u,    /**< See ::SFIT_PAIR_REASON_AXIS_FREE. */
    SFIT_PAIR_FLAG_AMBIGUOUS = 0x800u,    /**< See ::SFIT_PAIR_REASON_AMBIGUOUS. */
    SFIT_PAIR_FLAG_MISFIT = 0x1000u,      /**< See ::SFIT_PAIR_REASON_MISFIT. */
    SFIT_PAIR_FLAG_NO_NOISE = 0x2000u     /**< See ::SFIT_PAIR_REASON_NO_NOISE. */
};

/** @brief Information bits of a result (sfit_pair_result_t::info): facts about the
 * data that are not faults (a flag means something is wrong). */
enum sfit_pair_info {
    SFIT_PAIR_INFO_AXIS_FREE = 0x1u,  /**< Ball: the motion does not fix a hinge axis (as
                                           expected of a ball joint moved about 3 axes). */
    SFIT_PAIR_INFO_SKIN = 0x2u        /**< Ball: the joint model's residual moves with the
                                           joint angle beyond the marker noise (skin motion);
                                           sta_rms > 0 and center_cov_model carries it. */
};

/** @brief Options of a pair. Start from ::sfit_pair_cfg_default. */
typedef struct sfit_pair_cfg {
    sfit_pair_method_t method;  /**< Estimator. */
    sfit_pair_mode_t mode;      /**< Ball, hinge or auto. */
    sfit_pair_noise_t noise;    /**< Source of the marker variance. */
    float marker_var;           /**< SFIT_PAIR_NOISE_GIVEN: variance of each coordinate of
                                     every marker (>= 0, squared input units). */
    float hinge_ratio;          /**< Auto mode: hinge when lambda_min / lambda_max of the
                                     corrected S is below this (0 = default 0.02). */
    float max_trust;            /**< Untrusted (SMALL_MOTION) when trust_ratio is above
                                     this (0 = default 0.25). */
    float max_misfit;           /**< Untrusted (MISFIT) when the residual ratio is above
                                     this (0 = default 2.0); the default method weights a
                                     ball's frames only when its first estimate is below. */
    float axis_tol;             /**< Hinge: untrusted (AXIS_FREE) when the axis may be
                                     further off than this angle (rad; 0 = default 10
                                     degrees): its 95 % noise cone, the out-of-axis
                                     rotation seen, atan sqrt(lambda_1 / lambda_2), or the
                                     tilt an unseen out-of-axis rotation of size wobble
                                     could cause, atan(wobble / flexion spread). */
    float wobble;               /**< Hinge: out-of-axis rotation (rms, rad) a joint may have
                                     in step with its flexion (then the data are a rotation
                                     about a tilted axis and cannot show it). 0 = the
                                     defaults: AXIS_FREE when a knee's 2.5 degrees rms
                                     could tilt the axis beyond axis_tol,
                                     atan(wobble / flexion spread) (the flexion range is
                                     too small), and a floor of 0.5 degrees rms under
                                     axis_cov's model part. Above 0: this value for all
                                     (a tiny value, 1e-6, for a mechanical hinge). The
                                     model part itself comes from the data: an
                                     out-of-axis rotation seen beyond its noise (2
                                     standard deviations) means the joint wobbles, and
                                     its unseen in-step share is taken as a knee's
                                     (2.5 degrees rms; wobble above 0: that) or twice
                                     the seen part, whichever is larger. */
    uint32_t min_frames;        /**< Untrusted (FEW_FRAMES) below this many frames
                                     (0 = default 30). */
} sfit_pair_cfg_t;

/** @brief Defaults: default method, auto mode, variance from the residuals. */
extern const sfit_pair_cfg_t sfit_pair_cfg_default;

/** @brief Quantities of the two-level sums of a pair (see sfit_pair.c). */
#define SFIT_PAIR_NSUM 92

/**
 * @brief Streaming pair state. Caller-owned; members are private.
 * Initialise with sfit_pair_init().
 */
typedef struct sfit_pair {
    sfit_pair_cfg_t cfg;        /**< Options (a copy). */
    sfit_vec3_t cen_p;          /**< Parent template centroid (parent frame). */
    sfit_vec3_t cen_c;          /**< Child template centroid (child frame). */
    float k_p[6];               /**< Parent: tr(J^-1) I - J^-1, packed (XX YY ZZ XY XZ YZ). */
    float k_c[6];               /**< Child: the same. */
    uint32_t n_p;               /**< Parent markers in the template. */
    uint32_t n_c;               /**< Child markers in the template. */
    float a_ref[9];             /**< First frame's A (the shift of the sums). */
    float g_ref[3];             /**< First frame's g. */
    float d_ref[3];             /**< First frame's d = R_p^T (t_c - t_p). */
    uint32_t frames;            /**< Frames accepted. */
    uint32_t inblk;             /**< Terms in the inner level. */
    float tot[SFIT_PAIR_NSUM];  /**< Outer level of the sums. */
    float blk[SFIT_PAIR_NSUM];  /**< Inner level of the sums. */
} sfit_pair_t;

/** @brief A joint of two segments. Written only on SFIT_OK; always finite. */
typedef struct sfit_pair_result {
    sfit_pair_mode_t mode;      /**< SFIT_PAIR_MODE_BALL or SFIT_PAIR_MODE_HINGE. */
    sfit_pair_method_t method;  /**< Estimator used. */
    sfit_vec3_t center_p;       /**< Centre (ball) or point on the axis (hinge, the one
                                     nearest the mid-point of the two clusters), parent
                                     template frame. */
    sfit_vec3_t center_c;       /**< The same point in the child template frame. */
    sfit_vec3_t axis_p;         /**< Hinge axis (ball: the least-determined direction),
                                     unit, parent frame; largest component positive. */
    sfit_vec3_t axis_c;         /**< The same axis in the child frame (A^T axis_p). */
    sfit_mat3_t center_cov;     /**< Covariance of center_p (parent frame, squared input
                                     units): the marker noise's (scaled by the misfit
                                     when above 1) plus center_cov_model; hinge: of the
                                     part normal to the axis plus the axis' tilt at that
                                     point. docs/pair.md#model-error */
    sfit_mat3_t axis_cov;       /**< Hinge: covariance of the unit axis_p (rad^2): the
                                     noise's plus axis_cov_model; ball: zero. */
    sfit_mat3_t center_cov_model; /**< Ball: the model part of center_cov (included in
                                     it): the centre shift that skin motion linear in the
                                     joint angle causes, its size estimated from the
                                     angle-correlated residual (docs/pair.md#model-error);
                                     hinge: zero. */
    sfit_mat3_t axis_cov_model; /**< Hinge: the model part of axis_cov (included in it):
                                     the tilt that an out-of-axis rotation in step with
                                     the flexion can cause unseen (cfg.wobble: from the
                                     floor, or, once one is seen (wobble_rms), a knee's
                                     wobble or twice the seen part); ball: zero. */
    float sta_rms;              /**< Ball: RMS of the angle-correlated part of the joint
                                     model's residual beyond the noise (input units): how
                                     far the clusters move on their segments with the
                                     joint angle, as seen at the joint. Hinge: 0. */
    float sta_ratio;            /**< Ball: the angle-correlated residual / its expectation
                                     from the marker noise (about 1 without skin motion;
                                     6 dof). Hinge: 0. */
    float wobble_rms;           /**< Hinge: out-of-axis rotation seen beyond the noise
                                     (rms, rad). Ball: 0. */
    uint32_t info;              /**< ::sfit_pair_info bits (informational, not faults). */
    sfit_vec3_t eigenvalues;    /**< Eigenvalues of the (corrected) S / frames, ascending:
                                     the spread of the relative rotations (rad^2). */
    float trust_ratio;          /**< Noise eigenvalue / smallest eigenvalue used (ball:
                                     lambda_1, hinge: lambda_2) of S; the correction and
                                     the covariance are first order in it. */
    float misfit;               /**< Residual of the joint model / its expectation from the
                                     marker noise (about 1 when the model holds); ball:
                                     the part not explained by skin motion linear in the
                                     joint angle (sta_rms). */
    float rms;                  /**< RMS of the joint model's residual per frame (input units). */
    float marker_var;           /**< Marker variance used (mean of the two clusters'). */
    float marker_var_p;         /**< Parent cluster's marker variance. */
    float marker_var_c;         /**< Child cluster's marker variance. */
    sfit_pair_noise_t noise;    /**< Where the variance came from. */
    uint32_t frames;            /**< Frames accepted. */
    uint32_t flags;             /**< ::sfit_flag / ::sfit_pair_flag bits. */
    sfit_pair_reason_t reason;  /**< Main reason of SFIT_FLAG_UNTRUSTED (NONE without it). */
} sfit_pair_result_t;

/**
 * @brief Initialise a pair from the two cluster templates (their centroids
 * and spreads give the rotation noise of each pose).
 * @param[out] s       State; written only on SFIT_OK.
 * @param[in]  parent  Parent template (the frame of R_p, t_p).
 * @param[in]  child   Child template (the frame of R_c, t_c).
 * @param[in]  cfg     Options; NULL = ::sfit_pair_cfg_default.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL s/parent/child, a template count out of range or
 *                            a position not finite / out of range, an invalid option
 *                            (enum out of range, marker_var < 0 or not finite, a
 *                            threshold negative or not finite)
 * @retval SFIT_E_DEGENERATE  a template's markers are collinear (spread not invertible)
 * @par Cost O(markers) + two 3x3 Cholesky inverses. State: 916 B (sfit_pair_t, M4F).
 */
sfit_status_t sfit_pair_init(sfit_pair_t *s, const sfit_cluster_t *parent,
                             const sfit_cluster_t *child, const sfit_pair_cfg_t *cfg);

/**
 * @brief Forget every frame; keep the templates' summaries and the options.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  s is NULL or its counters are not valid
 * @par Cost no FLOPs (clears 145 words).
 */
sfit_status_t sfit_pair_reset(sfit_pair_t *s);

/**
 * @brief Add one frame from the two poses.
 *
 * Everything is validated before the state is touched: on any status but
 * SFIT_OK the state is bit for bit unchanged.
 * @param[in,out] s       State.
 * @param[in]     pose_p  Parent pose (sfit_cluster_register()).
 * @param[in]     fit_p   NULL, or the parent registration's residual (rms, used).
 * @param[in]     pose_c  Child pose.
 * @param[in]     fit_c   NULL, or the child registration's residual.
 * @retval SFIT_OK            frame accepted
 * @retval SFIT_E_ARG         NULL s/pose_p/pose_c, garbage counters in the state, a
 *                            fit with used not in 3..SFIT_CLUSTER_MAX_MARKERS or a
 *                            negative rms
 * @retval SFIT_E_NONFINITE   a pose or rms entry is NaN or Inf
 * @retval SFIT_E_RANGE       a translation >= 2^SFIT_COORD_MAX_EXP, a rotation entry
 *                            beyond 1 + 1e-3 in magnitude, or the frame counter full
 * @par Cost 271.44 FLOPs per frame, amortised over a block of SFIT_SUM_BLOCK
 * frames (tools/flopcount "pair_add"; instructions and stack: docs/cost.md).
 */
sfit_status_t sfit_pair_add(sfit_pair_t *s, const sfit_pose_t *pose_p,
                            const sfit_cluster_fit_t *fit_p, const sfit_pose_t *pose_c,
                            const sfit_cluster_fit_t *fit_c);

/**
 * @brief Add one frame from the markers: registers both clusters
 * (sfit_cluster_register()) and adds the poses with their residuals.
 * @param[in,out] s       State.
 * @param[in]     parent  Parent template (the one given to sfit_pair_init()).
 * @param[in]     pm      Parent markers (global), template order; NaN = occluded.
 * @param[in]     n_pm    Must equal the parent template's count.
 * @param[in]     child   Child template.
 * @param[in]     cm      Child markers (global); NaN = occluded.
 * @param[in]     n_cm    Must equal the child template's count.
 * @retval SFIT_OK  frame accepted
 * @retval any status of sfit_cluster_register() (for either cluster) or of
 *         sfit_pair_add(); SFIT_E_ARG also when a template's count differs from
 *         the one given to sfit_pair_init(). The state is unchanged on any error.
 * @par Cost 4 parent + 5 child markers: 2265.44 FLOPs per frame (tools/flopcount
 * "pair_add_markers"; instructions and stack: docs/cost.md).
 */
sfit_status_t sfit_pair_add_markers(sfit_pair_t *s, const sfit_cluster_t *parent,
                                    const sfit_vec3_t *pm, size_t n_pm,
                                    const sfit_cluster_t *child, const sfit_vec3_t *cm,
                                    size_t n_cm);

/**
 * @brief Solve from the frames so far (the state is not modified). Default
 * method, ball: the bias-corrected SCoRE centre, then the centre weighted by
 * the inverse noise covariance of the residual at it (see the file's
 * description; flags and trust_ratio come from the first estimate).
 * @param[in]  s    State.
 * @param[out] out  Result; written only on SFIT_OK.
 * @retval SFIT_OK            success (check out->flags)
 * @retval SFIT_E_ARG         NULL s/out, or garbage counters or options in the state
 * @retval SFIT_E_TOO_FEW     fewer than 3 frames
 * @retval SFIT_E_DEGENERATE  the relative rotation never changed (S is zero), or the
 *                            system to solve is singular (ball forced with a motion
 *                            about one axis only)
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @retval SFIT_E_RANGE       the result would not be finite (corrupted sums)
 * @par Cost ball, default method (weighted), with the skin-motion term: 10039
 * FLOPs (tools/flopcount "pair_solve", 61141 M4F instructions, 2816 B stack);
 * plain SCoRE 6644 FLOPs ("pair_solve_score"); independent of the number of
 * frames (docs/cost.md).
 */
sfit_status_t sfit_pair_solve(const sfit_pair_t *s, sfit_pair_result_t *out);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_PAIR_H */
