/* SPDX-License-Identifier: MIT */
/**
 * @file skel.h
 * @brief The skeleton found in a recording (`sfit skeleton FILE...`): host
 * side of issue 31. Segments (given by a map, or grouped from the data),
 * their poses (library: sfit_cluster.h), the joint cost of every pair of
 * segments (the library's pair module, sfit_pair.h), the tree (minimum spanning tree of the costs),
 * the skeleton's joint centres per frame, and the BVH / TRC / SVG / HTML
 * writers. Host only: it allocates; computations in double.
 *
 * Method, rules and thresholds: docs/skeleton.md.
 */
#ifndef SFIT_SKEL_H
#define SFIT_SKEL_H

#include <stddef.h>
#include <stdio.h>

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_pair.h"

#define SKEL_MAX_SEG 32   /* segments */
#define SKEL_MAX_MARK 256 /* markers of a recording */
#define SKEL_MAX_FILES 64 /* trials */
#define SKEL_NAME 64
#define SKEL_ERR 256

/* ---------------------------------------------------------- recording */

/** Several trials of one session, frames concatenated trial after trial. */
typedef struct skel_rec {
    int nfiles;
    const char *file[SKEL_MAX_FILES];
    long start[SKEL_MAX_FILES + 1]; /**< first frame of each trial; start[nfiles] = nframes */
    long nframes;
    int nmark;
    char (*label)[SKEL_NAME];       /**< nmark labels */
    float *xyz;                     /**< nframes * nmark * 3, NaN = not seen */
    float rate;                     /**< frames per second after --step (first file's) */
    long dropped;                   /**< samples not finite or beyond the library's range
                                         (2^SFIT_COORD_MAX_EXP), taken as unseen */
    char units[16];
} skel_rec_t;

/**
 * Load the C3D files; keep every step-th frame of each. Markers: `names`
 * (n of them) when given, else the labels of all files in order of first
 * appearance. A marker absent from a file is unseen (NaN) in that trial.
 * 0, or -1 with a message in why (SKEL_ERR).
 */
int skel_rec_load(skel_rec_t *r, const char *const *files, int nfiles, const char *const *names,
                  int n, long step, char *why);
void skel_rec_free(skel_rec_t *r);

static inline const float *skel_rec_at(const skel_rec_t *r, long f, int m)
{
    return r->xyz + ((size_t)f * (size_t)r->nmark + (size_t)m) * 3u;
}

/* ------------------------------------------------------------ segments */

typedef struct skel_seg {
    char name[SKEL_NAME];
    int nm;                            /**< markers of the segment */
    int mk[SKEL_MAX_MARK];             /**< indices into the recording */
    int npose;                         /**< markers used for its pose (<= SFIT_CLUSTER_MAX_MARKERS) */
    sfit_cluster_t tpl;                /**< template (segment frame) */
    int tpl_ok;
    long seen;                         /**< frames with a pose */
    double speed;                      /**< mean speed of its template origin (units/frame) */
    int vpar;                          /**< -1, or the segment whose joint centre is
                                            this segment's last pose point (a 2-marker group) */
    double vc[3];                      /**< that centre in segment vpar's frame */
    double vcost;                      /**< its sphere-fit cost (RMS radial residual) */
} skel_seg_t;

/** The session model's parts that sfit skeleton reads (SESSION_MODEL.md). */
typedef struct skel_map {
    int nseg;
    char seg[SKEL_MAX_SEG][SKEL_NAME];
    int nm[SKEL_MAX_SEG];
    char mk[SKEL_MAX_SEG][SFIT_CLUSTER_MAX_MARKERS * 4][SKEL_NAME];
    char root[SKEL_NAME];              /**< "" if not given */
    int njoint;
    char jname[SKEL_MAX_SEG][SKEL_NAME], jpar[SKEL_MAX_SEG][SKEL_NAME],
        jchi[SKEL_MAX_SEG][SKEL_NAME], jtype[SKEL_MAX_SEG][16];
    char jtrial[SKEL_MAX_SEG][SKEL_NAME]; /**< the joint's trial pattern ("" if none) */
} skel_map_t;

/** Parse a session model (segment / joint / root lines). 0, -1 open, -2 malformed (why). */
int skel_map_load(const char *path, skel_map_t *m, char *why);

/** One group of markers found from the data. */
typedef struct skel_groups {
    int n;                             /**< groups (including those of 1 or 2 markers) */
    int size[SKEL_MAX_MARK];
    int member[SKEL_MAX_MARK][SKEL_MAX_MARK];
    double spread[SKEL_MAX_MARK];      /**< largest pair spread inside the group */
    double threshold;                  /**< the merge threshold used */
    double noise;                      /**< the noise level it came from */
    double gap_lo, gap_hi;             /**< the spreads either side of the threshold */
} skel_groups_t;

/**
 * Group the markers by the spread of their pairwise distances (complete
 * linkage, threshold from the data; docs/skeleton.md). 0, or -1 (why).
 */
