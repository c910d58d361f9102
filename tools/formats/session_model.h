/* SPDX-License-Identifier: MIT */
/**
 * @file session_model.h
 * @brief The session model of `sfit calibrate` / `sfit apply` (and
 * `sfit skeleton`): segments, joints and the functional trial of each joint,
 * read from a text file (docs/session.md).
 *
 *     segment NAME MARKER,MARKER,MARKER[,...]
 *     joint NAME PARENT CHILD auto|ball|hinge POINTS [TRIAL_PATTERN]
 *     root SEGMENT
 *     landmarks JOINT MARKER,MARKER
 *
 * `landmarks` names two markers of the joint's parent segment that lie on
 * either side of the joint (a knee's epicondyles, an ankle's malleoli): a
 * hinge's centre is then the point of its functional axis nearest their
 * midpoint (the field's convention), not the axis point the data leave.
 * Blank lines and `#` comments are ignored. Host only.
 */
#ifndef SFIT_TOOLS_SESSION_MODEL_H
#define SFIT_TOOLS_SESSION_MODEL_H

#include <stddef.h>

#define SM_NAME_MAX 64      /* longest segment, joint, marker or point name + 1 */
#define SM_PATTERN_MAX 256  /* longest trial pattern + 1 */
#define SM_MARKERS_MAX 8    /* markers of one segment (SFIT_CLUSTER_MAX_MARKERS) */
#define SM_SEGMENTS_MAX 32
#define SM_JOINTS_MAX 32
#define SM_ERR_MAX 256

enum sm_type { SM_AUTO = 0, SM_BALL = 1, SM_HINGE = 2 };

typedef struct sm_segment {
    char name[SM_NAME_MAX];
    int nmarkers;                            /**< 3..SM_MARKERS_MAX */
    char markers[SM_MARKERS_MAX][SM_NAME_MAX];
} sm_segment_t;

typedef struct sm_joint {
    char name[SM_NAME_MAX];
    int parent, child;                       /**< segment indices (different) */
    int type;                                /**< enum sm_type */
    int npoints;                             /**< ball / auto: 1; hinge: 3 */
    char points[3][SM_NAME_MAX];             /**< auto: [1], [2] = NAME_AX1, NAME_AX2 */
    char pattern[SM_PATTERN_MAX];            /**< "" when not given */
    int nlandmarks;                          /**< 0, or 2: landmarks given */
    char landmarks[2][SM_NAME_MAX];          /**< markers of the parent segment */
    int line;                                /**< line of the model file */
} sm_joint_t;

typedef struct session_model {
    int nseg, njoint;
    sm_segment_t seg[SM_SEGMENTS_MAX];
    sm_joint_t joint[SM_JOINTS_MAX];
    int root;                                /**< segment index */
} session_model_t;

/**
 * Parse a model held in memory (len bytes, need not end in NUL). 0, or -1
 * with "line N: why" in err (SM_ERR_MAX bytes). Checks: known keywords,
 * names unique and not too long, 3..8 distinct markers per segment, joints
 * between two different declared segments, a child segment has one parent
 * joint, no cycle, the points' count for the type, one root.
 */
int session_model_parse(const char *text, size_t len, session_model_t *m, char *err);

/** Read and parse a model file. */
int session_model_load(const char *path, session_model_t *m, char *err);

/** Index of the segment NAME, or -1. */
int session_model_segment(const session_model_t *m, const char *name);

/** "auto", "ball" or "hinge". */
const char *session_model_type_name(int type);

#endif /* SFIT_TOOLS_SESSION_MODEL_H */
