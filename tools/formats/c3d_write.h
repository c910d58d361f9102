/* SPDX-License-Identifier: MIT */
/**
 * @file c3d_write.h
 * @brief Add points to a copy of a C3D recording, and write an OpenSim TRC
 * marker file (host only; docs/c3d.md).
 *
 * The C3D writer changes nothing but what adding points needs: the header's
 * point count and data block, POINT:USED, POINT:LABELS / DESCRIPTIONS (and
 * LABELS2, DESCRIPTIONS2 ... once 255 are reached), POINT:DATA_START, and
 * the frames, where the new points follow the recording's own. Every other
 * parameter, the header's events, every point sample and analog word are
 * kept, in the file's own processor format. Integer storage is kept unless a
 * new point cannot be held by a 16-bit integer times POINT:SCALE; then the
 * whole file is written as floats (POINT:SCALE = -|SCALE|, the recording's
 * samples and analog words converted exactly). A new point that cannot be
 * placed in a frame (NaN) gets residual -1 there.
 */
#ifndef SFIT_TOOLS_C3D_WRITE_H
#define SFIT_TOOLS_C3D_WRITE_H

#include <stddef.h>

#include "c3d.h"

/** Points to add. */
typedef struct c3d_add {
    int n;                      /**< new points (>= 1) */
    const char *const *names;   /**< n labels (the prefix is put before each) */
    const char *const *descs;   /**< n descriptions, or NULL (blank) */
    const float *xyz;           /**< nframes * n * 3, frame-major, in the file's units;
                                     NaN = cannot be placed (residual -1) */
    const char *prefix;         /**< subject prefix such as "P01:", or NULL / "" */
} c3d_add_t;

/**
 * Write `out_path`: the file held in buf (parsed into c by c3d_parse) with
 * the points of `add` (c->nframes frames). 0, or -1 with a message in err
 * (C3D_ERR_MAX). *to_float is set to 1 when integer storage had to become
 * float (may be NULL).
 */
int c3d_write_added(const unsigned char *buf, size_t len, const c3d_t *c, const c3d_add_t *add,
                    const char *out_path, int *to_float, char *err);

/** The same from the file at in_path. */
int c3d_write_added_file(const char *in_path, const char *out_path, const c3d_add_t *add,
                         int *to_float, char *err);

/**
 * An OpenSim TRC marker file: the recording's markers (c) and, when add is
 * not NULL, the new points (labels with add->prefix). Frame# counts from 1,
 * Time = (Frame# - 1) / rate; a missing sample is three blank cells.
 * 0, or -1 with a message in err.
 */
int c3d_write_trc(const char *path, const c3d_t *c, const c3d_add_t *add, char *err);

#endif /* SFIT_TOOLS_C3D_WRITE_H */
