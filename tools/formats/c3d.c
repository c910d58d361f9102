/* SPDX-License-Identifier: MIT */
/**
 * @file c3d.c
 * @brief C3D reader of the `sfit` tool (see c3d.h and docs/c3d.md). Written
 * from the format's description: every multi-byte read goes through rd_*(),
 * whose offsets are checked against the buffer first, so a hostile file
 * cannot make the reader look outside it.
 *
 * Layout used here (block = 512 bytes, block numbers count from 1):
 *   header, block 1: byte 0 parameter block, byte 1 key 0x50; 16-bit words
 *     (counting from 1) 2 points, 3 analog words per frame, 4 first frame,
 *     5 last frame, 7-8 float scale, 9 data block, 10 analog samples per
 *     frame, 11-12 float rate;
 *   parameters: 4 bytes (byte 2 = the section's size in blocks, byte 3 =
 *     83 + processor type), then entries: int8 name length (0 ends; < 0 =
 *     locked), int8 id (< 0 group, > 0 the parameter's group), name, int16
 *     offset of the next entry counted from this word (0 = last); a
 *     parameter then has int8 type (-1 char, 1 byte, 2 int16, 4 float),
 *     uint8 dimension count, the dimensions, the data, then (as a group)
 *     a description length byte and the description;
 *   data: per frame, per point x, y, z, residual word (4-byte floats when
 *     POINT:SCALE < 0, else 16-bit integers times SCALE), then the frame's
 *     analog words.
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
#define C3D_MAX_ENTRIES 65536   /* parameter entries walked at most */
#define C3D_MAX_LABEL_PARAMS 64 /* LABELS, LABELS2 ... LABELS64 */
#define C3D_FILE_MAX (1024ul * 1024ul * 1024ul) /* 1 GiB */

typedef struct c3d_in {
    const unsigned char *b;
    size_t n;
    int proc;
} c3d_in_t;

static int fail(char *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, C3D_ERR_MAX, fmt, ap);
    va_end(ap);
    return -1;
}

static void warn(c3d_t *c, const char *fmt, ...)
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

