/* SPDX-License-Identifier: MIT */
/**
 * @file swaps.h
 * @brief Label swaps within a rigid marker cluster, found from its
 * inter-marker distances, repaired or rejected (host tools: `sfit joint`,
 * `sfit skeleton`, the Python binding's joint_center).
 *
 * The markers of one segment keep their distances. A frame whose labels
 * were exchanged (the point labelled A is marker B and the point labelled
 * B is marker A) shows the distance pattern of the cluster with A and B
 * exchanged. Per frame, every relabelling that moves two or three labels
 * (the exchanges of two labels and the rotations of three) is compared
 * with the labels as given, against a reference of the cluster's
 * distances:
 *
 *  1. Anchor: the reference labelling is that of the start of the range:
 *     the per-pair median distance over its first SWAPS_ANCHOR frames
 *     (fewer than half of them may be swapped).
 *  2. Provisional pass: every frame relabelled by the best fit against the
 *     anchor; the reference R = the per-pair median over all frames so
 *     relabelled, the distance noise s = 1.4826 x the median absolute
 *     deviation of the distances from R (pooled over pairs and frames; at
 *     least SWAPS_SCALE_FLOOR x the median reference distance).
 *  3. Decision per frame, over the pairs of markers seen (>= 3 markers):
 *     cost(L) = sum (d_uv - R[L(u), L(v)])^2 for a labelling L. A
 *     relabelling is decidable in that frame when its reference pattern
 *     differs from the labels as given by at least 2 z s (z =
 *     SWAPS_Z), Euclidean over the pairs seen: two Gaussian
 *     hypotheses that far apart are told apart with an error probability
 *     Phi(-z) per frame. Undecidable relabellings are never applied; those
 *     of the whole cluster are listed (a near-symmetric cluster).
 *     The labelling of least cost among the labels as given and the
 *     decidable relabellings wins; the frame is
 *     - as given, or swapped (repaired: the points take their true labels);
 *     - rejected when no labelling fits: the winner's RMS deviation over
 *       the pairs exceeds z s and its Euclidean deviation exceeds half the
 *       least pattern change of a decidable relabelling (an error on the
 *       scale of a label problem: a label from another segment, a ghost;
 *       a marker jumping a few millimetres in one frame is left to the
 *       estimator); or when another decidable relabelling is within
 *       2 z s of the winner (which one is undecidable).
 *     Frames with fewer than 3 markers seen are not checked.
 *
 * Cost: O(F P C) for F frames, P <= 28 pairs and C <= 141 candidates
 * (M = 8 markers), plus three sorts of F P numbers. Deterministic.
 */
#ifndef SFIT_SWAPS_H
#define SFIT_SWAPS_H

#include <stddef.h>

#include "sfit/sfit_types.h"

#define SWAPS_MAX_MARKERS 8 /**< markers per cluster */
#define SWAPS_MAX_PAIRS 28  /**< MAX_MARKERS (MAX_MARKERS - 1) / 2 */
/** Candidates: the labels as given, C(8,2) exchanges, 2 C(8,3) rotations. */
#define SWAPS_MAX_CAND (1 + 28 + 112)
#define SWAPS_Z 10.0            /**< decision distance, noise standard deviations */
#define SWAPS_ANCHOR 50L        /**< frames of the anchor (start of the range) */
#define SWAPS_MIN_FRAMES 10L    /**< frames needed to check a cluster at all */
#define SWAPS_SCALE_FLOOR 1e-5  /**< s floor, relative to the median distance */

/** Per-frame status (swaps_t.status); > 0: candidate index (a swap). */
enum {
    SWAPS_UNCHECKED = -1, /**< outside the range, or fewer than 3 markers seen */
    SWAPS_AS_GIVEN = 0,   /**< the labels as given fit */
    SWAPS_NO_FIT = -2,    /**< rejected: no labelling fits */
    SWAPS_AMBIGUOUS = -3  /**< rejected: two relabellings fit alike */
};

/** Why a cluster was not checked (swaps_t.why). */
enum {
    SWAPS_WHY_CHECKED = 0,
    SWAPS_WHY_FEW_MARKERS = 1, /**< fewer than 3 markers */
    SWAPS_WHY_FEW_FRAMES = 2,  /**< fewer than SWAPS_MIN_FRAMES frames with 3 seen */
    SWAPS_WHY_DEGENERATE = 3   /**< no distance noise: the markers on one point */
};

/** The reason of swaps_t.why, in words. */
const char *swaps_why(int why);

/** One candidate labelling: the point given label u is marker lab[u]. */
typedef struct swaps_cand {
    unsigned char lab[SWAPS_MAX_MARKERS];
    int moved;        /**< labels moved: 0 (as given), 2 or 3 */
    double pattern;   /**< |R(L) - R| over all pairs (units) */
    int decidable;    /**< pattern >= 2 z s */
    long count;       /**< frames found with this labelling */
} swaps_cand_t;

/** What the detector found in one cluster. */
typedef struct swaps {
    int m;              /**< markers */
    int checked;        /**< 0: not checked (why says why) */
    int why;            /**< SWAPS_WHY_* */
    int repaired;       /**< 1: the frames were changed (repair on) */
    long first, last;   /**< range looked at */
    long frames_checked;
    long frames_swapped;
    long frames_no_fit, frames_ambiguous;
    double scale;       /**< s: distance noise (units) */
    double decide;      /**< 2 z s */
    double misfit;      /**< half the least pattern change of a decidable relabelling */
    double ref[SWAPS_MAX_MARKERS][SWAPS_MAX_MARKERS]; /**< reference distances */
    int ncand;
    swaps_cand_t cand[SWAPS_MAX_CAND]; /**< [0] = as given */
    signed short *status; /**< per frame of the file (nframes), see the enum */
    long nframes;
} swaps_t;

/**
 * Check one cluster: markers off..off+m-1 of frame f are at
 * xyz[f * stride + off + k] (NaN = not seen), frames first..last. With
 * repair, swapped frames get their true labels and rejected frames the
 * cluster's markers NaN (xyz changed in place); without, xyz is untouched.
 * Returns 0, -1 out of memory or bad arguments (out->checked 0).
 * Release out with swaps_free.
 */
int swaps_run(sfit_vec3_t *xyz, long nframes, int stride, int off, int m, long first,
                  long last, int repair, swaps_t *out);

/** Release what swaps_run allocated. */
void swaps_free(swaps_t *s);

/**
 * The maximal runs of consecutive frames with status st (a candidate
 * index > 0, SWAPS_NO_FIT or SWAPS_AMBIGUOUS): writes up to max
 * [first, last] pairs into runs (may be NULL with max 0); returns how many
 * runs there are in all.
 */
long swaps_runs(const swaps_t *s, int st, long (*runs)[2], long max);

/* ---- Both clusters of a joint (swaps_joint.c) ---- */

struct frames_data;

/** The parent and the child cluster of one joint. */
typedef struct swaps_joint {
    swaps_t parent, child;
    int repair;
} swaps_joint_t;

/**
 * Check the parent (markers 0..np-1 of fr) and the child (np..np+nc-1)
 * over frames first..last (last < 0: to the end), repairing fr in place
 * unless repair is 0. Returns 0, or -1 (out of memory: nothing checked).
 */
int swaps_joint_run(struct frames_data *fr, int np, int nc, long first, long last, int repair,
                        swaps_joint_t *out);

/** Release a swaps_joint_t. */
void swaps_joint_free(swaps_joint_t *s);

#endif /* SFIT_SWAPS_H */
