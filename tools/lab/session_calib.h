/* SPDX-License-Identifier: MIT */
/**
 * @file session_calib.h
 * @brief The computing part of `sfit calibrate` / `sfit apply` on loaded
 * trajectories (frames_data_t), shared by the CLI and the Python binding
 * (docs/session.md). Host only.
 */
#ifndef SFIT_TOOLS_SESSION_CALIB_H
#define SFIT_TOOLS_SESSION_CALIB_H

#include <stdio.h>

#include "frames.h"
#include "session.h"
#include "session_model.h"
#include "sfit/sfit_types.h"

/**
 * Calibrate joint k of model m: fr holds the parent's markers, then the
 * child's, in the model's order (label swaps are repaired in place). j gets
 * the joint in the parent template frame with its covariance, 95 %
 * semi-axes, rotation range, flags and verdict; trial is recorded in it.
 * 0, or -1 with the reason in err (SM_ERR_MAX bytes).
 */
int session_calibrate_frames(frames_data_t *fr, const session_model_t *m, int k,
                             const char *trial, session_joint_t *j, char *err);

/** What the placement of a joint centre in a trial adds to its uncertainty:
 * the parent's registration error in that trial, at the lever arm from the
 * seen markers' centroid to the centre (docs/session.md). */
typedef struct session_place_cov {
    long frames;          /**< frames placed */
    double var;           /**< marker variance from the registration residuals of the
                               frames placed: sum |r|^2 / sum (3 M_f - 6) (units^2) */
    double var_sys;       /**< its systematic part, the same in every frame (a deformation
                               of the cluster against the template): from each marker's
                               residual averaged over the frames, whose sum of squares / dof
                               estimates var_sys + var_rand / frames */
    double var_rand;      /**< the frame-to-frame part (var - var_sys) */
    double var_mean;      /**< the mean placement's: var_sys + var_rand / frames (with
                               var_sys clipped at 0: at least var / frames) */
    double cov_frame[3][3]; /**< covariance of the centre placed in one frame, averaged over
                               the frames placed (parent template frame, units^2) */
    double cov_mean[3][3];  /**< covariance of the centre averaged over the frames placed,
                               var_mean gain: the systematic part in full, the frame-to-frame
                               part / frames */
    double gain[3][3];    /**< cov_frame / var: the registration's error at the centre per
                               unit marker variance (lever arm and marker spread), averaged */
    double mean_res[SM_MARKERS_MAX][3]; /**< each parent marker's residual averaged over the
                               frames placed (template frame; 0 where never seen) */
    double total[3][3];   /**< per frame with the calibration: j->cov_model + cov_frame */
    double semi_frame[3], semi_mean[3], semi_total[3]; /**< 95 % semi-axes (chi2 3 dof) */
} session_place_cov_t;

/**
 * Place joint j in every frame of fr (the parent's markers in j's order;
 * swaps repaired in place): pts + f * stride * 3 gets the centre (and for a
 * hinge the two axis points, d either side) where the parent registers,
 * and is left as it is elsewhere; rot[f] (may be NULL) the parent's
 * rotation; pc (may be NULL) the placement's covariance (all zero when no
 * frame is placed). Returns the frames placed, or -1 (a count or template
 * that does not fit j).
 */
long session_place_frames(const session_joint_t *j, frames_data_t *fr, float d, float *pts,
                          int stride, sfit_mat3_t *rot, session_place_cov_t *pc);

/** pc as a JSON object (the "placement" of `sfit apply --json`; nmarkers
 * mean residuals). */
void session_place_json(FILE *f, const session_place_cov_t *pc, int nmarkers);

/** Eigenvalues of a symmetric 3x3 (descending) and the 95 % semi-axes
 * sqrt(q ev) (q: chi2 quantile; negative eigenvalues give 0). */
void session_semi_axes(double cov[3][3], double q, double semi[3]);

#endif /* SFIT_TOOLS_SESSION_CALIB_H */
