/* SPDX-License-Identifier: MIT */
/**
 * @file frames.h
 * @brief Marker trajectories for `sfit joint` and `sfit skeleton`: named
 * markers loaded from a C3D file (c3d.h) or a wide delimited table with one
 * x,y,z column triple per marker (table.h), frame by frame.
 */
#ifndef SFIT_TOOLS_FRAMES_H
#define SFIT_TOOLS_FRAMES_H

#include <stddef.h>

#include "sfit/sfit_types.h"

#define FRAMES_ERR_MAX 384
#define FRAMES_MARKERS_MAX 256 /* markers named in one command */

typedef struct frames_data {
    int nmarkers;        /**< markers loaded (in the order asked) */
    long nframes;        /**< frames (C3D frames or table data rows), index 0-based */
    float rate;          /**< frames per second (0 unknown: tables) */
    char units[16];      /**< "mm", "m" ... ("" unknown) */
    int is_c3d;
    long bad_rows;       /**< table rows that did not parse (all markers NaN there) */
    long zero_missing;   /**< C3D samples at exactly (0, 0, 0) with a valid residual,
                              taken as missing (how some systems write "missing") */
    sfit_vec3_t *xyz;    /**< nframes * nmarkers, frame-major; NaN = missing */
    /* every labelled point of a C3D file (context for pictures); NULL for tables */
    int nall;
    char (*all_labels)[64];
    float *all_xyz;      /**< nframes * nall * 3 */
} frames_data_t;

/**
 * Load `n` named markers of `path` (C3D when the file starts like one,
 * else delimited text). 0 on success; -1 if the file cannot be opened
 * (errno kept); -2 with a message in `why` (FRAMES_ERR_MAX) if it is
 * malformed or lacks a marker.
 */
int frames_load(const char *path, const char *const *names, int n, frames_data_t *out,
                    char *why);

/** Release a frames_data_t. */
void frames_free(frames_data_t *fr);

/** Marker k of frame f. */
static inline const sfit_vec3_t *frames_at(const frames_data_t *fr, long f, int k)
{
    return &fr->xyz[(size_t)f * (size_t)fr->nmarkers + (size_t)k];
}

/**
 * Split a comma-separated list in place into at most `max` items (empty
 * items rejected). Returns the count, or -1.
 */
int frames_split_list(char *s, char **items, int max);

/**
 * Parse F:L (whole numbers, 0 <= F <= L) into *first, *last. Returns 0;
 * 1 if F or the ':' is wrong; 2 if L is (or a number overflows);
 * *first and *last are unchanged on failure.
 */
int frames_parse_range(const char *s, long *first, long *last);

#endif /* SFIT_TOOLS_FRAMES_H */
