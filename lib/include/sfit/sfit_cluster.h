/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_cluster.h
 * @brief Pose of a rigid marker cluster: least-squares rotation and
 * translation of a template onto one frame's measured markers.
 * @defgroup sfit_cluster Rigid marker cluster
 * @{
 *
 * A cluster is 3..SFIT_CLUSTER_MAX_MARKERS markers fixed to one rigid
 * segment; its template holds their positions in the segment's own frame.
 * sfit_cluster_register() returns the pose (R, t) minimising
 * sum_i |R p_i + t - x_i|^2 over the markers seen, R a proper rotation:
 *   x_global = R x_segment + t,   x_segment = R^T (x_global - t).
 * A measured marker with a NaN coordinate is occluded and skipped.
 *
 * Frames, conventions, derivation and notes: docs/joint.md
 */
#ifndef SFIT_CLUSTER_H
#define SFIT_CLUSTER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sfit_config.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Template of a rigid cluster. Caller-owned; members are private.
 * Fill with sfit_cluster_init(), sfit_cluster_from_frame() or
 * sfit_cluster_from_frames().
 */
typedef struct sfit_cluster {
    uint32_t count;                              /**< Markers (3..SFIT_CLUSTER_MAX_MARKERS). */
    sfit_vec3_t pos[SFIT_CLUSTER_MAX_MARKERS];   /**< Positions in the segment frame. */
} sfit_cluster_t;

/**
 * @brief A rigid pose: x_global = r x_segment + t. A value type.
 */
typedef struct sfit_pose {
    sfit_mat3_t r;  /**< Proper rotation (det +1), segment -> global, row-major. */
    sfit_vec3_t t;  /**< Translation: the segment-frame origin in the global frame. */
} sfit_pose_t;

/** @brief What a registration measured besides the pose. */
typedef struct sfit_cluster_fit {
    float rms;      /**< RMS registration residual over the markers used:
                         sqrt(sum_i |R p_i + t - x_i|^2 / used), in input units. */
    uint32_t used;  /**< Markers used (seen, i.e. no NaN coordinate). */
} sfit_cluster_fit_t;

/**
 * @brief The state sfit_cluster_track() keeps between frames: the previous
 * frame's rotation. Caller-owned; members are private except steps. 24 B.
 */
typedef struct sfit_cluster_track {
    float q[4];     /**< Unit quaternion (w, x, y, z) of the previous rotation. */
    bool valid;     /**< true: q holds a previous frame's rotation; false: none (start,
                         gap). A byte other than 0/1 (a corrupted state): SFIT_E_ARG. */
    uint32_t steps; /**< Read-only: Newton steps the last successful call took from the
                         previous rotation; 0: it ran the full solve. */
} sfit_cluster_track_t;

/**
 * @brief Set a template from marker positions given in the segment frame.
 * The segment frame is the caller's frame of @p tpl (e.g. an anatomical
 * frame); nothing is re-centred.
 * @param[out] cl     Template; written only on SFIT_OK.
 * @param[in]  tpl    @p count positions, segment frame.
 * @param[in]  count  Markers, 3..SFIT_CLUSTER_MAX_MARKERS.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer, or count outside 3..SFIT_CLUSTER_MAX_MARKERS
 * @retval SFIT_E_NONFINITE   a coordinate is NaN or Inf
 * @retval SFIT_E_RANGE       |coordinate| >= 2^SFIT_COORD_MAX_EXP
 * @retval SFIT_E_DEGENERATE  the markers are coincident or collinear
 *                            (s2/s1 < SFIT_CLUSTER_COLLINEAR_RATIO, see sfit_cluster_register())
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @par Cost O(count) + one 3x3 Jacobi eigen-decomposition (the collinearity check).
 */
sfit_status_t sfit_cluster_init(sfit_cluster_t *cl, const sfit_vec3_t *tpl, size_t count);

/**
 * @brief Set a template from one measured frame. The segment frame is the
 * template frame of docs/joint.md: origin at the centroid of the markers,
 * axes parallel to the global axes at that frame.
 * @param[out] cl     Template; written only on SFIT_OK.
 * @param[in]  pts    @p count measured positions (global); every one must be finite.
 * @param[in]  count  Markers, 3..SFIT_CLUSTER_MAX_MARKERS.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL pointer, or count out of range
 * @retval SFIT_E_NONFINITE   a coordinate is NaN or Inf (occluded marker)
 * @retval SFIT_E_RANGE       |coordinate| >= 2^SFIT_COORD_MAX_EXP
 * @retval SFIT_E_DEGENERATE  coincident or collinear markers
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @par Cost O(count) + one 3x3 Jacobi eigen-decomposition.
 */
sfit_status_t sfit_cluster_from_frame(sfit_cluster_t *cl, const sfit_vec3_t *pts, size_t count);

/**
 * @brief Set a template averaged over several measured frames.
 *
 * The reference is the first frame whose markers are all finite and give a
 * valid template (sfit_cluster_from_frame()); it defines the frame's axes
 * (global axes at that frame). Every later frame is registered to the
 * reference and its seen markers, mapped into the segment frame, are
 * averaged marker by marker; frames that cannot be registered are skipped.
 * Finally the origin is moved to the centroid of the averaged markers.
 * @param[out] cl       Template; written only on SFIT_OK.
 * @param[in]  frames   @p nframes * @p count positions, frame-major
 *                      (frame f, marker i at frames[f * count + i]); NaN = occluded.
 * @param[in]  nframes  Number of frames (>= 1).
 * @param[in]  count    Markers per frame, 3..SFIT_CLUSTER_MAX_MARKERS.
 * @param[out] used     NULL, or the number of frames averaged (reference included).
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL frames/cl, nframes 0, or count out of range
 * @retval SFIT_E_TOO_FEW     no frame has every marker finite and a valid template
 * @retval SFIT_E_DEGENERATE  the averaged markers are collinear (a reference frame
 *                            at the limit of SFIT_CLUSTER_COLLINEAR_RATIO)
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @par Cost one sfit_cluster_register() per frame after the reference.
 */
sfit_status_t sfit_cluster_from_frames(sfit_cluster_t *cl, const sfit_vec3_t *frames,
                                       size_t nframes, size_t count, size_t *used);

/**
 * @brief Least-squares pose of the template on one frame's measured markers.
 * @param[in]  cl     Template.
 * @param[in]  meas   @p count measured positions (global), in template order;
 *                    a marker with a NaN coordinate is occluded and skipped.
 * @param[in]  count  Must equal the template's marker count.
 * @param[out] pose   Pose; written only on SFIT_OK.
 * @param[out] fit    NULL, or residual and markers used; written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         NULL cl/meas/pose, count differs from the template's,
 *                            or a corrupted template (count not in
 *                            3..SFIT_CLUSTER_MAX_MARKERS, a position not finite or
 *                            out of range)
 * @retval SFIT_E_NONFINITE   a coordinate is +-Inf (not an occlusion)
 * @retval SFIT_E_TOO_FEW     fewer than 3 markers seen
 * @retval SFIT_E_RANGE       |coordinate| >= 2^SFIT_COORD_MAX_EXP, or the result
 *                            would not be finite
 * @retval SFIT_E_DEGENERATE  the seen markers are coincident or collinear: the
 *                            second singular value of the cross-covariance is below
 *                            SFIT_CLUSTER_COLLINEAR_RATIO times the first
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @par Cost 4 markers: 964 FLOPs (tools/flopcount "cluster_register").
 */
sfit_status_t sfit_cluster_register(const sfit_cluster_t *cl, const sfit_vec3_t *meas,
                                    size_t count, sfit_pose_t *pose, sfit_cluster_fit_t *fit);

/**
 * @brief Start (or restart) a track: the next sfit_cluster_track() call
 * runs the full solve.
 * @param[out] tr  Track state.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  tr is NULL
 */
sfit_status_t sfit_cluster_track_reset(sfit_cluster_track_t *tr);

/**
 * @brief The pose of sfit_cluster_register(), started from the previous
 * frame's rotation: the frame-to-frame path of a firmware.
 *
 * With a previous rotation in @p tr, up to SFIT_CLUSTER_TRACK_STEPS Newton
 * steps on tr(R^T H) (H the centred cross-covariance) are taken from it,
 * each in quaternion form so that R is always a proper rotation. The
 * short path is accepted when the Hessian is positive definite, the
 * cluster is far from collinear (a bound that implies the collinearity
 * test of sfit_cluster_register()) and the quadratic-convergence bound
 * says that the remaining error is below one float epsilon; otherwise,
 * and at the start, the full solve of sfit_cluster_register() runs. The
 * pose equals the full solve's within float rounding
 * (docs/tracking.md: test, bound and measured differences).
 *
 * Statuses and outputs as sfit_cluster_register(); on SFIT_OK @p tr holds
 * this frame's rotation and, in tr->steps, the Newton steps taken (0: the
 * full solve ran). SFIT_E_TOO_FEW (fewer than 3 markers seen) is a
 * gap: @p tr forgets the rotation, and the next frame runs the full solve.
 * Any other failure leaves @p tr unchanged.
 * @param[in]     cl     Template.
 * @param[in,out] tr     Track state (sfit_cluster_track_reset() first).
 * @param[in]     meas   @p count measured positions, template order; NaN = occluded.
 * @param[in]     count  Must equal the template's marker count.
 * @param[out]    pose   Pose; written only on SFIT_OK.
 * @param[out]    fit    NULL, or residual and markers used; written only on SFIT_OK.
 * @retval SFIT_E_ARG  also for a corrupted @p tr (valid's byte not 0 or 1, or a
 *                     quaternion not finite or not of unit length)
 * @par Cost 4 markers, 1 degree between the frames (two Newton steps): 533
 * FLOPs for the pose (fit NULL, tools/flopcount "cluster_track_pose"); 679
 * FLOPs with the RMS residual ("cluster_track"); instructions (budgeted in
 * tools/flopcount/budget.txt) and stack: docs/cost.md.
 */
sfit_status_t sfit_cluster_track(const sfit_cluster_t *cl, sfit_cluster_track_t *tr,
                                 const sfit_vec3_t *meas, size_t count, sfit_pose_t *pose,
                                 sfit_cluster_fit_t *fit);

/**
 * @brief Map a point from the segment frame to the global frame: r x + t.
 * @param[in]  pose  Pose.
 * @param[in]  xs    Point in the segment frame.
 * @param[out] xg    Point in the global frame; may alias xs. Written only on SFIT_OK.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  a NULL pointer
 * @retval SFIT_E_NONFINITE  the result is not finite and pose or xs holds NaN / Inf
 * @retval SFIT_E_RANGE  the result overflows (finite inputs)
 * @par Cost 9 mul, 9 add.
 */
sfit_status_t sfit_cluster_to_global(const sfit_pose_t *pose, const sfit_vec3_t *xs,
                                     sfit_vec3_t *xg);

/**
 * @brief Map a point from the global frame to the segment frame: r^T (x - t).
 * @param[in]  pose  Pose.
 * @param[in]  xg    Point in the global frame.
 * @param[out] xs    Point in the segment frame; may alias xg. Written only on SFIT_OK.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  a NULL pointer
 * @retval SFIT_E_NONFINITE  the result is not finite and pose or xg holds NaN / Inf
 * @retval SFIT_E_RANGE  the result overflows (finite inputs)
 * @par Cost 18 FLOPs (3 sub, 9 mul, 6 add; tools/flopcount "pose_to_segment").
 */
sfit_status_t sfit_cluster_to_segment(const sfit_pose_t *pose, const sfit_vec3_t *xg,
                                      sfit_vec3_t *xs);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_CLUSTER_H */
