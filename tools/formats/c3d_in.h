/* SPDX-License-Identifier: MIT */
/**
 * @file c3d_in.h
 * @brief Internal to the C3D reader (c3d.c: header, frames, data;
 * c3d_param.c: the parameter section and the labels): the bounds-checked
 * byte readers and what the two files share. Not for other files.
 */
#ifndef SFIT_C3D_IN_H
#define SFIT_C3D_IN_H

#include "c3d.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#define C3D_BLOCK 512u
#define C3D_MAX_ENTRIES 65536   /* parameter entries walked at most */
#define C3D_MAX_LABEL_PARAMS 64 /* LABELS, LABELS2 ... LABELS64 */
#define C3D_FILE_MAX (1024ul * 1024ul * 1024ul) /* 1 GiB */


typedef struct c3d_in {
    const unsigned char *b;
    size_t n;
    int proc;
} c3d_in_t;

static inline int fail(char *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, C3D_ERR_MAX, fmt, ap);
    va_end(ap);
    return -1;
}

static inline void warn(c3d_t *c, const char *fmt, ...)
{
    va_list ap;
    if (c->nwarn >= C3D_WARNINGS_MAX) {
        c->nwarn_dropped++;
        return;
    }
    va_start(ap, fmt);
    (void)vsnprintf(c->warnings[c->nwarn++], C3D_WARN_MAX, fmt, ap);
    va_end(ap);
}

static inline int has(const c3d_in_t *in, size_t off, size_t len)
{
    return off <= in->n && len <= in->n - off;
}

static inline unsigned rd_u16(const c3d_in_t *in, size_t off)
{
    const unsigned char *p = in->b + off;
    return (in->proc == C3D_PROC_MIPS) ? ((unsigned)p[0] << 8) | p[1]
                                       : ((unsigned)p[1] << 8) | p[0];
}

static inline unsigned swap16(unsigned u)
{
    return ((u & 0xffu) << 8) | (u >> 8);
}

static inline int rd_i16(const c3d_in_t *in, size_t off)
{
    const unsigned u = rd_u16(in, off);
    return (u >= 0x8000u) ? (int)u - 0x10000 : (int)u;
}

/* A VAX F-float: two little-endian 16-bit words, the high one first;
 * value (1 + m / 2^23) 2^(e - 129); e = 0 is zero (or, with the sign,
 * the reserved operand, read as NaN). */
static inline float dec_float(const unsigned char *p)
{
    const uint32_t u = ((uint32_t)p[1] << 24) | ((uint32_t)p[0] << 16) | ((uint32_t)p[3] << 8) | p[2];
    const unsigned e = (unsigned)((u >> 23) & 0xffu);
    const double m = 1.0 + (double)(u & 0x7fffffu) / 8388608.0;
    double v;
    if (e == 0u) {
        return (u >> 31) ? NAN : 0.0f;
    }
    v = ldexp(m, (int)e - 129);
    return (float)((u >> 31) ? -v : v);
}

static inline float rd_f32(const c3d_in_t *in, size_t off)
{
    const unsigned char *p = in->b + off;
    uint32_t u;
    float f;
    if (in->proc == C3D_PROC_DEC) {
        return dec_float(p);
    }
    if (in->proc == C3D_PROC_MIPS) {
        u = ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
    } else {
        u = ((uint32_t)p[3] << 24) | ((uint32_t)p[2] << 16) | ((uint32_t)p[1] << 8) | p[0];
    }
    memcpy(&f, &u, sizeof f);
    return f;
}

static inline int name_eq(const char *a, const char *b)
{
    while (*a != '\0' && toupper((unsigned char)*a) == toupper((unsigned char)*b)) {
        a++;
        b++;
    }
    return *a == '\0' && *b == '\0';
}

/* How the walk ended where a link leads nowhere (no recovery). */
typedef struct walk_end {
    int ended;            /* the walk stopped at a link it could not follow */
    char name[C3D_NAME_MAX + C3D_NAME_MAX]; /* GROUP:NAME of the entry */
    unsigned long at, to; /* byte of the link word, byte it points to */
    size_t reach;         /* the end of the last entry read */
} walk_end_t;

/* c3d_param.c */

/* Walk the whole parameter section once (entries into c); 0, or -1 with err. */
int c3d_walk_params(const c3d_in_t *in, size_t start, size_t bound, c3d_t *c,
                    walk_end_t *end, char *err);

/* Element i of a numeric parameter, as a double; -1 when absent. */
int c3d_param_number_at(const c3d_in_t *in, const c3d_entry_t *p, size_t i, double *v);

/* A count parameter (an int16 read as unsigned, a byte or a float); -1 when
 * absent or not a count. */
long c3d_param_count(const c3d_in_t *in, const c3d_entry_t *p);

/* TRIAL:ACTUAL_*_FIELD: two unsigned 16-bit words, low first. */
long c3d_param_field(const c3d_in_t *in, const c3d_entry_t *p);

/* Copy a blank-padded label, trimmed, printable. */
void c3d_copy_label(const unsigned char *s, size_t len, char *dst, size_t size);

/* The point labels (POINT:LABELS, LABELS2, ...) into c. */
void c3d_read_labels(const c3d_in_t *in, c3d_t *c);

/* Duplicate labels: the second and later copies become LABEL#2, LABEL#3. */
int c3d_rename_duplicates(c3d_t *c);

#endif /* SFIT_C3D_IN_H */
