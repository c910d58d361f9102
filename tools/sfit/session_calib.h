/* SPDX-License-Identifier: MIT */
/**
 * @file session_calib.h
 * @brief The computing part of `sfit calibrate` / `sfit apply` on loaded
 * trajectories (cli_frames_t), shared by the CLI and the Python binding
 * (docs/session.md). Host only.
 */
#ifndef SFIT_TOOLS_SESSION_CALIB_H
#define SFIT_TOOLS_SESSION_CALIB_H

#include "cli_frames.h"
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
int session_calibrate_frames(cli_frames_t *fr, const session_model_t *m, int k,
                             const char *trial, session_joint_t *j, char *err);

/**
 * Place joint j in every frame of fr (the parent's markers in j's order;
 * swaps repaired in place): pts + f * stride * 3 gets the centre (and for a
 * hinge the two axis points, d either side) where the parent registers,
 * and is left as it is elsewhere; rot[f] (may be NULL) the parent's
 * rotation. Returns the frames placed, or -1 (a count or template that
 * does not fit j).
 */
long session_place_frames(const session_joint_t *j, cli_frames_t *fr, float d, float *pts,
                          int stride, sfit_mat3_t *rot);

#endif /* SFIT_TOOLS_SESSION_CALIB_H */
