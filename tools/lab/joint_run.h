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
#ifndef SFIT_CLI_JOINT_H
#define SFIT_CLI_JOINT_H

#include <stdio.h>

#include "cli.h"
#include "frames.h"
#include "sfit/sfit_joint.h"
#include "sfit/sfit_pair.h"

/** --method: the estimator (the pair module's for every one but mgdk). */
enum cli_joint_method {
    CLI_JOINT_DEFAULT = 0, /**< SCoRE / SARA with the bias removed (sfit_pair, default) */
    CLI_JOINT_SCORE = 1,   /**< plain SCoRE (ball; hinge with --mode planar) */
    CLI_JOINT_SARA = 2,    /**< plain SARA (hinge) */
    CLI_JOINT_MGDK = 3     /**< the multi-marker algebraic fit (sfit_joint) */
};

/** Options of one joint. */
typedef struct cli_joint_opts {
    long first, last;   /**< frames used, inclusive, 0-based (clamped to the file) */
    sfit_mode_t mode;   /**< auto, sphere or planar */
    int noise;          /**< 0 none (MGDK), 1 given (noise_var), 2 auto (estimated) */
    float noise_var;    /**< noise == 1: sigma^2 per coordinate of every measured marker
                             (unit^2), SFIT_JOINT_NOISE_MARKER */
    int no_repair_swaps; /**< 1: label swaps reported only (swaps.h) */
    int method;         /**< enum cli_joint_method */
} cli_joint_opts_t;

/** Everything a joint run produces. */
typedef struct cli_joint_out {
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
} cli_joint_out_t;

/**
 * Run the joint: markers 0..np-1 of `fr` are the parent cluster, markers
 * np..np+nc-1 the child markers. Returns out->st (SFIT_OK or the status of
 * the stage that failed). Release out with cli_joint_free.
 */
sfit_status_t cli_joint_run(const cli_frames_t *fr, int np, int nc, const cli_joint_opts_t *o,
                            cli_joint_out_t *out);

/** Release what cli_joint_run allocated. */
void cli_joint_free(cli_joint_out_t *out);

/**
 * The joint centre in the lab frame at frame f (parent registered there).
 * SFIT_OK or the registration's status.
 */
sfit_status_t cli_joint_lab(const cli_frames_t *fr, int np, const cli_joint_out_t *out, long f,
                            sfit_vec3_t *center, sfit_vec3_t *axis);

/** --frames F:L into a cli_joint_opts_t (a cli_opt_fn_t). */
const char *cli_joint_frames_opt(void *dst, const char *v);

/** --method default|score|sara|mgdk into a cli_joint_opts_t (a cli_opt_fn_t). */
const char *cli_joint_method_opt(void *dst, const char *v);

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
sfit_status_t cli_joint_mgdk_cov(const sfit_joint_t *j, const sfit_joint_result_t *res,
                                 const sfit_vec3_t *parent, const sfit_vec3_t *child, size_t nf,
                                 float var_given, sfit_mat3_t *cov, float *var);

/** The JSON members after "center"...: the pair's center_cov, axis_cov, noise, reason;
 *  for the multi-marker fit (mgdk) its center_cov, the marker noise used, reason. */
void cli_joint_print_pair_json(const cli_joint_out_t *out);

/** The result's flags as a JSON array (the pair's, or the multi-marker fit's). */
void cli_joint_print_flags_json(const cli_joint_out_t *out);

/** Text lines: 95 % semi-axes (mm), noise figure and source, flags (pair or mgdk). */
void cli_joint_print_pair_text(const cli_joint_out_t *out, const char *units, const char *indent);

/** --noise-var V|auto into a cli_joint_opts_t (a cli_opt_fn_t). */
const char *cli_joint_noise_opt(void *dst, const char *v);

/**
 * The cli_opt_t entries of the options shared by joint and skeleton
 * (--frames F:L, --noise-var V|auto, --mode auto|sphere|planar) for the
 * cli_joint_opts_t *J; a missing value is "NAME needs a value".
 */
#define CLI_JOINT_OPTS(J)                                                                   \
    {.name = "--frames", .kind = CLI_OPT_FN, .dst = (J), .fn = cli_joint_frames_opt,       \
     .needs = 1},                                                                          \
    {.name = "--noise-var", .kind = CLI_OPT_FN, .dst = (J), .fn = cli_joint_noise_opt,     \
     .needs = 1},                                                                          \
    {.name = "--mode", .kind = CLI_OPT_MODE, .dst = &(J)->mode, .needs = 1,                \
     .err = "--mode is auto, sphere or planar"},                                           \
    {.name = "--no-repair-swaps", .kind = CLI_OPT_FLAG, .dst = &(J)->no_repair_swaps},    \
    {.name = "--method", .kind = CLI_OPT_FN, .dst = (J), .fn = cli_joint_method_opt,       \
     .needs = 1}

/** Defaults: every frame, auto mode, no noise model. */
void cli_joint_opts_default(cli_joint_opts_t *o);

/** The usage lines of the shared joint options. */
#define CLI_JOINT_USAGE                                                                     \
    "  --frames F:L     use frames F to L (0-based, both included; default: all)\n"        \
    "  --noise-var V    the multi-marker fit (mgdk) made unbiased: V = noise variance\n" \
    "                   of each measured marker coordinate (unit^2), propagated\n"       \
    "                   through the parent pose\n"                                        \
    "  --noise-var auto the child markers' noise in the parent frame, estimated per\n"   \
    "                   marker (self-calibrated UGDK) and pooled\n"                       \
    "  --mode M         auto (default): ball joint, or hinge when the markers' arcs are\n" \
    "                   near-planar; sphere / planar force one\n"                       \
    "  --no-repair-swaps report label swaps within a cluster but leave the frames as\n"  \
    "                   they are (default: exchange the labels back; reject frames\n"     \
    "                   whose distances fit no labelling)\n"                            \
    "  --method M       default: SCoRE / SARA from the two clusters' poses with the\n"    \
    "                   bias removed (marker noise from the registration residuals;\n"  \
    "                   needs 3 child markers, else mgdk); score, sara: as published;\n"\
    "                   mgdk: one sphere per child marker in the parent's frame,\n"    \
    "                   sharing their centre (the multi-marker sphere fit)\n"

#endif /* SFIT_CLI_JOINT_H */
