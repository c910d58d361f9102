/* SPDX-License-Identifier: MIT */
/**
 * @file c3d.c
 * @brief C3D reader of the `sfit` tool (see c3d.h). Written from the
 * format's description: every multi-byte read goes through rd_*(), which
 * checks the offset against the buffer, so a hostile file cannot make the
 * reader look outside it.
 *
 * Layout used here (block = 512 bytes, block numbers count from 1):
 *   header, block 1: byte 0 parameter block, byte 1 key 0x50; 16-bit words
 *     (counting from 1) 2 points, 3 analog words per frame, 4 first frame,
 *     5 last frame, 7-8 float scale, 9 data block, 11-12 float rate;
 *   parameters: 4 bytes (byte 3 = 83 + processor type), then entries:
 *     int8 name length (0 ends; < 0 = locked), int8 id (< 0 group, > 0 the
 *     parameter's group), name, int16 offset of the next entry counted from
 *     this word (0 = last); a parameter then has int8 type (-1 char, 1 byte,
 *     2 int16, 4 float), uint8 dimension count, the dimensions, the data;
 *   data: per frame, per point x, y, z, residual word (4-byte floats when
 *     POINT:SCALE < 0, else 16-bit integers times SCALE), then the frame's
 *     analog words, which are skipped.
 */
#include "c3d.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define C3D_BLOCK 512u
#define C3D_PROC_INTEL 84
#define C3D_PROC_DEC 85
#define C3D_PROC_MIPS 86
#define C3D_MAX_ENTRIES 65536   /* parameter entries walked at most */
#define C3D_MAX_LABEL_PARAMS 64 /* LABELS, LABELS2 ... LABELS64 */
#define C3D_FILE_MAX (1024ul * 1024ul * 1024ul) /* 1 GiB */

typedef struct c3d_in {
    const unsigned char *b;
    size_t n;
    int proc;
} c3d_in_t;

/* One located parameter of the POINT group. */
typedef struct c3d_param {
    int found;
    int type;       /* -1, 1, 2, 4 */
    int ndims;
    unsigned dims[8];
    size_t data;    /* offset of the data */
    size_t count;   /* number of elements (product of the dimensions) */
} c3d_param_t;

typedef struct c3d_point_group {
    c3d_param_t used, scale, rate, units, data_start, frames;
    c3d_param_t labels[C3D_MAX_LABEL_PARAMS];
} c3d_point_group_t;

static int fail(char *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, C3D_ERR_MAX, fmt, ap);
    va_end(ap);
    return -1;
}

static int has(const c3d_in_t *in, size_t off, size_t len)
{
    return off <= in->n && len <= in->n - off;
}

static unsigned rd_u16(const c3d_in_t *in, size_t off)
{
    const unsigned char *p = in->b + off;
    return (in->proc == C3D_PROC_MIPS) ? ((unsigned)p[0] << 8) | p[1]
                                       : ((unsigned)p[1] << 8) | p[0];
}

static int rd_i16(const c3d_in_t *in, size_t off)
{
    const unsigned u = rd_u16(in, off);
    return (u >= 0x8000u) ? (int)u - 0x10000 : (int)u;
}

/* A VAX F-float: two little-endian 16-bit words, the high one first;
 * value (1 + m / 2^23) 2^(e - 129); e = 0 is zero (or, with the sign,
 * the reserved operand, read as NaN). */
static float dec_float(const unsigned char *p)
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

static float rd_f32(const c3d_in_t *in, size_t off)
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

static int name_is(const unsigned char *s, size_t len, const char *want)
{
    size_t i;
    if (strlen(want) != len) {
        return 0;
    }
    for (i = 0; i < len; i++) {
        if (toupper(s[i]) != toupper((unsigned char)want[i])) {
            return 0;
        }
    }
    return 1;
}

/* The first element of a numeric parameter, as a double. */
static int param_number(const c3d_in_t *in, const c3d_param_t *p, double *v)
{
    if (!p->found || p->count < 1u) {
        return -1;
    }
    switch (p->type) {
    case 1: *v = (double)in->b[p->data]; return 0;
    case 2: *v = (double)rd_i16(in, p->data); return 0;
    case 4: *v = (double)rd_f32(in, p->data); return 0;
    default: return -1;
    }
}

/* A count parameter: an int16 read as unsigned (counts above 32767), a
 * byte or a float; -1 when absent or not a count. */
static long param_count(const c3d_in_t *in, const c3d_param_t *p)
{
    double v;
    if (param_number(in, p, &v) != 0) {
        return -1;
    }
    if (p->type == 2 && v < 0.0) {
        v += 65536.0;
    }
    if (!(v >= 0.0) || v > 1.0e9) {
        return -1;
    }
    return (long)v;
}