int skel_group(const skel_rec_t *r, skel_groups_t *g, char *why);

/**
 * Groups of 2 markers: each is attached to the posed segment about whose
 * point its markers turn best (the chapter's sphere route, sfit_joint),
 * and becomes a segment posed by its 2 markers and that centre. Call after
 * skel_poses; poses the new segments. Returns how many were attached.
 */
struct skel;
int skel_attach(struct skel *s, const skel_groups_t *g, char *why);

/** The `sfit skeleton FILE...` form (skel_cmd.c); wanted: one of its options or a C3D FILE. */
int skel_cmd_wanted(int argc, char **argv);
int skel_cmd(int argc, char **argv);

/* ----------------------------------------------------------- pair cost */

/** Joint type of a pair. */
typedef enum skel_jtype { SKEL_NONE = 0, SKEL_BALL = 1, SKEL_HINGE = 2 } skel_jtype_t;

/** Flags of a pair / joint. */
#define SKEL_F_NO_MOTION 1u    /**< the two segments did not move relative to each other */
#define SKEL_F_SMALL_RANGE 2u  /**< relative rotation spread below SKEL_SMALL_RANGE */
#define SKEL_F_FEW_FRAMES 4u   /**< fewer than SKEL_MIN_FRAMES common frames */
#define SKEL_F_BORDERLINE 8u   /**< the pair module calls ball / hinge ambiguous (its AMBIGUOUS
                                    flag, all trials together) */
#define SKEL_F_FORCED 16u      /**< type forced by the map */
#define SKEL_F_TYPE_TRIAL 32u  /**< type decided on the joint's functional trial (all trials
                                    together were ambiguous; docs/skeleton.md) */
#define SKEL_F_ONE_TRIAL 64u   /**< a hinge estimated on its functional trial alone (all
                                    trials together do not fix its axis) */
#define SKEL_F_UNTRUSTED 128u  /**< the fit is not what a joint can be (why: SKEL_U_*) */

