/* SPDX-License-Identifier: MIT */
/**
 * @file session.h
 * @brief A calibrated session (`sfit calibrate` writes it, `sfit apply`
 * reads it): per joint the parent segment's marker template and the joint
 * centre (and hinge axis) in that template's frame, with its covariance,
 * flags and verdict (docs/session.md). Host only.
 */
#ifndef SFIT_TOOLS_SESSION_H
#define SFIT_TOOLS_SESSION_H

#include <stdint.h>
#include <stdio.h>

#include "json_out.h"
#include "session_model.h"

#define SESSION_VERDICT_MAX 640
#define SESSION_PATH_MAX 512

/** One calibrated joint. */
#define SESSION_CONVENTION_MAX 160 /* the centre's convention, in words, + 1 */

typedef struct session_joint {
    char name[SM_NAME_MAX];
    char parent[SM_NAME_MAX], child[SM_NAME_MAX]; /**< segment names */
    int hinge;                        /**< 1: hinge (centre on the axis), 0: ball */
    int npoints;                      /**< points written: 1 ball, 3 hinge */
    char points[3][SM_NAME_MAX];
    char trial[SESSION_PATH_MAX];     /**< the functional trial (as given) */
    int nmarkers;                     /**< parent markers (3..8) */
    char markers[SM_MARKERS_MAX][SM_NAME_MAX];
    float tpl[SM_MARKERS_MAX][3];     /**< parent template (parent frame) */
    float center[3], axis[3];         /**< parent frame; axis unit (hinge) */
    char convention[SESSION_CONVENTION_MAX]; /**< where the centre is put, in words */
    long ref_frame;                   /**< the template frame's axes are the lab's at this
                                           frame of the trial (-1: not recorded) */
    double cov[3][3];                 /**< centre covariance (parent frame, units^2) */
    double semi95[3];                 /**< 95 % ellipsoid semi-axes, descending (units) */
    double range_deg[3];              /**< rotation range of the child about lab x, y, z
                                           at the reference frame (degrees) */
    double flex_deg;                  /**< hinge: rotation range about its axis (degrees) */
    double marker_sigma;              /**< marker noise used for cov (units) */
    double misfit;                    /**< the pair's misfit: the joint model's residual /
                                           the marker noise's expectation (0: not the pair's) */
    double model_rms;                 /**< the pair's joint-model residual per frame (units) */
    double cov_jack[3][3];            /**< block jackknife covariance of the centre (parent
                                           frame; zero when not computed) */
    double jack_ratio;                /**< tr(cov^-1 cov_jack) / p (0: not computed) */
    double model_scale;               /**< cov_model = model_scale cov (1: the model holds) */
    double cov_model[3][3];           /**< centre covariance with the model error */
    double semi95_model[3];           /**< its 95 % semi-axes (units) */
    double skin_rms;                  /**< ball: the clusters' motion on the skin with the
                                           joint angle, at the joint (units; 0: not seen) */
    double semi95_skin[3];            /**< ball: 95 % semi-axes of the centre's uncertainty
                                           from that motion alone (in cov; units) */
    double cone_deg, cone_model_deg;  /**< hinge: the axis' 95 % cone half-angle and the
                                           part from an out-of-axis rotation in step with
                                           the flexion (degrees) */
    double wobble_deg;                /**< hinge: the out-of-axis rotation seen (rms, deg) */
    uint32_t flags;                   /**< sfit flags of the fit */
    long frames_used, frames_total;
    char verdict[SESSION_VERDICT_MAX];
} session_joint_t;

typedef struct session {
    char units[16];
    int nseg;
    sm_segment_t seg[SM_SEGMENTS_MAX];
    int root;
    int njoint;
    session_joint_t joint[SM_JOINTS_MAX];
} session_t;

#define SESSION_DESC_MAX 96 /* a written point's C3D description + 1 */

/** The C3D description of joint j's point q (0: the centre, 1 and 2: a
 * hinge's axis points): the joint and where its centre is put. */
void session_point_desc(const session_joint_t *j, int q, char *d, size_t cap);

/**
 * Write the session as JSON (one object). A joint's "flags" are the names
 * `flag_names` gives its flag bits (names_flags(NAMES_SESSION, ...) of
 * tools/lab/names.h: the format holds no name table of its own).
 */
void session_write_json(FILE *f, const session_t *s, const json_out_flag_t *flag_names,
                        size_t nflag_names);

/**
 * Read a session JSON file written by session_write_json. 0, or -1 with a
 * message in err (SM_ERR_MAX bytes). Checks every count, name and number.
 */
int session_read(const char *path, session_t *s, char *err);

/** The same from memory. */
int session_parse(const char *text, size_t len, session_t *s, char *err);

#endif /* SFIT_TOOLS_SESSION_H */
