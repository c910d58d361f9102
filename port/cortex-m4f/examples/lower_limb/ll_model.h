/* SPDX-License-Identifier: MIT */
/**
 * @file ll_model.h
 * @brief The lower-limb model of the firmware example: 7 segments from the
 * marker set of the shared session (docs/lower_limb_firmware.md; the session model of
 * SESSION_MODEL.md), 6 joints, and the layout of the generated data.
 */
#ifndef LL_MODEL_H
#define LL_MODEL_H

#include <math.h>
#include <stdint.h>

#define LL_NAN NAN
#define LL_NMARK 32   /* markers per frame, segment by segment */
#define LL_NSEG 7
#define LL_NJOINT 6
#define LL_NTRIALS 4  /* rhip, rknee, rankle functional trials; anatomical_posture */

/* Frames of each trial in ll_xyz (the order of ll_gen's k_trials). */
#define LL_F_RHIP 525
#define LL_F_RKNEE 217
#define LL_F_RANKLE 486
#define LL_F_ANAT 122

enum { LL_PELVIS = 0, LL_RTHIGH, LL_RSHANK, LL_RFOOT, LL_LTHIGH, LL_LSHANK, LL_LFOOT };

/* First marker and count of each segment in a frame. */
static const uint8_t ll_seg_first[LL_NSEG] = {0, 4, 9, 14, 18, 23, 28};
static const uint8_t ll_seg_count[LL_NSEG] = {4, 5, 5, 4, 5, 5, 4};

/* Joints: parent, child; the right ones have a functional trial (index in
 * ll_xyz's trial order), the left ones none (-1). */
static const uint8_t ll_joint_parent[LL_NJOINT] = {LL_PELVIS, LL_RTHIGH, LL_RSHANK,
                                                   LL_PELVIS, LL_LTHIGH, LL_LSHANK};
static const uint8_t ll_joint_child[LL_NJOINT] = {LL_RTHIGH, LL_RSHANK, LL_RFOOT,
                                                  LL_LTHIGH, LL_LSHANK, LL_LFOOT};

static const char *const ll_marker_names[LL_NMARK] = {
    "RASI", "LASI", "RPSI", "LPSI",                  /* pelvis */
    "RTHI", "RTHIB", "RTHID", "RKNE", "RKNEM",       /* right thigh */
    "RTIB", "RTIBF", "RTIBD", "RANK", "RANKM",       /* right shank */
    "RHEE", "RTOE", "RNAV", "RTOE5",                 /* right foot */
    "LTHI", "LTHIB", "LTHID", "LKNE", "LKNEM",       /* left thigh */
    "LTIB", "LTIBF", "LTIBD", "LANK", "LANKM",       /* left shank */
    "LHEE", "LTOE", "LNAV", "LTOE5"};                /* left foot */

extern const float ll_xyz[][LL_NMARK][3];

#endif /* LL_MODEL_H */
