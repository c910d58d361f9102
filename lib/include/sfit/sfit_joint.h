/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_joint.h
 * @brief Functional joint centre as a stream: register the parent cluster,
 * express each child marker in the parent frame, accumulate, solve.
 * @defgroup sfit_joint Functional joint centre
 * @{
 *
 * A parent segment carries a rigid cluster (template, sfit_cluster.h); a
 * child segment carries 1..SFIT_JOINT_MAX_CHILD markers. Each frame
 * (sfit_joint_add) registers the parent, maps every child marker into the
 * parent's template frame and adds it to that marker's moments accumulator
 * (O(1) memory per marker). sfit_joint_fit() is the multi-marker fit
 * (sfit_multi.h) of those accumulators: the joint centre (ball) or the
 * hinge axis and a centre on it, in the parent's template frame; it leaves
 * the state unchanged and can be called at any time.
 * sfit_joint_center_at() gives the centre in the global frame of one frame.
 *
 * A rejected frame leaves the state bit for bit unchanged (so rejected
 * frames are not counted in the state). A child marker with a NaN
 * coordinate is skipped for that frame only.
 *
 * Frames, conventions, derivation and notes: docs/joint.md
 */
#ifndef SFIT_JOINT_H
#define SFIT_JOINT_H

#include <stddef.h>
#include <stdint.h>

#include "sfit_cluster.h"
#include "sfit_config.h"
#include "sfit_moments.h"
#include "sfit_multi.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief What the noise options of the solve describe. */
typedef enum sfit_joint_noise {
    SFIT_JOINT_NOISE_SOLVE = 0,  /**< cfg.solve.fit is used as given: its Sigma_hat is the
                                      noise of a child marker in the parent frame. */
    SFIT_JOINT_NOISE_MARKER = 1  /**< cfg.solve.fit.noise must be SFIT_NOISE_ISO and
                                      noise_var is the variance of each coordinate of every
                                      measured marker (parent and child); the solve is
                                      sfit_multi_fit_noise() with each child marker's own
                                      propagation of it through the parent pose,
                                      sfit_joint_marker_noise(). */
} sfit_joint_noise_t;

/** @brief Options of a joint. Start from ::sfit_joint_cfg_default. */
typedef struct sfit_joint_cfg {
    uint32_t n_child;        /**< Child markers, 1..SFIT_JOINT_MAX_CHILD. */
    sfit_multi_cfg_t solve;  /**< Multi-marker solve: mode (auto/sphere/planar),
                                  noise model, marker weights. */
    sfit_joint_noise_t noise_model; /**< Meaning of the solve's noise options. */
} sfit_joint_cfg_t;

/** @brief Defaults: 1 child marker, ::sfit_multi_cfg_default (auto, MGDK),
 * SFIT_JOINT_NOISE_SOLVE. */
extern const sfit_joint_cfg_t sfit_joint_cfg_default;

/**
 * @brief Streaming joint-centre state. Caller-owned; members are private.
 * Initialise with sfit_joint_init().
 */
typedef struct sfit_joint {
    sfit_cluster_t parent;                        /**< Parent template (a copy). */
    sfit_joint_cfg_t cfg;                         /**< Options (a copy). */
    sfit_moments_t child[SFIT_JOINT_MAX_CHILD];   /**< One accumulator per child marker,
                                                       parent frame. */
    uint32_t frames;                              /**< Frames accepted. */
    float res_mean;                               /**< Mean registration RMS residual. */
    float res_max;                                /**< Largest registration RMS residual. */
} sfit_joint_t;

/** @brief A joint centre. Written only on SFIT_OK; always finite. */
typedef struct sfit_joint_result {
    sfit_multi_result_t fit;  /**< Common centre, axis (hinge), eigenvalues, flags,
                                   mode: all in the parent template frame. */
    uint32_t frames;          /**< Frames accepted so far. */
    float residual_mean;      /**< Mean over accepted frames of the parent's RMS
                                   registration residual. */
    float residual_max;       /**< Largest such residual. */
} sfit_joint_result_t;

/**
 * @brief Initialise a joint: copy the parent template and the options, clear
 * the accumulators.
 * @param[out] j       State; written only on SFIT_OK.
 * @param[in]  parent  Parent cluster template (valid: 3..SFIT_CLUSTER_MAX_MARKERS markers).
 * @param[in]  cfg     Options; NULL = ::sfit_joint_cfg_default.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  NULL j/parent, parent count out of range, n_child not in
 *                     1..SFIT_JOINT_MAX_CHILD, or an invalid solve option
 * @par Cost O(SFIT_JOINT_MAX_CHILD) stores.
 */
sfit_status_t sfit_joint_init(sfit_joint_t *j, const sfit_cluster_t *parent,
                              const sfit_joint_cfg_t *cfg);

/**
 * @brief Forget every frame; keep the template and the options.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  j is NULL or its counters are not valid
 */
sfit_status_t sfit_joint_reset(sfit_joint_t *j);

/**
 * @brief Add one frame.
 *
 * Everything is validated before the state is touched: on any status but
 * SFIT_OK the state is bit for bit unchanged.
 * @param[in,out] j         State.
 * @param[in]     parent    Parent markers (global), template order; NaN = occluded.
 * @param[in]     n_parent  Must equal the template's marker count.
 * @param[in]     child     Child markers (global); a marker with a NaN coordinate
 *                          is skipped for this frame.
 * @param[in]     n_child   Must equal cfg.n_child.
 * @param[out]    pose      NULL, or the parent's pose in this frame; written only on SFIT_OK.
 * @retval SFIT_OK            frame accepted
 * @retval SFIT_E_ARG         NULL j/parent/child, a count mismatch, or garbage
 *                            counters in the state
 * @retval SFIT_E_NONFINITE   a parent or child coordinate is +-Inf
 * @retval SFIT_E_TOO_FEW     fewer than 3 parent markers seen
 * @retval SFIT_E_RANGE       a coordinate (global or mapped) >= 2^SFIT_COORD_MAX_EXP,
 *                            or a counter is full
 * @retval SFIT_E_DEGENERATE  the seen parent markers are collinear or coincident
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @par Cost 4 parent + 5 child markers: 1191.3 FLOPs per frame, amortised
 * (tools/flopcount "joint_frame"); 45 FLOPs per further child
 * marker ("joint_per_child").
 */
sfit_status_t sfit_joint_add(sfit_joint_t *j, const sfit_vec3_t *parent, size_t n_parent,
                             const sfit_vec3_t *child, size_t n_child, sfit_pose_t *pose);

/**
 * @brief Solve the joint centre from the frames so far (the state is not modified).
 * @param[in]  j      State.
 * @param[out] out    Result; written only on SFIT_OK.
 * @param[out] radii  NULL, or cfg.n_child floats: each child marker's radius about
 *                    the centre (distance to the axis for a hinge; 0 for a marker
 *                    skipped for too few samples); written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL j/out, or garbage counters or options in the state
 * @retval SFIT_E_TOO_FEW     no child marker has SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_DEGENERATE  as the multi-marker solve (coincident/collinear, or
 *                            singular sphere system)
 * @retval SFIT_E_NOT_POSDEF  as the multi-marker solve (noise-compensated system)
 * @retval SFIT_E_TOO_FEW     (also) SFIT_JOINT_NOISE_MARKER with no child marker
 *                            having 2 samples
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @retval SFIT_E_RANGE       the result would not be finite
 * @par Cost 5 child markers: 933 FLOPs (tools/flopcount "joint_fit"); with
 * SFIT_JOINT_NOISE_MARKER 3279 FLOPs ("joint_fit_marker").
 */
sfit_status_t sfit_joint_fit(const sfit_joint_t *j, sfit_joint_result_t *out, float *radii);

/**
 * @brief Noise covariance of a child marker in the parent frame, to first
 * order, for isotropic noise of variance @p marker_var on every coordinate
 * of every measured marker:
 *   marker_var ((1 + 1/P) I + mean [y]x J^-1 [y]x^T),
 * P the parent's marker count, J = sum_i (|p_i|^2 I - p_i p_i^T) over the
 * template centred on its centroid, y a child sample relative to that
 * centroid; the mean is over each child marker's samples (from its moments:
 * E[y y^T] = m m^T + (N-1)/N C), then over the markers with samples, equally
 * weighted. The rotation term grows with the lever arm |y| (docs/joint.md).
 * Occlusion of parent markers is not modelled (all P assumed seen).
 * @param[in]  j           State.
 * @param[in]  marker_var  sigma^2 (>= 0, finite), in squared input units.
 * @param[out] cov         Covariance (symmetric); written only on SFIT_OK.
 * @retval SFIT_OK         success
 * @retval SFIT_E_ARG        NULL j/cov, garbage counters, or marker_var negative
 * @retval SFIT_E_NONFINITE  marker_var is NaN or Inf
 * @retval SFIT_E_TOO_FEW    no child marker has 2 samples
 * @retval SFIT_E_RANGE    the result would not be finite, or a child accumulator
 *                         is corrupted (statistics not finite)
 * @par Cost O(cfg.n_child), one 3x3 symmetric inverse (Cholesky).
 */
sfit_status_t sfit_joint_noise_cov(const sfit_joint_t *j, float marker_var, sfit_mat3_t *cov);

/**
 * @brief Noise model of each child marker in the parent frame, for
 * sfit_multi_fit_noise(): per marker i, cov = the mean over its samples of
 * the covariance of sfit_joint_noise_cov() (evaluated at each sample, not
 * averaged over the markers), and skew = the mean of
 * (2 Sigma(y) + tr Sigma(y) I)(y - m_i), the bias that this position-dependent
 * noise puts into the marker's third-moment vector S_i. Both come from the
 * marker's moments; the one term they cannot give, the anisotropic part of
 * J^-1 in E[(b^T J^-1 b) b], is left out (docs/joint.md#per-marker-noise).
 * A marker with fewer than 2 samples gets a zero model.
 * @param[in]  j           State.
 * @param[in]  marker_var  sigma^2 (>= 0, finite), in squared input units.
 * @param[out] noise       cfg.n_child models; written only on SFIT_OK.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL j/noise, garbage counters, or marker_var negative
 * @retval SFIT_E_NONFINITE  marker_var is NaN or Inf
 * @retval SFIT_E_TOO_FEW    no child marker has 2 samples
 * @retval SFIT_E_RANGE      a model would not be finite, or a child accumulator is
 *                           corrupted (statistics not finite)
 * @par Cost O(cfg.n_child), one 3x3 symmetric inverse (Cholesky).
 */
sfit_status_t sfit_joint_marker_noise(const sfit_joint_t *j, float marker_var,
                                      sfit_multi_noise_t *noise);

/**
 * @brief Covariance of the joint centre of a result, to first order, for
 * isotropic noise of variance @p marker_var on every measured marker
 * coordinate (parent and child): a second pass over the frames that gave
 * the result.
 *
 * The parent's pose error is shared by every child marker of a frame, so
 * the centre's covariance depends on products of different markers'
 * positions in the same frame, which no per-marker accumulator holds: this
 * function reads the frames again (a caller's array) with the centre and
 * the marker means already known. Cov = A^-1 M A^-1 with A the solve's
 * matrix sum w_p C'_p and
 * M = sigma^2 sum_f [sum_p v_p^2 |a|^2 b b^T + W_f E W_f^T], W_f = sum_p v_p b a^T,
 * a = y - c, b = y - m_p for each child sample y of frame f in the parent
 * frame, v_p = w_p / (N_p - 1), E = I/P + [c - pb]x J^-1 [c - pb]x^T the
 * pose translation at the centre per unit variance (docs/joint.md#centre-covariance).
 * Planar result: the pseudo-inverse normal to the axis (the covariance of
 * the centre's part normal to the axis; the position along the axis is a
 * convention). Frames that sfit_joint_add() rejects are skipped, so the same
 * arrays as were added give the covariance of that result.
 * @param[in]  j           State that gave @p res (not modified).
 * @param[in]  res         Its result (sfit_joint_fit()).
 * @param[in]  parent      nf x (parent marker count) parent markers, frame by frame.
 * @param[in]  child       nf x cfg.n_child child markers, frame by frame.
 * @param[in]  nf          Frames.
 * @param[in]  marker_var  sigma^2 (>= 0, finite), in squared input units.
 * @param[out] cov         Centre covariance (symmetric); written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL j/res/parent/child/cov, garbage counters, marker_var < 0
 * @retval SFIT_E_NONFINITE   marker_var NaN or Inf, a non-finite centre or axis in res,
 *                            or an unknown mode
 * @retval SFIT_E_TOO_FEW     nf is 0, or no child marker has SFIT_MIN_SAMPLES samples
 * @retval SFIT_E_NOT_POSDEF  the solve's matrix is not positive definite
 * @retval SFIT_E_RANGE       the result would not be finite, or a child
 *                            accumulator is corrupted (statistics not finite)
 * @par Cost 4 parent + 5 child markers: 1327.45 FLOPs per frame (tools/flopcount
 * "joint_center_cov_frame").
 */
sfit_status_t sfit_joint_center_cov(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                    const sfit_vec3_t *parent, const sfit_vec3_t *child,
                                    size_t nf, float marker_var, sfit_mat3_t *cov);

/**
 * @brief The joint centre (and axis) in the global frame for one frame:
 * registers the parent markers of that frame with the joint's template and
 * maps the result's centre (and axis) back.
 * @param[in]  j         State (its template is used).
 * @param[in]  res       A result of sfit_joint_fit().
 * @param[in]  parent    That frame's parent markers (global); NaN = occluded.
 * @param[in]  n_parent  Must equal the template's marker count.
 * @param[out] center    Centre in the global frame; written only on SFIT_OK.
 * @param[out] axis      NULL, or the axis (res->fit.axis) in the global frame;
 *                       written only on SFIT_OK.
 * @retval SFIT_OK, SFIT_E_ARG, SFIT_E_TOO_FEW, SFIT_E_DEGENERATE, SFIT_E_NONFINITE,
 *         SFIT_E_RANGE, SFIT_E_NO_CONVERGENCE  as sfit_cluster_register()
 *         (SFIT_E_ARG also for a NULL res/center or garbage counters;
 *         SFIT_E_NONFINITE also for a non-finite centre or axis in res)
 * @par Cost 4 parent markers: 851 FLOPs (tools/flopcount "joint_center_at").
 */
sfit_status_t sfit_joint_center_at(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                   const sfit_vec3_t *parent, size_t n_parent,
                                   sfit_vec3_t *center, sfit_vec3_t *axis);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_JOINT_H */
