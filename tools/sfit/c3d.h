/* SPDX-License-Identifier: MIT */
/**
 * @file c3d.h
 * @brief A small C3D reader for the `sfit` host tool (3-D point data only).
 *
 * C3D is the motion-capture field's binary file: a 512-byte header block,
 * a parameter section (groups and typed parameters), then the frames. This
 * reader takes from the parameter section the POINT group (USED, LABELS,
 * LABELS2, LABELS3, ..., SCALE, RATE, UNITS, DATA_START, FRAMES) and the
 * header words it needs, and loads every frame's 3-D points; analog data
 * are skipped. Point data are floats (POINT:SCALE < 0) or scaled 16-bit
 * integers (SCALE > 0). Processor types: Intel (84) and DEC (85, VAX
 * F-floats converted) are little-endian; MIPS/SGI (86) is big-endian; all
 * three are read. A sample whose residual word is negative is invalid: its
 * x, y, z are NaN.
 *
 * Every read is bounded by the buffer: a malformed or truncated file gives
 * an error message, never a read outside the buffer. Host only (allocates).
 */
#ifndef SFIT_TOOLS_C3D_H
#define SFIT_TOOLS_C3D_H

#include <stddef.h>

#define C3D_LABEL_MAX 64 /* longest label kept (longer ones are cut) */
#define C3D_ERR_MAX 160  /* size of the error-message buffer */

typedef struct c3d {
    int npoints;           /**< points per frame (POINT:USED) */
    long nframes;          /**< frames stored */
    long first_frame;      /**< the header's number of the first stored frame */
    float rate;            /**< POINT:RATE (frames per second) */
    float scale;           /**< POINT:SCALE (< 0: float storage) */
    int processor;         /**< 84 Intel, 85 DEC, 86 MIPS */
    char units[16];        /**< POINT:UNITS ("mm", "m", ...), "" if absent */
    char (*labels)[C3D_LABEL_MAX]; /**< npoints labels, trailing blanks removed */
    float *xyz;            /**< nframes * npoints * 3 floats, NaN = invalid */
} c3d_t;

/**
 * Parse a whole C3D file held in memory. On success returns 0 and fills
 * `out` (release it with c3d_free). On failure returns -1, writes a
 * one-line explanation to `err` (C3D_ERR_MAX bytes) and leaves `out`
 * empty (c3d_free is still safe).
 */
int c3d_parse(const unsigned char *buf, size_t len, c3d_t *out, char *err);

/** Read and parse `path`. -1 with errno-based text in `err` if it cannot be read. */
int c3d_read_file(const char *path, c3d_t *out, char *err);

/** Release what c3d_parse allocated; `c` is left empty. */
void c3d_free(c3d_t *c);

/** Index of the point labelled `name` (exact, case-sensitive, then case-insensitive), or -1. */
int c3d_find(const c3d_t *c, const char *name);

/** Non-zero when the first bytes look like a C3D file (parameter block byte, key 0x50). */
int c3d_sniff(const unsigned char *buf, size_t len);

#endif /* SFIT_TOOLS_C3D_H */