/* Walk the parameter section once; pass 0 finds the POINT group id, pass 1
 * records its parameters. */
static int walk_params(const c3d_in_t *in, size_t start, int pass, int *point_id,
                       c3d_point_group_t *g, char *err)
{
    size_t off = start + 4u;
    long k;
    for (k = 0; k < C3D_MAX_ENTRIES; k++) {
        int nl, id, next;
        size_t name, after;
        if (!has(in, off, 2u)) {
            return fail(err, "parameter section truncated at byte %lu", (unsigned long)off);
        }
        nl = (int)(signed char)in->b[off];
        id = (int)(signed char)in->b[off + 1u];
        if (nl == 0) {
            return 0; /* end of the parameters */
        }
        if (nl < 0) {
            nl = -nl;
        }
        name = off + 2u;
        if (!has(in, name, (size_t)nl + 2u)) {
            return fail(err, "parameter section truncated at byte %lu", (unsigned long)off);
        }
        after = name + (size_t)nl; /* the offset word */
        next = (int)rd_u16(in, after);
        if (pass == 0 && id < 0 && name_is(in->b + name, (size_t)nl, "POINT")) {
            *point_id = -id;
        } else if (pass == 1 && id > 0 && id == *point_id) {
            c3d_param_t p;
            c3d_param_t *dst = NULL;
            size_t q = after + 2u, elem;
            int d;
            memset(&p, 0, sizeof p);
            if (!has(in, q, 2u)) {
                return fail(err, "parameter entry truncated at byte %lu", (unsigned long)q);
            }
            p.type = (int)(signed char)in->b[q];
            p.ndims = (int)in->b[q + 1u];
            q += 2u;
            if (p.type != -1 && p.type != 1 && p.type != 2 && p.type != 4) {
                return fail(err, "parameter POINT:%.*s has an invalid type %d", nl,
                            (const char *)(in->b + name), p.type);
            }
            if (p.ndims > 7 || !has(in, q, (size_t)p.ndims)) {
                return fail(err, "parameter POINT:%.*s has bad dimensions", nl,
                            (const char *)(in->b + name));
            }
            p.count = 1u;
            for (d = 0; d < p.ndims; d++) {
                p.dims[d] = in->b[q + (size_t)d];
                p.count *= p.dims[d];
            }
            q += (size_t)p.ndims;
            elem = (size_t)(p.type < 0 ? 1 : p.type);
            if (!has(in, q, p.count * elem)) {
                return fail(err, "parameter POINT:%.*s: data past the end of the file", nl,
                            (const char *)(in->b + name));
            }
            p.data = q;
            p.found = 1;
            if (name_is(in->b + name, (size_t)nl, "USED")) {
                dst = &g->used;
            } else if (name_is(in->b + name, (size_t)nl, "SCALE")) {
                dst = &g->scale;
            } else if (name_is(in->b + name, (size_t)nl, "RATE")) {
                dst = &g->rate;
            } else if (name_is(in->b + name, (size_t)nl, "UNITS")) {
                dst = &g->units;
            } else if (name_is(in->b + name, (size_t)nl, "DATA_START")) {
                dst = &g->data_start;
            } else if (name_is(in->b + name, (size_t)nl, "FRAMES")) {
                dst = &g->frames;
            } else if (name_is(in->b + name, (size_t)nl, "LABELS")) {
                dst = &g->labels[0];
            } else if (nl > 6 && nl <= 8 && name_is(in->b + name, 6u, "LABELS")) {
                int i, num = 0;
                for (i = 6; i < nl && isdigit(in->b[name + (size_t)i]); i++) {
                    num = 10 * num + (in->b[name + (size_t)i] - '0');
                }
                if (i == nl && num >= 2 && num <= C3D_MAX_LABEL_PARAMS) {
                    dst = &g->labels[num - 1];
                }
            }
            if (dst != NULL && !dst->found) {
                *dst = p;
            }
        }
        if (next == 0) {
            return 0; /* last entry */
        }
        off = after + (size_t)next; /* counted from the offset word; > off: no loop */
    }
    return fail(err, "parameter section: more than %d entries", C3D_MAX_ENTRIES);
}

/* Copy a blank-padded label, trimmed, printable. */
static void copy_label(const unsigned char *s, size_t len, char *dst)
{
    size_t a = 0, b = len, i, k = 0;
    while (a < b && (s[a] == ' ' || s[a] == '\0')) {
        a++;
    }
    while (b > a && (s[b - 1u] == ' ' || s[b - 1u] == '\0')) {
        b--;
    }
    for (i = a; i < b && k < C3D_LABEL_MAX - 1u; i++) {
        dst[k++] = (s[i] >= 0x20u && s[i] < 0x7fu) ? (char)s[i] : '?';
    }
    dst[k] = '\0';
}