/** Why a pair / joint is untrusted (docs/skeleton.md, "What a joint can be"). */
#define SKEL_U_MISFIT 1u  /**< residual above SKEL_TRUST_MISFIT times what the marker noise
                               explains (the pair module's misfit) */
#define SKEL_U_COST 2u    /**< cost above SKEL_TRUST_COST times the marker noise (sigma) */
#define SKEL_U_REACH 4u   /**< the centre lies further from a segment's nearest marker than
                               SKEL_TRUST_REACH times the larger segment's marker extent */
#define SKEL_U_MODULE 8u  /**< the pair module cannot say (too few frames, no noise figure) */
#define SKEL_TRUST_MISFIT 4.0
#define SKEL_TRUST_COST 6.0
#define SKEL_TRUST_REACH 2.0
#define SKEL_ATTACH_COST 3.0 /* a 2-marker group's sphere-route cost, times the rigid level */

/** Solution of one pair: the library's pair module (sfit_pair.h), the same
 * module and options `sfit calibrate` and `sfit joint` use. */
typedef struct skel_pair_res {
    skel_jtype_t type;
    double ca[3], cb[3];  /**< centre in a's and b's segment frames (lib.center_p / _c) */
    double axis_a[3];     /**< hinge axis in a's frame (unit; lib.axis_p) */
    double rms;           /**< joint cost: the module's model residual per frame (lib.rms) */
    double s[3];          /**< spread of the relative rotation (lib.eigenvalues, >= 0) */
    double cov_a[9];      /**< covariance of ca: lib.center_cov, for a joint of the tree
                               times the inflation of its slow residual (skel_joint_t) */
    double sigma;         /**< 1-sigma radius: sqrt(largest eigenvalue of cov_a) */
    double n;             /**< frames the module accepted */
    long rejected;        /**< frames with both poses that the module rejected */
    unsigned flags;       /**< SKEL_F_* */
    sfit_pair_result_t lib; /**< the module's result as it gave it (covariances, noise,
                               flags, reason) */
    int trial;            /**< trials used: -1 all, else that trial only (SKEL_F_ONE_TRIAL) */
    int type_trial;       /**< -1, or the trial whose auto decision gave the type */
    const char *type_rule; /**< "map", "all_trials", "functional_trial" (docs/skeleton.md) */
    double reach_a, reach_b; /**< distance from the centre to the nearest marker of a, of b
                               (their templates; a 2-marker segment's own markers) */
    unsigned why_untrusted; /**< SKEL_U_* bits: why the joint cannot be trusted (0: it can) */
} skel_pair_res_t;

/** Largest distance between two of a segment's own markers (template frame). */
double skel_seg_extent(const skel_seg_t *g);
/** Distance from c (segment frame) to the segment's nearest own marker (template). */
double skel_seg_reach(const skel_seg_t *g, const double c[3]);

/** Symmetric 3x3 eigen-decomposition (double, Jacobi): ascending w, vectors in v's columns. */
int skel_eig3(const double a[9], double w[3], double v[9]);

struct skel;
/**
 * The pair (a, b) by the library's pair module (sfit_pair_init / _add /
 * _solve, default options as `sfit calibrate`) on the frames of trial
 * `trial` (-1: all) where both have a pose; mode SKEL_NONE = auto. 0, or
 * -1 (too few frames, or the module failed).
 */
int skel_pair_run(const struct skel *s, int a, int b, skel_jtype_t mode, int trial,
                  skel_pair_res_t *res);
/**
 * A joint of the tree (a parent, b child): its type (force from the map, else
 * the rule of docs/skeleton.md: all trials together, or the functional trial
 * when they are ambiguous; `pattern` the map's trial pattern or NULL) and its
 * estimate over all trials with that type. 0, or -1.
 */
int skel_pair_joint(const struct skel *s, int a, int b, skel_jtype_t force, const char *pattern,
                    skel_pair_res_t *res);

/* ------------------------------------------------------------ skeleton */

typedef struct skel_joint {
    char name[SKEL_NAME];
    int parent, child;      /**< segment indices */
    skel_pair_res_t pr;     /**< in (parent, child) order */
    double lag1;            /**< lag-1 autocorrelation of the residual */
    double infl;            /**< variance inflation (1 + rho) / (1 - rho) applied to cov */
    double bvh_med, bvh_p95; /**< distance from the BVH's forward kinematics of the joint to
                                  its centre as the parent carries it (median, 95th
                                  percentile over the frames where the parent has a pose;
                                  units of the recording); NaN without such frames */
    long bvh_frames;        /**< those frames */
} skel_joint_t;

typedef struct skel {
    skel_rec_t *rec;
    int nseg;
    skel_seg_t seg[SKEL_MAX_SEG];
    int root;
    int root_named;
    /* pair table (upper triangle a < b) */
    skel_pair_res_t pair[SKEL_MAX_SEG][SKEL_MAX_SEG];
    int pair_ok[SKEL_MAX_SEG][SKEL_MAX_SEG];
    /* tree */
    int parent_joint[SKEL_MAX_SEG]; /**< joint entering each segment (-1: root) */
    int njoint;
    skel_joint_t joint[SKEL_MAX_SEG];
    int order[SKEL_MAX_SEG];        /**< segments, parents before children */
    /* per frame */
    unsigned char *pose_ok;         /**< nframes * nseg */
    float *fit_rms;                 /**< nframes * nseg: registration residual (RMS) */
    unsigned char *fit_used;        /**< nframes * nseg: markers used */
    sfit_pose_t *fpose;             /**< nframes * nseg: the registration's pose as it
                                         came (what sfit_pair_add_markers would add) */
    double *pose;                   /**< nframes * nseg * 12: R (9) then t (3) */
    double *rel;                    /**< nframes * nseg * 9: rotation written in the BVH
                                         (root: R_root; others: R_parent^T R_child) */
    double *root_t;                 /**< nframes * 3 */
    double *jc;                     /**< nframes * njoint * 3: the skeleton's joint centres (lab) */
    double end_site[SKEL_MAX_SEG][3]; /**< leaf end site in the segment frame */
    double *ends;                   /**< nframes * nseg * 3: end site in the lab (leaves;
                                         NaN for the others) */
    int leaf[SKEL_MAX_SEG];         /**< 1: a segment of the tree with no child */
} skel_t;

/** Poses of every segment in every frame (templates over all frames). 0, -1 (why). */
int skel_poses(skel_t *s, char *why);
/** Pair costs, tree, root, joints; force types from the map. 0, -1 (why). */
int skel_tree(skel_t *s, const skel_map_t *map, const char *root, char *why);
/**
 * The skeleton found from the data alone (no map): groups (skel_group), the
 * groups of 3 or more markers as segments, their poses, the 2-marker groups
 * attached (skel_attach), the tree (skel_tree; `root` a segment name or
 * NULL), the segments named seg1 (root), seg2, ... down the tree. s->rec set,
 * s otherwise empty. Segments in the tree, or -1 (why).
 */
int skel_from_data(skel_t *s, skel_groups_t *grp, const char *root, char *why);
/** Per-frame rotations and joint centres (the forward kinematics of the BVH). 0, -1. */
int skel_motion(skel_t *s, char *why);
void skel_free(skel_t *s);

/* ------------------------------------------------------------- writers */

int skel_write_bvh(const skel_t *s, const char *path);
int skel_write_trc(const skel_t *s, const char *path);
/** Per frame, each joint's centre carried by its parent (and a hinge's axis), CSV. */
int skel_write_centres(const skel_t *s, const char *path);
int skel_write_svg(const skel_t *s, const char *path, long frame);
int skel_write_html(const skel_t *s, const char *path);

/** Rotation (row-major) -> ZXY Euler angles in degrees: R = Rz(z) Rx(x) Ry(y). */
void skel_euler_zxy(const double r[9], double deg[3]);

#endif /* SFIT_SKEL_H */
