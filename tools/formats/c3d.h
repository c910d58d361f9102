/* SPDX-License-Identifier: MIT */
/**
 * @file c3d.h
 * @brief The C3D reader of the `sfit` host tool (3-D points; the layout of
 * everything else is checked and kept for the writer, c3d_write.h).
 *
 * C3D is the motion-capture field's binary file: a 512-byte header block,
 * a parameter section (groups and typed parameters), then the frames (per
 * frame the points' x, y, z, residual words, then the analog words).
 * Processor types: Intel (84) and DEC (85, VAX F-floats) little-endian,
 * MIPS/SGI (86) big-endian. Point data are floats (POINT:SCALE < 0) or
 * scaled 16-bit integers (SCALE > 0). A sample whose residual word is
 * negative is invalid: its x, y, z are NaN.
 *
 * Every count is taken from the header, the parameters and the file's size
 * together (docs/c3d.md): a conflict that changes what the samples mean is
 * refused with the numbers; a disagreement that the file's size settles is
 * read and reported as a warning. Every read is bounded by the buffer: a
 * malformed or truncated file gives an error message, never a read outside
 * the buffer. Host only (allocates).
 */
#ifndef SFIT_TOOLS_C3D_H
#define SFIT_TOOLS_C3D_H

#include <stddef.h>

#define C3D_LABEL_MAX 64   /* longest label kept (longer ones are cut) */
#define C3D_ERR_MAX 320    /* size of the error-message buffer */
#define C3D_WARN_MAX 240   /* size of one warning */
#define C3D_WARNINGS_MAX 16 /* warnings kept (more are counted in nwarn_dropped) */
#define C3D_NAME_MAX 130   /* parameter / group names (127; a length byte -128 reads 128) */

#define C3D_PROC_INTEL 84
#define C3D_PROC_DEC 85
#define C3D_PROC_MIPS 86

/** One entry of the parameter section: a group or a parameter. */
typedef struct c3d_entry {
    size_t off;         /**< byte offset of the entry (its name-length byte) */
    size_t body;        /**< offset of the body (after the link word) */
    size_t end;         /**< offset of the next entry (body + body length) */
    int group;          /**< group id (> 0), for a group and its parameters */
    int is_group;
    int locked;         /**< negative name length in the file */
    char name[C3D_NAME_MAX];
    /* parameters only */
    int type;           /**< -1 char, 1 byte, 2 int16, 4 float */
    int ndims;
    unsigned dims[7];
    size_t data;        /**< offset of the data */
    size_t count;       /**< elements (product of the dimensions) */
} c3d_entry_t;

typedef struct c3d {
    int npoints;           /**< points per frame (POINT:USED) */
    long nframes;          /**< frames read */
    long first_frame;      /**< the header's number of the first stored frame */
    float rate;            /**< POINT:RATE (frames per second) */
    float scale;           /**< POINT:SCALE (< 0: float storage) */
    int processor;         /**< 84 Intel, 85 DEC, 86 MIPS */
    char units[16];        /**< POINT:UNITS ("mm", "m", ...), "" if absent */
    char (*labels)[C3D_LABEL_MAX]; /**< npoints labels, trailing blanks removed,
                                        duplicates renamed LABEL#2, LABEL#3 ... */
    float *xyz;            /**< nframes * npoints * 3 floats, NaN = invalid */
    /* layout */
    int analog_channels;   /**< ANALOG:USED (0 when absent) */
    int analog_per_frame;  /**< analog samples per point frame */
    long analog_words;     /**< analog words per frame (channels x samples) */
    float analog_rate;     /**< ANALOG:RATE (0 when absent) */
    int word;              /**< bytes per stored value: 4 float, 2 integer */
    size_t param_start;    /**< byte offset of the parameter section (0: none) */
    unsigned param_blocks; /**< its declared size in 512-byte blocks */
    size_t data_start;     /**< byte offset of the first frame */
    size_t frame_bytes;    /**< bytes per frame (points and analog) */
    long frames_in_file;   /**< whole frames the data section holds */
    long zero_samples;     /**< valid samples at exactly (0, 0, 0) */
    /* where each count came from (static strings, for reports) */
    const char *src_processor, *src_points, *src_frames, *src_scale, *src_rate, *src_analog;
    /* warnings: what was read differently from what one source says */
    char warnings[C3D_WARNINGS_MAX][C3D_WARN_MAX];
    int nwarn;
    int nwarn_dropped;
    /* the parameter section, for the writer (NULL when there is none) */
    c3d_entry_t *entries;
    int nentries;
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

/**
 * Read `path` into memory (at most 1 GiB). 0 and a malloc'ed buffer in
 * *buf (free it), or -1 with a message in err.
 */
int c3d_load_bytes(const char *path, unsigned char **buf, size_t *len, char *err);

/** Release what c3d_parse allocated; `c` is left empty. */
void c3d_free(c3d_t *c);

/**
 * Index of the point labelled `name`: exact, then case-insensitive, then
 * the only label whose part after a subject prefix ("P01:RASI") matches; -1.
 */
int c3d_find(const c3d_t *c, const char *name);

/** The subject prefix of label k ("P01:" of "P01:RASI", up to the last ':'), "" if none. */
void c3d_label_prefix(const c3d_t *c, int k, char *out, size_t size);

/** Non-zero when the first bytes look like a C3D file (parameter block byte, key 0x50). */
int c3d_sniff(const unsigned char *buf, size_t len);

/** The entry GROUP:NAME of a parsed file, or NULL. */
const c3d_entry_t *c3d_param(const c3d_t *c, const char *group, const char *name);

/** "Intel", "DEC" or "MIPS". */
const char *c3d_processor_name(int proc);

#endif /* SFIT_TOOLS_C3D_H */
