/* SPDX-License-Identifier: MIT */
/**
 * @file joint_run.h
 * @brief The functional joint centre over loaded trajectories, shared by
 * `sfit joint` and `sfit skeleton` (library: sfit_cluster.h, sfit_joint.h).
 *
 * Parent frame: the template frame of the parent cluster, built by
 * sfit_cluster_from_frames() over the frames used: its axes are the lab
 * axes at the reference frame (the first frame of the range where every
 * parent marker is seen), its origin the centroid of the parent markers'
 * template (their positions averaged over the frames, in that frame).
 */
#ifndef SFIT_JOINT_RUN_H
#define SFIT_JOINT_RUN_H

#include <stdio.h>

#include "frames.h"
#include "sfit/sfit_joint.h"
#include "sfit/sfit_pair.h"

/** --method: the estimator (the pair module's for every one but mgdk). */
enum joint_run_method {
    JOINT_RUN_DEFAULT = 0, /**< SCoRE / SARA with the bias removed (sfit_pair, default) */
    JOINT_RUN_SCORE = 1,   /**< plain SCoRE (ball; hinge with --mode planar) */
    JOINT_RUN_SARA = 2,    /**< plain SARA (hinge) */
    JOINT_RUN_MGDK = 3     /**< the multi-marker algebraic fit (sfit_joint) */
};

/** Options of one joint. */
typedef struct joint_run_opts {
    long first, last;   /**< frames used, inclusive, 0-based (clamped to the file) */
    sfit_mode_t mode;   /**< auto, sphere or planar */
    int noise;          /**< 0 none (MGDK), 1 given (noise_var), 2 auto (estimated) */
    float noise_var;    /**< noise == 1: sigma^2 per coordinate of every measured marker
                             (unit^2), SFIT_JOINT_NOISE_MARKER */
    int no_repair_swaps; /**< 1: label swaps reported only (swaps.h) */
    int method;         /**< enum joint_run_method */
} joint_run_opts_t;

/** Everything a joint run produces. */
typedef struct joint_run_out {
    sfit_joint_t j;                     /**< state: template and accumulators */
    sfit_joint_result_t res;            /**< centre, axis, ... in the parent frame */
    float radii[SFIT_JOINT_MAX_CHILD];  /**< per child marker */
    long used, rejected;                /**< frames of the range */
    long ref_frame;                     /**< reference frame of the template (-1 none) */
    unsigned long template_frames;      /**< frames averaged into the template */
    unsigned long child_n[SFIT_JOINT_MAX_CHILD]; /**< samples per child marker */
    int has_noise, noise_estimated;
    float noise_var;
    unsigned char *ok;                  /**< per frame of the file: 1 = accepted */
    int pair_used;                      /**< 1: res.fit.center / axis / mode are the pair's */
    const char *method_name;            /**< "default", "score", "sara", "mgdk" */
    const char *note;                   /**< NULL, or why the method differs from the asked */
    sfit_pair_result_t pair;            /**< pair_used: centre, covariances, flags */
    long pair_rejected;                 /**< frames the pair rejected (child not registrable) */
    int mgdk_cov_ok;                    /**< !pair_used: 1 when mgdk_cov holds the centre's
                                             covariance (sfit_joint_center_cov) */
    sfit_mat3_t mgdk_cov;               /**< !pair_used: centre covariance, parent frame */
    float mgdk_var;                     /**< !pair_used: the marker variance it used */
    int mgdk_var_given;                 /**< 1: --noise-var V; 0: the parent cluster's
                                             registration residuals */
    sfit_status_t st;                   /**< SFIT_OK or the failure */
    const char *stage;                  /**< where it failed: "template", "frames", "solve" */
} joint_run_out_t;

/**
 * Run the joint: markers 0..np-1 of `fr` are the parent cluster, markers
 * np..np+nc-1 the child markers. Returns out->st (SFIT_OK or the status of
 * the stage that failed). Release out with joint_run_free.
 */
sfit_status_t joint_run(const frames_data_t *fr, int np, int nc, const joint_run_opts_t *o,
                            joint_run_out_t *out);

/** Release what joint_run allocated. */
void joint_run_free(joint_run_out_t *out);

/**
 * The joint centre in the lab frame at frame f (parent registered there).
 * SFIT_OK or the registration's status.
 */
sfit_status_t joint_run_lab(const frames_data_t *fr, int np, const joint_run_out_t *out, long f,
                            sfit_vec3_t *center, sfit_vec3_t *axis);

/**
 * The multi-marker fit's (mgdk) centre covariance, as `sfit joint --method
 * mgdk` and Python's joint_center(method="mgdk") report it:
 * sfit_joint_center_cov() over the nf frames of parent (nf x parent count)
 * and child (nf x n_child) that were fed to j, with var_given (>= 0), or
 * (var_given < 0) the marker variance of the parent cluster's registration
 * residuals (sum rms^2 used / sum (3 used - 6) over the frames it
 * registers). *var receives the variance used. MGDK's own bias at a small
 * range of motion is not in the covariance. Returns the status.
 */
sfit_status_t joint_run_mgdk_cov(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                 const sfit_vec3_t *parent, const sfit_vec3_t *child, size_t nf,
                                 float var_given, sfit_mat3_t *cov, float *var);

/** Defaults: every frame, auto mode, no noise model. */
void joint_run_opts_default(joint_run_opts_t *o);

#endif /* SFIT_JOINT_RUN_H */