static int read_labels(const c3d_in_t *in, const c3d_point_group_t *g, c3d_t *c)
{
    int p, next = 0;
    for (p = 0; p < C3D_MAX_LABEL_PARAMS && next < c->npoints; p++) {
        const c3d_param_t *l = &g->labels[p];
        size_t len, cnt, i;
        if (!l->found || l->type != -1) {
            if (p == 0) {
                continue;
            }
            break;
        }
        len = (l->ndims >= 1) ? l->dims[0] : 0u;
        cnt = (l->ndims >= 2) ? l->dims[1] : (len > 0u ? 1u : 0u);
        if (len > 0u && cnt > l->count / len) {
            cnt = l->count / len; /* a zero third dimension: fewer bytes stored */
        }
        for (i = 0; i < cnt && next < c->npoints; i++) {
            copy_label(in->b + l->data + i * len, len, c->labels[next++]);
        }
    }
    for (; next < c->npoints; next++) {
        (void)snprintf(c->labels[next], C3D_LABEL_MAX, "POINT%d", next + 1);
    }
    return 0;
}

int c3d_sniff(const unsigned char *buf, size_t len)
{
    return len >= 2u && buf[1] == 0x50u && buf[0] >= 2u;
}

static int parse(const unsigned char *buf, size_t len, c3d_t *out, char *err)
{
    c3d_in_t in;
    c3d_point_group_t g;
    size_t pstart, dstart, frame_bytes, word, need_per_frame;
    unsigned hdr_points, hdr_analog, hdr_first, hdr_last, hdr_data;
    int point_id = 0, proc;
    long nframes, f, cnt;
    double v;

    memset(out, 0, sizeof *out);
    err[0] = '\0';
    in.b = buf;
    in.n = len;
    in.proc = C3D_PROC_INTEL;
    if (len < C3D_BLOCK) {
        return fail(err, "not a C3D file: %lu bytes, shorter than the 512-byte header",
                    (unsigned long)len);
    }
    if (buf[1] != 0x50u || buf[0] < 2u) {
        return fail(err, "not a C3D file: no 0x50 key in the header");
    }
    pstart = ((size_t)buf[0] - 1u) * C3D_BLOCK;
    if (!has(&in, pstart, 4u)) {
        return fail(err, "truncated: the parameter section (block %u) is missing", buf[0]);
    }
    proc = (int)buf[pstart + 3u];
    if (proc != C3D_PROC_INTEL && proc != C3D_PROC_DEC && proc != C3D_PROC_MIPS) {
        return fail(err, "unknown processor type %d (84 Intel, 85 DEC, 86 MIPS)", proc);
    }
    in.proc = proc;
    hdr_points = rd_u16(&in, 2u);
    hdr_analog = rd_u16(&in, 4u);
    hdr_first = rd_u16(&in, 6u);
    hdr_last = rd_u16(&in, 8u);
    hdr_data = rd_u16(&in, 16u);

    memset(&g, 0, sizeof g);
    if (walk_params(&in, pstart, 0, &point_id, &g, err) != 0) {
        return -1;
    }
    if (point_id == 0) {
        return fail(err, "no POINT group in the parameter section");
    }
    if (walk_params(&in, pstart, 1, &point_id, &g, err) != 0) {
        return -1;
    }

    out->processor = proc;
    out->npoints = (int)hdr_points;
    cnt = param_count(&in, &g.used);
    if (cnt >= 0 && cnt != (long)hdr_points) {
        return fail(err, "POINT:USED (%ld) differs from the header's point count (%u)", cnt,
                    hdr_points);
    }
    out->scale = rd_f32(&in, 12u);
    if (param_number(&in, &g.scale, &v) == 0) {
        out->scale = (float)v;
    }
    if (!isfinite(out->scale) || out->scale == 0.0f) {
        return fail(err, "POINT:SCALE is %g: neither float (< 0) nor integer (> 0) storage",
                    (double)out->scale);
    }
    out->rate = rd_f32(&in, 20u);
    if (param_number(&in, &g.rate, &v) == 0) {
        out->rate = (float)v;
    }
    if (!isfinite(out->rate) || out->rate < 0.0f) {
        out->rate = 0.0f;
    }
    if (g.units.found && g.units.type == -1) {
        copy_label(buf + g.units.data, g.units.count < sizeof out->units ? g.units.count
                                                                          : sizeof out->units - 1u,
                   out->units);
    }
    cnt = param_count(&in, &g.data_start);
    if (cnt >= 1 && cnt <= 65535) {
        hdr_data = (unsigned)cnt;
    }
    if (hdr_data < 2u) {
        return fail(err, "invalid data start block %u", hdr_data);
    }
    nframes = (hdr_last >= hdr_first) ? (long)hdr_last - (long)hdr_first + 1 : 0;
    cnt = param_count(&in, &g.frames);
    if (cnt > nframes) {
        nframes = cnt; /* long trials overflow the header's 16-bit words */
    }
    out->first_frame = (long)hdr_first;

    word = (out->scale < 0.0f) ? 4u : 2u;
    need_per_frame = (4u * (size_t)hdr_points + (size_t)hdr_analog) * word;
    dstart = ((size_t)hdr_data - 1u) * C3D_BLOCK;
    if (dstart > len) {
        return fail(err, "truncated: the data section (block %u) starts past the end", hdr_data);
    }
    frame_bytes = need_per_frame;
    if (frame_bytes > 0u && (size_t)nframes > (len - dstart) / frame_bytes) {
        return fail(err, "truncated: %ld frames of %lu bytes announced, the file holds %lu",
                    nframes, (unsigned long)frame_bytes,
                    (unsigned long)((len - dstart) / frame_bytes));
    }
    out->nframes = nframes;

    out->labels = calloc((size_t)out->npoints + 1u, sizeof *out->labels);
    out->xyz = malloc(((size_t)nframes * (size_t)out->npoints * 3u + 1u) * sizeof(float));
    if (out->labels == NULL || out->xyz == NULL) {
        c3d_free(out);
        return fail(err, "out of memory");
    }
    (void)read_labels(&in, &g, out);
    for (f = 0; f < nframes && out->npoints > 0; f++) {
        const size_t fo = dstart + (size_t)f * frame_bytes;
        int p;
        for (p = 0; p < out->npoints; p++) {
            const size_t po = fo + (size_t)p * 4u * word;
            float *x = out->xyz + ((size_t)f * (size_t)out->npoints + (size_t)p) * 3u;
            int invalid, i;
            if (word == 4u) {
                for (i = 0; i < 3; i++) {
                    x[i] = rd_f32(&in, po + 4u * (size_t)i);
                }
                invalid = !(rd_f32(&in, po + 12u) >= 0.0f);
            } else {
                for (i = 0; i < 3; i++) {
                    x[i] = (float)rd_i16(&in, po + 2u * (size_t)i) * out->scale;
                }
                invalid = rd_i16(&in, po + 6u) < 0;
            }
            if (invalid) {
                x[0] = x[1] = x[2] = NAN;
            }
        }
    }
    return 0;
}