static unsigned swap16(unsigned u)
{
    return ((u & 0xffu) << 8) | (u >> 8);
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

static int name_eq(const char *a, const char *b)
{
    while (*a != '\0' && toupper((unsigned char)*a) == toupper((unsigned char)*b)) {
        a++;
        b++;
    }
    return *a == '\0' && *b == '\0';
}

const char *c3d_processor_name(int proc)
{
    return proc == C3D_PROC_INTEL ? "Intel" : proc == C3D_PROC_DEC ? "DEC" : "MIPS";
}

/* ------------------------------------------------------------ parameters */

/* Bytes of an entry's body (after the link word) from its content:
 * type, dims, data, description for a parameter; description for a group.
 * 0 when it does not fit before `bound`; fills the parameter fields. */
static size_t natural_body(const c3d_in_t *in, size_t body, size_t bound, c3d_entry_t *e)
{
    size_t q = body, elem, bytes;
    int d;
    if (!e->is_group) {
        if (q + 2u > bound) {
            return 0;
        }
        e->type = (int)(signed char)in->b[q];
        e->ndims = (int)in->b[q + 1u];
        q += 2u;
        if ((e->type != -1 && e->type != 1 && e->type != 2 && e->type != 4) || e->ndims > 7
            || q + (size_t)e->ndims > bound) {
            e->type = 0; /* unreadable parameter: kept as bytes, never interpreted */
            e->ndims = 0;
            return 0;
        }
        e->count = 1u;
        for (d = 0; d < e->ndims; d++) {
            e->dims[d] = in->b[q + (size_t)d];
            e->count *= e->dims[d];
        }
        q += (size_t)e->ndims;
        elem = (size_t)(e->type < 0 ? 1 : e->type);
        bytes = e->count * elem; /* <= 255^7 * 4: fits in 64 bits */
        if (bytes > bound - q) {
            e->type = 0;
            e->count = 0;
            return 0;
        }
        e->data = q;
        q += bytes;
    }
    if (q + 1u > bound) {
        return (size_t)(q - body); /* no description byte before the bound */
    }
    q += 1u + (size_t)in->b[q];
    if (q > bound) {
        q = bound;
    }
    return (size_t)(q - body);
}

/* A plausible entry start at `off`: a name of printable characters. */
static int plausible_entry(const c3d_in_t *in, size_t off, size_t bound)
{
    int nl, i;
    if (off + 1u > bound) {
        return 0;
    }
    nl = (int)(signed char)in->b[off];
    if (nl == 0) {
        return 1; /* the end mark */
    }
    if (nl < 0) {
        nl = -nl;
    }
    if (off + 4u + (size_t)nl > bound) {
        return 0;
    }
    for (i = 0; i < nl; i++) {
        const unsigned char ch = in->b[off + 2u + (size_t)i];
        if (ch < 0x20u || ch >= 0x7fu) {
            return 0;
        }
    }
    return 1;
}

typedef struct bad_link {
    int entry;
    unsigned link, used;
    int how; /* 1 other byte order, 2 the entry's own length */
} bad_link_t;

/* The name of the group of a parameter entry ("?" when not read). */
static const char *group_name(const c3d_t *c, const c3d_entry_t *e)
{
    int j;
    for (j = 0; j < c->nentries; j++) {
        if (c->entries[j].is_group && c->entries[j].group == e->group) {
            return c->entries[j].name;
        }
    }
    return "?";
}

/* How the walk ended where a link leads nowhere (no recovery). */
typedef struct walk_end {
    int ended;            /* the walk stopped at a link it could not follow */
    char name[C3D_NAME_MAX + C3D_NAME_MAX]; /* GROUP:NAME of the entry */
    unsigned long at, to; /* byte of the link word, byte it points to */
    size_t reach;         /* the end of the last entry read */
} walk_end_t;

/* Walk the whole parameter section once, bounded by `bound` (its declared
 * size, or the data section's start when the entries run past that size).
 * A link that leads nowhere, where neither the other byte order nor the
 * entry's own length gives a next entry, ends the walk (`end`). */
static int walk_params(const c3d_in_t *in, size_t start, size_t bound, c3d_t *c,
                       walk_end_t *end, char *err)
{
    size_t off = start + 4u, cap = 0;
    bad_link_t bad[C3D_WARNINGS_MAX];
    int nbad = 0, k, i, stop = 0;
    for (k = 0; k < C3D_MAX_ENTRIES; k++) {
        c3d_entry_t e;
        int nl;
        size_t after, nat, next_off;
        unsigned link;
        if (off + 2u > bound) {
            if (off >= bound && k > 0) {
                break; /* the section ends without an end mark: its size bounds it */
            }
            return fail(err, "parameter section truncated at byte %lu", (unsigned long)off);
        }
        memset(&e, 0, sizeof e);
        nl = (int)(signed char)in->b[off];
        e.group = (int)(signed char)in->b[off + 1u];
        if (nl == 0) {
            break; /* end of the parameters */
        }
        e.locked = nl < 0;
        if (nl < 0) {
            nl = -nl;
        }
        if (off + 4u + (size_t)nl > bound) {
            return fail(err, "parameter section truncated at byte %lu", (unsigned long)off);
        }
        e.off = off;
        e.is_group = e.group < 0;
        if (e.group < 0) {
            e.group = -e.group;
        }
        for (i = 0; i < nl; i++) {
            const unsigned char ch = in->b[off + 2u + (size_t)i];
            e.name[i] = (ch >= 0x20u && ch < 0x7fu) ? (char)ch : '?';
        }
        e.name[nl] = '\0';
        after = off + 2u + (size_t)nl; /* the link word */
        e.body = after + 2u;
        link = rd_u16(in, after);
        nat = natural_body(in, e.body, bound, &e);
        next_off = after + (size_t)link;
        if (link != 0u && (link < 2u || next_off > bound || !plausible_entry(in, next_off, bound))) {
            /* a link out of the section: the other byte order, or the entry's own length */
            const unsigned sw = swap16(link);
            bad_link_t b;
            b.entry = (int)c->nentries;
            b.link = link;
            if (sw >= 2u && after + sw <= bound && plausible_entry(in, after + sw, bound)) {
                b.used = sw;
                b.how = 1;
            } else if (nat > 0u && plausible_entry(in, e.body + nat, bound)) {
                b.used = (unsigned)(nat + 2u);
                b.how = 2;
            } else {
                /* the walk ends here: this entry is kept at its own length */
                end->ended = 1;
                end->at = (unsigned long)after;
                end->to = (unsigned long)next_off;
                (void)snprintf(end->name, sizeof end->name, "%s", e.name);
                stop = 1;
                b.used = 0u;
                b.how = 0;
            }
            if (!stop && nbad < C3D_WARNINGS_MAX) {
                bad[nbad++] = b;
            }
            link = b.used;
            next_off = after + (size_t)link;
        }
        e.end = (link == 0u) ? e.body + nat : next_off;
        if (e.end < e.body + nat) {
            e.end = e.body + nat; /* overlapping link: keep the body whole */
        }
        if ((size_t)c->nentries == cap) {
            const size_t ncap = (cap == 0u) ? 64u : 2u * cap;
            c3d_entry_t *ne = realloc(c->entries, ncap * sizeof *ne);
            if (ne == NULL) {
                return fail(err, "out of memory");
            }
            c->entries = ne;
            cap = ncap;
        }
        c->entries[c->nentries++] = e;
        if (e.end > end->reach) {
            end->reach = e.end;
        }
        if (link == 0u) {
            break; /* last entry */
        }
        off = next_off; /* > off: no loop */
    }
    if (k == C3D_MAX_ENTRIES) {
        return fail(err, "parameter section: more than %d entries", C3D_MAX_ENTRIES);
    }
    if (end->ended) {
        const c3d_entry_t *e = &c->entries[c->nentries - 1];
        const char *g = group_name(c, e);
        char nm[sizeof end->name];
        (void)snprintf(nm, sizeof nm, "%s%s%s", e->is_group ? "group " : g,
                       e->is_group ? "" : ":", e->name);
        (void)snprintf(end->name, sizeof end->name, "%s", nm);
    }
    for (i = 0; i < nbad; i++) {
        const c3d_entry_t *e = &c->entries[bad[i].entry];
        const char *g = group_name(c, e);
        warn(c,
             "parameter section: the link after %s%s%s (byte %lu) reads %u, outside the section; "
             "read as %u (%s)",
             e->is_group ? "group " : g, e->is_group ? "" : ":", e->name,
             (unsigned long)(e->body - 2u), bad[i].link, bad[i].used,
             bad[i].how == 1 ? "the other byte order" : "the entry's own length");
    }
    return 0;
}

const c3d_entry_t *c3d_param(const c3d_t *c, const char *group, const char *name)
{
    int g = -1, i;
    for (i = 0; i < c->nentries; i++) {
        if (c->entries[i].is_group && name_eq(c->entries[i].name, group)) {
            g = c->entries[i].group;
            break;
        }
    }
    if (g < 0) {
        return NULL;
    }
    for (i = 0; i < c->nentries; i++) {
        const c3d_entry_t *e = &c->entries[i];
        if (!e->is_group && e->group == g && e->type != 0 && name_eq(e->name, name)) {
            return e;
        }
    }
    return NULL;
}

/* Element i of a numeric parameter, as a double; -1 when absent. */
static int param_number_at(const c3d_in_t *in, const c3d_entry_t *p, size_t i, double *v)
{
    if (p == NULL || p->count <= i) {
        return -1;
    }
    switch (p->type) {
    case 1: *v = (double)in->b[p->data + i]; return 0;
    case 2: *v = (double)rd_i16(in, p->data + 2u * i); return 0;
    case 4: *v = (double)rd_f32(in, p->data + 4u * i); return 0;
    default: return -1;
    }
}

/* A count parameter: an int16 read as unsigned (counts above 32767), a
 * byte or a float; -1 when absent or not a count. */
static long param_count(const c3d_in_t *in, const c3d_entry_t *p)
{
    double v;
    if (param_number_at(in, p, 0u, &v) != 0) {
        return -1;
    }
    if (p->type == 2 && v < 0.0) {
        v += 65536.0;
    }
    if (!(v >= 0.0) || v > 1.0e9 || v != floor(v)) {
        return -1;
    }
    return (long)v;
}

/* TRIAL:ACTUAL_*_FIELD: two unsigned 16-bit words, low first. */
static long param_field(const c3d_in_t *in, const c3d_entry_t *p)
{
    double lo, hi;
    if (p == NULL || p->type != 2 || param_number_at(in, p, 0u, &lo) != 0
        || param_number_at(in, p, 1u, &hi) != 0) {
        return -1;
    }
    if (lo < 0.0) {
        lo += 65536.0;
    }
    if (hi < 0.0) {
        hi += 65536.0;
    }
    if (hi > 16383.0) {
        return -1;
    }
    return (long)lo + 65536L * (long)hi;
}

/* Copy a blank-padded label, trimmed, printable. */
static void copy_label(const unsigned char *s, size_t len, char *dst, size_t size)
{
    size_t a = 0, b = len, i, k = 0;
    while (a < b && (s[a] == ' ' || s[a] == '\0')) {
        a++;
    }
    while (b > a && (s[b - 1u] == ' ' || s[b - 1u] == '\0')) {
        b--;
    }
    for (i = a; i < b && k + 1u < size; i++) {
        dst[k++] = (s[i] >= 0x20u && s[i] < 0x7fu) ? (char)s[i] : '?';
    }
    dst[k] = '\0';
}

static void read_labels(const c3d_in_t *in, c3d_t *c)
{
    int p, next = 0;
    for (p = 0; p < C3D_MAX_LABEL_PARAMS && next < c->npoints; p++) {
        char nm[24];
        const c3d_entry_t *l;
        size_t len, cnt, i;
        if (p == 0) {
            (void)snprintf(nm, sizeof nm, "LABELS");
        } else {
            (void)snprintf(nm, sizeof nm, "LABELS%d", p + 1);
        }
        l = c3d_param(c, "POINT", nm);
        if (l == NULL || l->type != -1) {
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
            copy_label(in->b + l->data + i * len, len, c->labels[next++], C3D_LABEL_MAX);
        }
    }
    for (p = 0; p < c->npoints; p++) {
        if (c->labels[p][0] == '\0') {
            (void)snprintf(c->labels[p], C3D_LABEL_MAX, "POINT%d", p + 1);
        }
    }
}

static const c3d_t *g_sort_c3d; /* qsort has no context argument (C99) */

static int cmp_label(const void *a, const void *b)
{
    const int i = *(const int *)a, j = *(const int *)b;
    const int r = strcmp(g_sort_c3d->labels[i], g_sort_c3d->labels[j]);
    return (r != 0) ? r : (i > j) - (i < j);
}

/* Duplicate labels: the second and later copies become LABEL#2, LABEL#3. */
static int rename_duplicates(c3d_t *c)
{
    int *idx, k, renamed = 0;
    char first[C3D_WARN_MAX] = "";
    if (c->npoints < 2) {
        return 0;
    }
    idx = malloc((size_t)c->npoints * sizeof *idx);
    if (idx == NULL) {
        return -1;
    }
    for (k = 0; k < c->npoints; k++) {
        idx[k] = k;
    }
    g_sort_c3d = c;
    qsort(idx, (size_t)c->npoints, sizeof *idx, cmp_label);
    {
        int start = 0, run = 1;
        for (k = 1; k < c->npoints; k++) {
            char base[C3D_LABEL_MAX];
            if (strcmp(c->labels[idx[k]], c->labels[idx[start]]) != 0) {
                start = k;
                run = 1;
                continue;
            }
            run++;
            memcpy(base, c->labels[idx[k]], sizeof base);
            base[C3D_LABEL_MAX - 12] = '\0';
            if (renamed == 0) {
                (void)snprintf(first, sizeof first, "%.40s (points %d and %d) -> %.40s#%d", base,
                               idx[start] + 1, idx[k] + 1, base, run);
            }
            (void)snprintf(c->labels[idx[k]], C3D_LABEL_MAX, "%.51s#%d", base, run);
            renamed++;
        }
    }
    free(idx);
    if (renamed > 0) {
        warn(c, "duplicate labels: %d renamed LABEL#2, LABEL#3, ... in point order; first: %s",
             renamed, first);
    }
    return 0;
}

int c3d_sniff(const unsigned char *buf, size_t len)
{
    return len >= 2u && buf[1] == 0x50u && buf[0] >= 2u;
}

/* Frames lo .. hi-1 of the data section are all zero bytes. */
static int zero_frames(const c3d_in_t *in, const c3d_t *c, long lo, long hi)
{
    const size_t a = c->data_start + (size_t)lo * c->frame_bytes;
    const size_t b = c->data_start + (size_t)hi * c->frame_bytes;
    size_t i;
    if (hi <= lo || b > in->n) {
        return 0;
    }
    for (i = a; i < b; i++) {
        if (in->b[i] != 0u) {
            return 0;
        }
    }
    return 1;
}

/* Whole frames held, without trailing frames of zero bytes that start in
 * the file's last 512 bytes (the last block's padding). */
static long held_frames(const c3d_in_t *in, const c3d_t *c)
{
    long n = c->frames_in_file;
    while (n > 1 && c->data_start + (size_t)(n - 1) * c->frame_bytes + C3D_BLOCK >= in->n
           && zero_frames(in, c, n - 1, n)) {
        n--;
    }
    return n;
}

/* Frames: the header's count, POINT:FRAMES, the long counts and the file's
 * size. 0 with c->nframes set, or -1. */
static int choose_frames(const c3d_in_t *in, c3d_t *c, long hdr_frames, int have_params,
                         char *err)
{
    const long cap = c->frames_in_file;
    const long pf = have_params ? param_count(in, c3d_param(c, "POINT", "FRAMES")) : -1;
    /* a data section that ends after whole frames (or a file of whole
     * 512-byte blocks) was written to its end: a count above what it
     * holds was never updated. One that ends inside a frame was cut. */
    const size_t rest = (c->frame_bytes > 0u && in->n >= c->data_start)
                            ? (in->n - c->data_start) - (size_t)cap * c->frame_bytes
                            : 1u;
    const int complete = cap >= 1 && (rest == 0u || in->n % C3D_BLOCK == 0u);
    long lf = -1, n;
    const char *lsrc = NULL;
    if (have_params) {
        const c3d_entry_t *lp = c3d_param(c, "POINT", "LONG_FRAMES");
        const long s = param_field(in, c3d_param(c, "TRIAL", "ACTUAL_START_FIELD"));
        const long e = param_field(in, c3d_param(c, "TRIAL", "ACTUAL_END_FIELD"));
        double v;
        if (lp != NULL && lp->type == 2 && lp->count >= 2u) {
            lf = param_field(in, lp);
        } else if (param_number_at(in, lp, 0u, &v) == 0 && v >= 1.0 && v < 1.0e9) {
            lf = (long)v;
        }
        if (lf > 65535) {
            lsrc = "POINT:LONG_FRAMES";
        } else if (s >= 0 && e >= s && e - s + 1 > 65535) {
            lf = e - s + 1;
            lsrc = "TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD";
            c->first_frame = s;
        } else {
            lf = -1;
        }
    }
    if (lsrc != NULL) {
        if (lf > cap) {
            if (!complete) {
                return fail(err,
                            "truncated: %s announces %ld frames of %lu bytes, the file holds %ld "
                            "and ends inside a frame",
                            lsrc, lf, (unsigned long)c->frame_bytes, cap);
            }
            warn(c, "frame count: %s announces %ld frames, the data section holds %ld whole "
                    "frames and ends there: read %ld", lsrc, lf, cap, held_frames(in, c));
            lf = held_frames(in, c);
        }
        c->nframes = lf;
        c->src_frames = lsrc;
        return 0;
    }
    if (pf < 0 || pf == hdr_frames) {
        n = hdr_frames;
        c->src_frames = (pf < 0) ? "header" : "header, POINT:FRAMES";
        if (n > cap) {
            if (!complete) {
                return fail(err,
                            "truncated: %ld frames of %lu bytes announced (%s), the file holds "
                            "%ld and ends inside a frame",
                            n, (unsigned long)c->frame_bytes, c->src_frames, cap);
            }
            warn(c, "frame count: %ld announced (%s), the data section holds %ld whole frames "
                    "and ends there: read %ld", n, c->src_frames, cap, held_frames(in, c));
            c->src_frames = (pf < 0) ? "data section size (the header says more)"
                                     : "data section size (header and POINT:FRAMES say more)";
            n = held_frames(in, c);
        }
    } else {
        const int h_ok = hdr_frames <= cap, p_ok = pf <= cap;
        if (!h_ok && !p_ok) {
            if (!complete) {
                return fail(err,
                            "truncated: the header announces %ld frames, POINT:FRAMES %ld; the "
                            "file holds %ld frames of %lu bytes and ends inside a frame",
                            hdr_frames, pf, cap, (unsigned long)c->frame_bytes);
            }
            n = held_frames(in, c);
            c->src_frames = "data section size (header and POINT:FRAMES say more)";
            warn(c,
                 "frame count: the header says %ld, POINT:FRAMES %ld; the data section holds %ld "
                 "whole frames and ends there: read %ld",
                 hdr_frames, pf, cap, n);
        } else {
            const long lo = (hdr_frames < pf) ? hdr_frames : pf;
            const long hi = (hdr_frames < pf) ? pf : hdr_frames;
            if (h_ok && p_ok && zero_frames(in, c, lo, hi)) {
                /* the larger count's extra frames are zero bytes: padding */
                n = lo;
            } else {
                n = (h_ok && p_ok) ? hi : (h_ok ? hdr_frames : pf);
            }
            c->src_frames = (n == hdr_frames) ? "header (file size)" : "POINT:FRAMES (file size)";
            if (h_ok && p_ok && n == lo) {
                warn(c,
                     "frame count: the header says %ld, POINT:FRAMES %ld; frames %ld to %ld of "
                     "the data section are zero bytes (padding): read %ld (%s)",
                     hdr_frames, pf, lo, hi - 1, n, n == pf ? "POINT:FRAMES" : "the header");
            } else {
                warn(c,
                     "frame count: the header says %ld, POINT:FRAMES %ld; the file holds %ld: "
                     "read %ld (%s)",
                     hdr_frames, pf, cap, n, n == pf ? "POINT:FRAMES" : "the header");
            }
        }
    }
    c->nframes = n;
    if (cap > n && c->frame_bytes > 0u && (size_t)(cap - n) * c->frame_bytes >= C3D_BLOCK) {
        warn(c, "the data section holds %ld frames, %ld announced (%s): read %ld", cap, n,
             c->src_frames, n);
    }
    return 0;
}

/* A frame count n fits a frame size fb in a data section of `bytes` when
 * the n frames end at its end or in its last 512-byte block (padding). */
static int count_fits(size_t fb, size_t bytes, long n)
{
    if (n < 1 || fb == 0u || (size_t)n > bytes / fb) {
        return 0;
    }
    return bytes - (size_t)n * fb < C3D_BLOCK;
}

/* The announced count (the header's, else POINT:FRAMES) that frames of fb
 * bytes fit in the data section; 0 when neither does. */
static long fitting_count(size_t fb, size_t bytes, long hdr_frames, long pframes)
{
    return count_fits(fb, bytes, hdr_frames) ? hdr_frames
           : count_fits(fb, bytes, pframes)  ? pframes
                                             : 0;
}

/* Frames of fb bytes fit one announced count. */
static int layout_fits(size_t fb, size_t bytes, long hdr_frames, long pframes)
{
    return fitting_count(fb, bytes, hdr_frames, pframes) > 0;
}

/* Analog words per frame: the header against ANALOG:USED and the rates;
 * where they differ, the layout whose frames fill the data section. */
static int check_analog(const c3d_in_t *in, c3d_t *c, unsigned hdr_words, unsigned hdr_samples,
                        long hdr_frames, size_t data_bytes, char *err)
{
    const long pframes = param_count(in, c3d_param(c, "POINT", "FRAMES"));
    const long used = param_count(in, c3d_param(c, "ANALOG", "USED"));
    double ar = 0.0;
    c->analog_words = (long)hdr_words;
    c->src_analog = "header";
    if (param_number_at(in, c3d_param(c, "ANALOG", "RATE"), 0u, &ar) == 0 && isfinite(ar)
        && ar > 0.0) {
        c->analog_rate = (float)ar;
    }
    if (used < 0) {
        if (hdr_samples > 0u && hdr_words % hdr_samples == 0u) {
            c->analog_per_frame = (int)hdr_samples;
            c->analog_channels = (int)(hdr_words / hdr_samples);
        }
        return 0;
    }
    c->analog_channels = (int)used;
    if (used == 0) {
        if (hdr_words != 0u) {
            return fail(err,
                        "analog layout conflict: the header says %u analog words per frame, "
                        "ANALOG:USED 0",
                        hdr_words);
        }
        return 0;
    }
    if (c->analog_rate > 0.0f && c->rate > 0.0f) {
        const double ratio = (double)c->analog_rate / (double)c->rate;
        const double r = floor(ratio + 0.5);
        /* a ratio or a channel count past 16 bits cannot describe a frame
         * (the header's word is 16 bits): not used */
        if (r >= 1.0 && r <= 65535.0 && used <= 65535L && fabs(ratio - r) <= 1e-3 * r) {
            const long want = used * (long)r;
            if (want != (long)hdr_words) {
                const size_t pb = 4u * (size_t)c->npoints * (size_t)c->word;
                const size_t fh = pb + (size_t)hdr_words * (size_t)c->word;
                const size_t fp = pb + (size_t)want * (size_t)c->word;
                const int fits_h = layout_fits(fh, data_bytes, hdr_frames, pframes);
                const int fits_p = layout_fits(fp, data_bytes, hdr_frames, pframes);
                if (fits_h != fits_p) {
                    /* the data section's size decides: one layout ends the
                     * announced frames at its end (or in its last block) */
                    warn(c,
                         "analog layout: the header says %u analog words per frame, ANALOG:USED "
                         "%ld x ANALOG:RATE %g / POINT:RATE %g = %ld; the data section (%lu "
                         "bytes) holds the %ld frames announced in the %s layout only: read so",
                         hdr_words, used, ar, (double)c->rate, want, (unsigned long)data_bytes,
                         fits_h ? fitting_count(fh, data_bytes, hdr_frames, pframes)
                             : fitting_count(fp, data_bytes, hdr_frames, pframes),
                         fits_h ? "header's" : "parameters'");
                    c->analog_per_frame = fits_h ? (int)(hdr_words / (unsigned long)used) : (int)r;
                    if (fits_h && hdr_words % (unsigned long)used != 0u) {
                        c->analog_per_frame = 0;
                    }
                    c->analog_words = fits_h ? (long)hdr_words : want;
                    c->src_analog = fits_h ? "header (data section size)"
                                        : "ANALOG:USED x ANALOG:RATE / POINT:RATE (data section size)";
                    return 0;
                }
                return fail(err,
                            "analog layout conflict: the header says %u analog words per frame, "
                            "ANALOG:USED %ld x ANALOG:RATE %g / POINT:RATE %g = %ld; %ld frames "
                            "announced, the data section holds %lu frames of the header's layout, "
                            "%lu of the parameters'",
                            hdr_words, used, ar, (double)c->rate, want, hdr_frames,
                            (unsigned long)(fh > 0u ? data_bytes / fh : 0u),
                            (unsigned long)(fp > 0u ? data_bytes / fp : 0u));
            }
            c->analog_per_frame = (int)r;
            c->src_analog = "header, ANALOG:USED x ANALOG:RATE / POINT:RATE";
            return 0;
        }
        warn(c, "ANALOG:RATE / POINT:RATE = %g / %g is not a whole number", ar, (double)c->rate);
    }
    if (hdr_words % (unsigned long)used != 0u) {
        return fail(err,
                    "analog layout conflict: the header's %u analog words per frame are not a "
                    "multiple of ANALOG:USED %ld",
                    hdr_words, used);
    }
    c->analog_per_frame = (int)(hdr_words / (unsigned long)used);
    c->src_analog = "header, ANALOG:USED";
    return 0;
}

/* A walk ended at a link that leads nowhere: read on when the parameters
 * that fix the layout were read before it, else refuse naming the link and
 * the missing parameter. */
static int check_walk_end(c3d_t *c, const walk_end_t *w, unsigned hdr_points, unsigned hdr_analog,
                          char *err)
{
    static const char *const need[][2] = {{"POINT", "USED"},   {"POINT", "SCALE"},
                                          {"POINT", "RATE"},   {"POINT", "LABELS"},
                                          {"ANALOG", "USED"},  {"ANALOG", "RATE"}};
    size_t k;
    for (k = 0; k < sizeof need / sizeof need[0]; k++) {
        const int analog = need[k][0][0] == 'A';
        const int labels = need[k][1][0] == 'L';
        if ((analog && hdr_analog == 0u) || (labels && hdr_points == 0u)) {
            continue;
        }
        if (c3d_param(c, need[k][0], need[k][1]) == NULL) {
            return fail(err,
                        "parameter section: the link after %s (byte %lu) points to byte %lu, "
                        "where no entry starts (neither the other byte order nor the entry's "
                        "length gives one), and %s:%s was not read before it",
                        w->name, w->at, w->to, need[k][0], need[k][1]);
        }
    }
    warn(c,
         "parameter section: the link after %s (byte %lu) points to byte %lu, where no entry "
         "starts: the walk ends there, %d entries read (the layout's parameters among them)",
         w->name, w->at, w->to, c->nentries);
    return 0;
}

/* The processor type of a file without a parameter section: the byte order
 * that gives a data-start block inside the file, Intel or DEC by the rate. */
static int guess_processor(const unsigned char *buf, size_t len)
{
    c3d_in_t in;
    const unsigned nblocks = (unsigned)(len / C3D_BLOCK);
    unsigned w;
    float r;
    in.b = buf;
    in.n = len;
    in.proc = C3D_PROC_INTEL;
    w = rd_u16(&in, 16u);
    if (w < 2u || w > nblocks) {
        return C3D_PROC_MIPS;
    }
    r = rd_f32(&in, 20u);
    if (isfinite(r) && r > 0.0f && r < 1.0e6f) {
        return C3D_PROC_INTEL;
    }
    in.proc = C3D_PROC_DEC;
    r = rd_f32(&in, 20u);
    return (isfinite(r) && r > 0.0f && r < 1.0e6f) ? C3D_PROC_DEC : C3D_PROC_INTEL;
}

static int parse(const unsigned char *buf, size_t len, c3d_t *out, char *err)
{
    c3d_in_t in;
    size_t pstart, dstart, bound;
    unsigned hdr_points, hdr_analog, hdr_first, hdr_last, hdr_data, hdr_samples;
    int proc, have_params = 1;
    long f, cnt, hdr_frames;
    float hdr_scale, hdr_rate;
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
    proc = has(&in, pstart, 4u) ? (int)buf[pstart + 3u] : 0;
    {
        /* No parameter section: the header's data block is the parameter
         * block (read in the processor's byte order, or either one). */
        const unsigned le = (unsigned)buf[16] | ((unsigned)buf[17] << 8);
        const unsigned be = ((unsigned)buf[16] << 8) | buf[17];
        const int valid = proc == C3D_PROC_INTEL || proc == C3D_PROC_DEC || proc == C3D_PROC_MIPS;
        const unsigned w9 = valid ? (proc == C3D_PROC_MIPS ? be : le) : 0u;
        if ((valid && w9 == buf[0]) || (!valid && (le == buf[0] || be == buf[0]))) {
            have_params = 0;
            proc = guess_processor(buf, len);
        } else if (!valid && !has(&in, pstart, 4u)) {
            return fail(err, "truncated: the parameter section (block %u) is missing", buf[0]);
        } else if (!valid) {
            return fail(err, "unknown processor type %d (84 Intel, 85 DEC, 86 MIPS)", proc);
        }
    }
    in.proc = proc;
    out->processor = proc;
    out->src_processor = have_params ? "parameter section" : "header (no parameter section)";
    hdr_points = rd_u16(&in, 2u);
    hdr_analog = rd_u16(&in, 4u);
    hdr_first = rd_u16(&in, 6u);
    hdr_last = rd_u16(&in, 8u);
    hdr_scale = rd_f32(&in, 12u);
    hdr_data = rd_u16(&in, 16u);
    hdr_samples = rd_u16(&in, 18u);
    hdr_rate = rd_f32(&in, 20u);
    hdr_frames = (hdr_last >= hdr_first) ? (long)hdr_last - (long)hdr_first + 1 : 0;
    out->first_frame = (long)hdr_first;

    if (have_params) {
        /* The walk is bounded by the section's declared size, or by the
         * data section's start when that is later (a declared size too
         * small: the entries run on to the data, as the field's readers
         * follow them). */
        const unsigned nb = buf[pstart + 2u];
        const size_t declared = (nb > 0u) ? pstart + (size_t)nb * C3D_BLOCK : pstart;
        const size_t dsb = (hdr_data >= 2u) ? ((size_t)hdr_data - 1u) * C3D_BLOCK : 0u;
        walk_end_t wend;
        int i, g = 0, ngroups = 0;
        memset(&wend, 0, sizeof wend);
        bound = (dsb > declared) ? dsb : (nb > 0u ? declared : len);
        if (bound > len) {
            bound = len;
        }
        out->param_start = pstart;
        out->param_blocks = nb;
        if (walk_params(&in, pstart, bound, out, &wend, err) != 0) {
            return -1;
        }
        if (nb > 0u && wend.reach > declared) {
            warn(out,
                 "parameter section: its first block declares %u blocks (%lu bytes), its entries "
                 "run to byte %lu, before the data section (block %u): read to there",
                 nb, (unsigned long)(declared - pstart), (unsigned long)wend.reach, hdr_data);
        }
        if (wend.ended) {
            if (check_walk_end(out, &wend, hdr_points, hdr_analog, err) != 0) {
                return -1;
            }
        }
        for (i = 0; i < out->nentries; i++) {
            g |= out->entries[i].is_group && name_eq(out->entries[i].name, "POINT");
            ngroups += out->entries[i].is_group;
        }
        if (!g && ngroups > 0) {
            return fail(err, "no POINT group in the parameter section (%d groups, %d entries)",
                        ngroups, out->nentries);
        }
        if (!g) {
            /* no group at all: the header alone describes the data */
            have_params = 0;
            warn(out,
                 "parameter section: no groups (%d entries): counts, scale and rate from the "
                 "header, points named POINT1, POINT2, ...",
                 out->nentries);
            out->src_processor = "parameter section (no groups)";
        }
    }

    out->npoints = (int)hdr_points;
    out->src_points = "header";
    cnt = param_count(&in, c3d_param(out, "POINT", "USED"));
    if (cnt >= 0) {
        if (cnt != (long)hdr_points) {
            /* refused: which labels go with which points cannot be told;
             * the message gives the frames each count makes of the data */
            double sv = (double)hdr_scale;
            unsigned long fa = 0, fb = 0;
            size_t ws, ds;
            (void)param_number_at(&in, c3d_param(out, "POINT", "SCALE"), 0u, &sv);
            ws = (sv < 0.0) ? 4u : 2u;
            ds = (hdr_data >= 2u && ((size_t)hdr_data - 1u) * C3D_BLOCK < len)
                     ? len - ((size_t)hdr_data - 1u) * C3D_BLOCK
                     : 0u;
            if (cnt <= 65535L) {
                const size_t ha = (4u * (size_t)hdr_points + hdr_analog) * ws;
                const size_t pa = (4u * (size_t)cnt + hdr_analog) * ws;
                fa = (ha > 0u) ? (unsigned long)(ds / ha) : 0ul;
                fb = (pa > 0u) ? (unsigned long)(ds / pa) : 0ul;
            }
            return fail(err,
                        "POINT:USED (%ld) differs from the header's point count (%u); %ld frames "
                        "announced, the data section holds %lu frames of %u points, %lu of %ld",
                        cnt, hdr_points, hdr_frames, fa, hdr_points, fb, cnt);
        }
        out->src_points = "header, POINT:USED";
    }
    out->scale = hdr_scale;
    out->src_scale = "header";
    if (param_number_at(&in, c3d_param(out, "POINT", "SCALE"), 0u, &v) == 0) {
        out->scale = (float)v;
        out->src_scale = "POINT:SCALE";
        if (!(fabsf(out->scale - hdr_scale) <= 1e-6f * fabsf(out->scale))) {
            warn(out, "the header's scale %g differs from POINT:SCALE %g: POINT:SCALE used",
                 (double)hdr_scale, (double)out->scale);
            out->src_scale = "POINT:SCALE (the header differs)";
        }
    }
    if (!isfinite(out->scale) || out->scale == 0.0f) {
        return fail(err, "POINT:SCALE is %g: neither float (< 0) nor integer (> 0) storage",
                    (double)out->scale);
    }
    out->rate = hdr_rate;
    out->src_rate = "header";
    if (param_number_at(&in, c3d_param(out, "POINT", "RATE"), 0u, &v) == 0) {
        out->rate = (float)v;
        out->src_rate = "POINT:RATE";
    }
    if (!isfinite(out->rate) || out->rate < 0.0f) {
        out->rate = 0.0f;
    }
    {
        const c3d_entry_t *u = c3d_param(out, "POINT", "UNITS");
        if (u != NULL && u->type == -1) {
            copy_label(buf + u->data, u->count, out->units, sizeof out->units);
        }
    }
    cnt = param_count(&in, c3d_param(out, "POINT", "DATA_START"));
    if (cnt >= 1 && cnt <= 65535) {
        if ((unsigned)cnt != hdr_data) {
            warn(out, "the header's data block %u differs from POINT:DATA_START %ld: "
                      "POINT:DATA_START used", hdr_data, cnt);
        }
        hdr_data = (unsigned)cnt;
    }
    if (hdr_data < 2u) {
        return fail(err, "invalid data start block %u", hdr_data);
    }
    out->word = (out->scale < 0.0f) ? 4 : 2;
    dstart = ((size_t)hdr_data - 1u) * C3D_BLOCK;
    if (dstart > len) {
        return fail(err, "truncated: the data section (block %u) starts past the end", hdr_data);
    }
    out->data_start = dstart;
    if (check_analog(&in, out, hdr_analog, hdr_samples, hdr_frames, len - dstart, err) != 0) {
        return -1;
    }
    out->frame_bytes = (4u * (size_t)hdr_points + (size_t)out->analog_words) * (size_t)out->word;
    out->frames_in_file = (out->frame_bytes > 0u) ? (long)((len - dstart) / out->frame_bytes)
                                                  : 2147483647L;
    if (choose_frames(&in, out, hdr_frames, have_params, err) != 0) {
        return -1;
    }
    if (!have_params && out->param_start == 0u) {
        warn(out, "no parameter section: counts, scale and rate from the header, processor type "
                  "%s guessed from its byte order, points named POINT1, POINT2, ...",
             c3d_processor_name(proc));
    }

    out->labels = calloc((size_t)out->npoints + 1u, sizeof *out->labels);
    out->xyz = malloc(((size_t)out->nframes * (size_t)out->npoints * 3u + 1u) * sizeof(float));
    if (out->labels == NULL || out->xyz == NULL) {
        return fail(err, "out of memory");
    }
    read_labels(&in, out);
    if (rename_duplicates(out) != 0) {
        return fail(err, "out of memory");
    }
    {
        long zero_markers = 0;
        int p;
        for (p = 0; p < out->npoints; p++) {
            long zeros = 0;
            for (f = 0; f < out->nframes; f++) {
                const size_t po = dstart + (size_t)f * out->frame_bytes
                                  + (size_t)p * 4u * (size_t)out->word;
                float *x = out->xyz + ((size_t)f * (size_t)out->npoints + (size_t)p) * 3u;
                int invalid, i;
                if (out->word == 4) {
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
                } else if (x[0] == 0.0f && x[1] == 0.0f && x[2] == 0.0f) {
                    zeros++;
                }
            }
            out->zero_samples += zeros;
            zero_markers += zeros > 0;
        }
        if (out->zero_samples > 0) {
            warn(out,
                 "%ld samples of %ld markers at exactly (0, 0, 0) with a valid residual (how some "
                 "systems write a missing marker): sfit joint and skeleton take them as missing",
                 out->zero_samples, zero_markers);
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

int c3d_load_bytes(const char *path, unsigned char **out, size_t *len, char *err)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t n = 0, cap = 0;
    *out = NULL;
    *len = 0;
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
    *out = buf;
    *len = n;
    return 0;
}

int c3d_read_file(const char *path, c3d_t *out, char *err)
{
    unsigned char *buf;
    size_t n;
    int rc;
    memset(out, 0, sizeof *out);
    if (c3d_load_bytes(path, &buf, &n, err) != 0) {
        return -1;
    }
    rc = c3d_parse(buf, n, out, err);
    free(buf);
    return rc;
}

void c3d_free(c3d_t *c)
{
    free(c->labels);
    free(c->xyz);
    free(c->entries);
    memset(c, 0, sizeof *c);
}

int c3d_find(const c3d_t *c, const char *name)
{
    int i, hit = -1;
    for (i = 0; i < c->npoints; i++) {
        if (strcmp(c->labels[i], name) == 0) {
            return i;
        }
    }
    for (i = 0; i < c->npoints; i++) {
        if (name_eq(c->labels[i], name)) {
            return i;
        }
    }
    for (i = 0; i < c->npoints; i++) { /* "RASI" for "P01:RASI", when only one matches */
        const char *colon = strrchr(c->labels[i], ':');
        if (colon != NULL && strcmp(colon + 1, name) == 0) {
            if (hit >= 0) {
                return -1;
            }
            hit = i;
        }
    }
    return hit;
}

void c3d_label_prefix(const c3d_t *c, int k, char *out, size_t size)
{
    const char *colon;
    out[0] = '\0';
    if (k < 0 || k >= c->npoints || size == 0u) {
        return;
    }
    colon = strrchr(c->labels[k], ':');
    if (colon != NULL) {
        const size_t n = (size_t)(colon - c->labels[k]) + 1u;
        (void)snprintf(out, size, "%.*s", (int)n, c->labels[k]);
    }
}