int c3d_parse(const unsigned char *buf, size_t len, c3d_t *out, char *err)
{
    const int rc = parse(buf, len, out, err);
    if (rc != 0) {
        c3d_free(out); /* nothing half-filled on failure */
    }
    return rc;
}

int c3d_read_file(const char *path, c3d_t *out, char *err)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t n = 0, cap = 0;
    int rc;
    memset(out, 0, sizeof *out);
    if (f == NULL) {
        return fail(err, "cannot open %s: %s", path, strerror(errno));
    }
    for (;;) {
        size_t got;
        if (n == cap) {
            unsigned char *nb;
            if (cap >= C3D_FILE_MAX) {
                free(buf);
                fclose(f);
                return fail(err, "%s: larger than 1 GiB", path);
            }
            cap = (cap == 0u) ? 65536u : 2u * cap;
            nb = realloc(buf, cap);
            if (nb == NULL) {
                free(buf);
                fclose(f);
                return fail(err, "out of memory");
            }
            buf = nb;
        }
        got = fread(buf + n, 1u, cap - n, f);
        n += got;
        if (got == 0u) {
            break;
        }
    }
    if (ferror(f)) {
        free(buf);
        fclose(f);
        return fail(err, "cannot read %s", path);
    }
    fclose(f);
    rc = c3d_parse(buf, n, out, err);
    free(buf);
    return rc;
}

void c3d_free(c3d_t *c)
{
    free(c->labels);
    free(c->xyz);
    memset(c, 0, sizeof *c);
}

int c3d_find(const c3d_t *c, const char *name)
{
    int i;
    for (i = 0; i < c->npoints; i++) {
        if (strcmp(c->labels[i], name) == 0) {
            return i;
        }
    }
    for (i = 0; i < c->npoints; i++) {
        const char *a = c->labels[i], *b = name;
        while (*a != '\0' && toupper((unsigned char)*a) == toupper((unsigned char)*b)) {
            a++;
            b++;
        }
        if (*a == '\0' && *b == '\0') {
            return i;
        }
    }
    return -1;
}
