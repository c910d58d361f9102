/* SPDX-License-Identifier: MIT */
/**
 * @file c3d_write.c
 * @brief Points added to a copy of a C3D recording; OpenSim TRC files
 * (c3d_write.h, docs/c3d.md). The parameter section is rebuilt entry by
 * entry from the reader's table (c3d_entry_t): every entry's bytes are
 * copied, except the few values adding points changes; the links are
 * rewritten (so a link the reader had to recover comes out right).
 */
#include "c3d_write.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W_BLOCK 512u
#define W_CHUNK 255 /* strings per LABELS / DESCRIPTIONS parameter */
#define W_MAX_CHUNKS 64

static int wfail(char *err, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, C3D_ERR_MAX, fmt, ap);
    va_end(ap);
    return -1;
}

/* ---------------------------------------------------------------- bytes */
typedef struct bbuf {
    unsigned char *p;
    size_t n, cap;
    int oom;
} bbuf_t;

static void put(bbuf_t *b, const void *src, size_t len)
{
    if (b->oom) {
        return;
    }
    if (b->n + len > b->cap) {
        size_t nc = (b->cap == 0u) ? 4096u : b->cap;
        unsigned char *np;
        while (nc < b->n + len) {
            nc *= 2u;
        }
        np = realloc(b->p, nc);
        if (np == NULL) {
            b->oom = 1;
            return;
        }
        b->p = np;
        b->cap = nc;
    }
    if (len > 0u) {
        memcpy(b->p + b->n, src, len);
    }
    b->n += len;
}

static void put_byte(bbuf_t *b, unsigned v)
{
    const unsigned char c = (unsigned char)(v & 0xffu);
    put(b, &c, 1u);
}

static void enc_u16(int proc, unsigned v, unsigned char *p)
{
    if (proc == C3D_PROC_MIPS) {
        p[0] = (unsigned char)((v >> 8) & 0xffu);
        p[1] = (unsigned char)(v & 0xffu);
    } else {
        p[0] = (unsigned char)(v & 0xffu);
        p[1] = (unsigned char)((v >> 8) & 0xffu);
    }
}

static unsigned dec_u16(int proc, const unsigned char *p)
{
    return (proc == C3D_PROC_MIPS) ? ((unsigned)p[0] << 8) | p[1] : ((unsigned)p[1] << 8) | p[0];
}

/* A float in the file's format; DEC: the VAX F-float (exponent bias 2
 * higher than IEEE, 16-bit halves swapped). -1 if DEC cannot hold it. */
static int enc_f32(int proc, float v, unsigned char *p)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    if (proc == C3D_PROC_DEC) {
        const unsigned e = (unsigned)((u >> 23) & 0xffu);
        if (e == 0u) {
            u = 0u; /* zero and subnormals: zero */
        } else if (e >= 254u) {
            return -1;
        } else {
            u += (uint32_t)2u << 23;
        }
        p[1] = (unsigned char)(u >> 24);
        p[0] = (unsigned char)(u >> 16);
        p[3] = (unsigned char)(u >> 8);
        p[2] = (unsigned char)u;
        return 0;
    }
    if (proc == C3D_PROC_MIPS) {
        p[0] = (unsigned char)(u >> 24);
        p[1] = (unsigned char)(u >> 16);
        p[2] = (unsigned char)(u >> 8);
        p[3] = (unsigned char)u;
    } else {
        p[3] = (unsigned char)(u >> 24);
        p[2] = (unsigned char)(u >> 16);
        p[1] = (unsigned char)(u >> 8);
        p[0] = (unsigned char)u;
    }
    return 0;
}

static int dec_i16(int proc, const unsigned char *p)
{
    const unsigned u = dec_u16(proc, p);
    return (u >= 0x8000u) ? (int)u - 0x10000 : (int)u;
}

/* ------------------------------------------------- string array params */
typedef struct strarr {
    int entry;           /* index in c->entries, -1 for a new parameter */
    unsigned width;
    size_t count;
    size_t first;        /* index of its first string in the family's list */
} strarr_t;

typedef struct family {
    strarr_t ch[W_MAX_CHUNKS];
    int nch;
    int last_entry;      /* entry after which new chunks go (-1: at the end) */
    char (*s)[256];      /* every string, blank-padded */
    size_t total;
    const char (*base)[256];
} family_t;

static void family_free(family_t *f)
{
    free(f->s);
    f->s = NULL;
    f->nch = 0;
}

/* Load LABELS, LABELS2 ... (or DESCRIPTIONS ...) of the POINT group, with
 * room for `extra` more strings. */
static int family_load(const unsigned char *buf, const c3d_t *c, const char *base, size_t extra,
                       family_t *f)
{
    int k;
    size_t total = 0, i;
    memset(f, 0, sizeof *f);
    f->last_entry = -1;
    for (k = 1; k <= W_MAX_CHUNKS; k++) {
        char nm[32];
        const c3d_entry_t *e;
        strarr_t *a;
        if (k == 1) {
            (void)snprintf(nm, sizeof nm, "%s", base);
        } else {
            (void)snprintf(nm, sizeof nm, "%s%d", base, k);
        }
        e = c3d_param(c, "POINT", nm);
        if (e == NULL || e->type != -1) {
            break;
        }
        a = &f->ch[f->nch++];
        a->entry = (int)(e - c->entries);
        a->width = (e->ndims >= 1) ? e->dims[0] : 0u;
        a->count = (e->ndims >= 2) ? e->dims[1] : (a->width > 0u ? 1u : 0u);
        if (a->width == 0u) {
            a->count = 0u;
        } else if (a->count > e->count / a->width) {
            a->count = e->count / a->width;
        }
        a->first = total;
        total += a->count;
        f->last_entry = a->entry;
    }
    f->s = malloc((total + extra + 1u) * sizeof *f->s);
    if (f->s == NULL) {
        return -1;
    }
    for (k = 0; k < f->nch; k++) {
        const c3d_entry_t *e = &c->entries[f->ch[k].entry];
        for (i = 0; i < f->ch[k].count; i++) {
            char *d = f->s[f->ch[k].first + i];
            memset(d, ' ', 256u);
            memcpy(d, buf + e->data + i * f->ch[k].width, f->ch[k].width);
        }
    }
    f->total = total;
    return 0;
}

static size_t trimmed(const char *s)
{
    size_t l = 255u;
    while (l > 0u && s[l - 1u] == ' ') {
        l--;
    }
    return l;
}

/* Insert n strings at position pos (blank ones first up to pos). The chunk
 * holding pos receives them; a chunk past 255 strings hands its last ones
 * to the next chunk (a new one after the last). Widths grow to fit. */
static int family_insert(family_t *f, size_t pos, const char *const *strs, int n,
                         const char *prefix, size_t room)
{
    size_t npad = (pos > f->total) ? pos - f->total : 0u, at, k, cnt[W_MAX_CHUNKS];
    int i, ci;
    const size_t nins = npad + (size_t)n;
    if (f->total + nins > room) {
        return -1;
    }
    at = (pos > f->total) ? f->total : pos;
    memmove(f->s + at + nins, f->s + at, (f->total - at) * sizeof *f->s);
    for (k = 0; k < nins; k++) {
        char item[256];
        size_t len;
        if (k < npad) {
            item[0] = '\0';
        } else {
            const size_t j = k - npad;
            (void)snprintf(item, sizeof item, "%s%s", prefix != NULL ? prefix : "",
                           strs != NULL && strs[j] != NULL ? strs[j] : "");
        }
        len = strlen(item);
        memset(f->s[at + k], ' ', 256u);
        memcpy(f->s[at + k], item, len);
    }
    f->total += nins;
    if (f->nch == 0) {
        f->ch[0].entry = -1;
        f->ch[0].width = 1u;
        f->ch[0].count = 0u;
        f->nch = 1;
    }
    for (ci = 0; ci < f->nch - 1; ci++) {
        if (at < f->ch[ci].first + f->ch[ci].count) {
            break;
        }
    }
    for (i = 0; i < f->nch; i++) {
        cnt[i] = f->ch[i].count + (i == ci ? nins : 0u);
    }
    for (i = 0; i < f->nch; i++) {
        if (cnt[i] > W_CHUNK) {
            if (i + 1 == f->nch) {
                if (f->nch >= W_MAX_CHUNKS) {
                    return -2;
                }
                f->ch[f->nch].entry = -1;
                f->ch[f->nch].width = f->ch[i].width;
                cnt[f->nch] = 0u;
                f->nch++;
            }
            cnt[i + 1] += cnt[i] - W_CHUNK;
            cnt[i] = W_CHUNK;
        }
    }
    for (i = 0, k = 0; i < f->nch; i++) {
        size_t j;
        f->ch[i].first = k;
        f->ch[i].count = cnt[i];
        for (j = 0; j < cnt[i]; j++) {
            const size_t l = trimmed(f->s[k + j]);
            if (l > f->ch[i].width) {
                f->ch[i].width = (unsigned)l;
            }
        }
        k += cnt[i];
    }
    return 0;
}

/* The body of a string-array parameter: type, dims, data, description. */
static void strarr_body(bbuf_t *b, const family_t *f, const strarr_t *a, const unsigned char *buf,
                        const c3d_t *c)
{
    size_t i;
    put_byte(b, 0xffu); /* type -1 */
    put_byte(b, 2u);
    put_byte(b, a->width);
    put_byte(b, (unsigned)a->count);
    for (i = 0; i < a->count; i++) {
        put(b, f->s[a->first + i], a->width);
    }
    if (a->entry >= 0) {
        const c3d_entry_t *e = &c->entries[a->entry];
        const size_t after = e->data + e->count; /* description length byte and text */
        if (after < e->end) {
            put(b, buf + after, e->end - after);
        } else {
            put_byte(b, 0u);
        }
    } else {
        put_byte(b, 0u);
    }
}

/* One entry: name length (sign kept), id, name, link, body. */
static int put_entry(bbuf_t *out, const c3d_t *c, const c3d_entry_t *e, int proc, const char *name,
                     int group, int is_group, int locked, const bbuf_t *body, char *err)
{
    const size_t nl = strlen(name);
    unsigned char w[2];
    (void)c;
    (void)e;
    if (nl == 0u || nl > 127u) {
        return wfail(err, "parameter name '%s' cannot be written", name);
    }
    if (body->n + 2u > 65535u) {
        return wfail(err, "parameter %s is too large for a C3D parameter (%lu bytes)", name,
                     (unsigned long)body->n);
    }
    put_byte(out, locked ? (unsigned)(256 - (int)nl) : (unsigned)nl);
    put_byte(out, is_group ? (unsigned)(256 - group) : (unsigned)group);
    put(out, name, nl);
    enc_u16(proc, (unsigned)(body->n + 2u), w);
    put(out, w, 2u);
    put(out, body->p, body->n);
    return 0;
}

static int point_group_id(const c3d_t *c)
{
    int i;
    for (i = 0; i < c->nentries; i++) {
        const char *a = c->entries[i].name, *b = "POINT";
        if (!c->entries[i].is_group) {
            continue;
        }
        while (*a != '\0' && (*a == *b || *a == *b + 32)) {
            a++;
            b++;
        }
        if (*a == '\0' && *b == '\0') {
            return c->entries[i].group;
        }
    }
    return -1;
}

static int is_entry(const c3d_t *c, int i, const c3d_entry_t *e)
{
    return e != NULL && &c->entries[i] == e;
}

/* Patch one numeric value (element 0) of a copied parameter body. */
static int patch_number(bbuf_t *body, const c3d_entry_t *e, int proc, double v)
{
    unsigned char *p = body->p + (e->data - e->body);
    if (e->count < 1u) {
        return -1;
    }
    switch (e->type) {
    case 1: p[0] = (unsigned char)v; return 0;
    case 2: enc_u16(proc, (unsigned)((long)v & 0xffff), p); return 0;
    case 4: return enc_f32(proc, (float)v, p);
    default: return -1;
    }
}

/* POINT:FRAMES as stored (an int16 read as unsigned), -1 if not a count. */
static long frames_of(const unsigned char *buf, const c3d_t *c, const c3d_entry_t *e)
{
    if (e->count < 1u) {
        return -1;
    }
    if (e->type == 2) {
        return (long)dec_u16(c->processor, buf + e->data);
    }
    if (e->type == 1) {
        return (long)buf[e->data];
    }
    return -1; /* a float count: rewritten */
}

static int new_number(bbuf_t *out, const c3d_t *c, const char *name, int group, int type,
                      double v, char *err)
{
    bbuf_t b;
    unsigned char w[4];
    int rc;
    memset(&b, 0, sizeof b);
    put_byte(&b, (unsigned)type);
    put_byte(&b, 0u); /* a scalar */
    if (type == 2) {
        enc_u16(c->processor, (unsigned)((long)v & 0xffff), w);
        put(&b, w, 2u);
    } else if (enc_f32(c->processor, (float)v, w) == 0) {
        put(&b, w, 4u);
    } else {
        free(b.p);
        return wfail(err, "POINT:%s %g cannot be written", name, v);
    }
    put_byte(&b, 0u); /* no description */
    rc = b.oom ? wfail(err, "out of memory") : put_entry(out, c, NULL, c->processor, name, group, 0, 0, &b, err);
    free(b.p);
    return rc;
}

/* A file without a POINT group (its header alone describes the points):
 * the group and the parameters a reader needs, from what was read. */
static int new_point_group(const c3d_t *c, const c3d_add_t *add, unsigned data_block,
                           int to_float, bbuf_t *out, int *pg, char *err)
{
    int i, g = 0;
    bbuf_t b;
    for (i = 0; i < c->nentries; i++) {
        if (c->entries[i].group > g) {
            g = c->entries[i].group;
        }
    }
    if (g >= 127) {
        return wfail(err, "no group id left for a POINT group");
    }
    *pg = g + 1;
    memset(&b, 0, sizeof b);
    put_byte(&b, 0u);
    if (put_entry(out, c, NULL, c->processor, "POINT", *pg, 1, 0, &b, err) != 0) {
        free(b.p);
        return -1;
    }
    free(b.p);
    if (new_number(out, c, "USED", *pg, 2, (double)(c->npoints + add->n), err) != 0
        || new_number(out, c, "SCALE", *pg, 4, to_float ? -fabs((double)c->scale) : (double)c->scale,
                      err) != 0
        || new_number(out, c, "RATE", *pg, 4, (double)c->rate, err) != 0
        || new_number(out, c, "DATA_START", *pg, 2, (double)data_block, err) != 0
        || (c->nframes <= 65535L
            && new_number(out, c, "FRAMES", *pg, 2, (double)c->nframes, err) != 0)) {
        return -1;
    }
    return 0;
}

/* A new parameter for chunk k of family f in group pg: BASE, BASE2, ... */
static int put_chunk(bbuf_t *out, const c3d_t *c, int proc, int pg, const family_t *f, int k,
                     const char *base, const unsigned char *buf, char *err)
{
    char nm[32];
    bbuf_t nb;
    int rc = 0;
    memset(&nb, 0, sizeof nb);
    (void)snprintf(nm, sizeof nm, k == 0 ? "%s" : "%s%d", base, k + 1);
    strarr_body(&nb, f, &f->ch[k], buf, c);
    if (nb.oom) {
        rc = wfail(err, "out of memory");
    } else if (put_entry(out, c, NULL, proc, nm, pg, 0, 0, &nb, err) != 0) {
        rc = -1;
    }
    free(nb.p);
    return rc;
}

/* The rebuilt parameter section (without its 4-byte head). */
static int build_params(const unsigned char *buf, const c3d_t *c, const c3d_add_t *add,
                        family_t *lab, family_t *des, unsigned data_block, int to_float,
                        bbuf_t *out, char *err)
{
    const int proc = c->processor;
    int pg = point_group_id(c);
    const c3d_entry_t *used = c3d_param(c, "POINT", "USED");
    const c3d_entry_t *ds = c3d_param(c, "POINT", "DATA_START");
    const c3d_entry_t *sc = c3d_param(c, "POINT", "SCALE");
    const c3d_entry_t *fr = c3d_param(c, "POINT", "FRAMES");
    family_t *fams[2];
    const char *bases[2] = {"LABELS", "DESCRIPTIONS"};
    int i, k, fi;
    fams[0] = lab;
    fams[1] = des;
    if (pg < 0 && new_point_group(c, add, data_block, to_float, out, &pg, err) != 0) {
        return -1;
    }
    for (i = 0; i < c->nentries; i++) {
        const c3d_entry_t *e = &c->entries[i];
        bbuf_t body;
        int done = 0;
        memset(&body, 0, sizeof body);
        for (fi = 0; fi < 2 && !done; fi++) {
            family_t *f = fams[fi];
            if (f == NULL) {
                continue;
            }
            for (k = 0; k < f->nch; k++) {
                if (f->ch[k].entry == i) {
                    strarr_body(&body, f, &f->ch[k], buf, c);
                    done = 1;
                    break;
                }
            }
        }
        if (!done) {
            put(&body, buf + e->body, e->end - e->body);
            if (body.oom) {
                return wfail(err, "out of memory");
            }
            if (is_entry(c, i, used)
                && patch_number(&body, e, proc, (double)(c->npoints + add->n)) != 0) {
                free(body.p);
                return wfail(err, "POINT:USED cannot be written");
            }
            if (is_entry(c, i, ds) && patch_number(&body, e, proc, (double)data_block) != 0) {
                free(body.p);
                return wfail(err, "POINT:DATA_START cannot be written");
            }
            if (is_entry(c, i, fr) && c->nframes <= 65535L && frames_of(buf, c, e) != c->nframes
                && patch_number(&body, e, proc, (double)c->nframes) != 0) {
                free(body.p);
                return wfail(err, "POINT:FRAMES cannot be written");
            }
            if (is_entry(c, i, sc) && to_float
                && patch_number(&body, e, proc, -fabs((double)c->scale)) != 0) {
                free(body.p);
                return wfail(err, "POINT:SCALE cannot be written");
            }
        }
        if (body.oom || put_entry(out, c, e, proc, e->name, e->group, e->is_group, e->locked, &body,
                                  err) != 0) {
            free(body.p);
            return body.oom ? wfail(err, "out of memory") : -1;
        }
        free(body.p);
        /* new chunks of a family go after its last existing parameter */
        for (fi = 0; fi < 2; fi++) {
            family_t *f = fams[fi];
            if (f == NULL || f->last_entry != i) {
                continue;
            }
            for (k = 0; k < f->nch; k++) {
                if (f->ch[k].entry < 0
                    && put_chunk(out, c, proc, pg, f, k, bases[fi], buf, err) != 0) {
                    return -1;
                }
            }
        }
    }
    /* a family with no parameter before (no POINT:LABELS): at the end */
    for (fi = 0; fi < 2; fi++) {
        family_t *f = fams[fi];
        if (f == NULL || f->last_entry >= 0) {
            continue;
        }
        for (k = 0; k < f->nch; k++) {
            if (put_chunk(out, c, proc, pg, f, k, bases[fi], buf, err) != 0) {
                return -1;
            }
        }
    }
    if (out->oom) {
        return wfail(err, "out of memory");
    }
    return 0;
}

/* Set the last entry's link to 0 (the end of the section). */
static void terminate_links(bbuf_t *ps, int proc)
{
    size_t off = 0, last = (size_t)-1;
    while (off + 4u <= ps->n) {
        int nl = (int)(signed char)ps->p[off];
        size_t lo;
        unsigned link;
        if (nl == 0) {
            break;
        }
        if (nl < 0) {
            nl = -nl;
        }
        lo = off + 2u + (size_t)nl;
        link = dec_u16(proc, ps->p + lo);
        last = lo;
        off = lo + link;
    }
    if (last != (size_t)-1) {
        enc_u16(proc, 0u, ps->p + last);
    }
}

int c3d_write_added(const unsigned char *buf, size_t len, const c3d_t *c, const c3d_add_t *add,
                    const char *out_path, int *to_float_out, char *err)
{
    const int proc = c->processor, old_word = c->word;
    int to_float = 0, word, i, rc = -1;
    long f;
    family_t lab, des;
    int have_des;
    bbuf_t ps, data;
    unsigned pblock, nblocks, data_block;
    size_t npts_bytes, hdr_gap, pstart;
    unsigned char hdr[W_BLOCK], w[4];
    FILE *fo;
    int unsigned_analog = 0;
    size_t room;

    memset(&ps, 0, sizeof ps);
    memset(&data, 0, sizeof data);
    memset(&lab, 0, sizeof lab);
    memset(&des, 0, sizeof des);
    if (to_float_out != NULL) {
        *to_float_out = 0;
    }
    if (add == NULL || add->n < 1 || add->names == NULL || add->xyz == NULL) {
        return wfail(err, "no points to add");
    }
    pstart = (c->param_start > 0u) ? c->param_start : ((size_t)buf[0] - 1u) * W_BLOCK;
    if (pstart < W_BLOCK || pstart > c->data_start) {
        return wfail(err, "the parameter block %u is not between the header and the data",
                     (unsigned)buf[0]);
    }
    if ((long)c->npoints + add->n > 65535) {
        return wfail(err, "%d + %d points: more than a C3D file holds (65535)", c->npoints, add->n);
    }
    if (c->data_start + (size_t)c->nframes * c->frame_bytes > len) {
        return wfail(err, "the recording is shorter than its frames");
    }
    for (i = 0; i < add->n; i++) {
        if (add->names[i] == NULL || add->names[i][0] == '\0') {
            return wfail(err, "new point %d has no name", i + 1);
        }
    }
    /* integer storage holds |v / scale| <= 32767 */
    if (old_word == 2) {
        const size_t nv = (size_t)c->nframes * (size_t)add->n * 3u;
        size_t j;
        for (j = 0; j < nv; j++) {
            const float v = add->xyz[j];
            if (isfinite(v) && !(fabs((double)v / (double)c->scale) <= 32767.0)) {
                to_float = 1;
                break;
            }
        }
    }
    word = to_float ? 4 : old_word;
    {
        const c3d_entry_t *fmt = c3d_param(c, "ANALOG", "FORMAT");
        if (fmt != NULL && fmt->type == -1 && fmt->count >= 8u
            && memcmp(buf + fmt->data, "UNSIGNED", 8u) == 0) {
            unsigned_analog = 1;
        }
    }
    room = (size_t)c->npoints + (size_t)add->n;
    if (family_load(buf, c, "LABELS", room, &lab) != 0
        || family_load(buf, c, "DESCRIPTIONS", room, &des) != 0) {
        family_free(&lab);
        family_free(&des);
        return wfail(err, "out of memory");
    }
    have_des = des.nch > 0;
    if (family_insert(&lab, (size_t)c->npoints, add->names, add->n, add->prefix,
                      lab.total + room) != 0
        || (have_des
            && family_insert(&des, (size_t)c->npoints, add->descs, add->n, NULL, des.total + room)
                   != 0)) {
        family_free(&lab);
        family_free(&des);
        return wfail(err, "cannot add %d labels (memory, or more than %d label parameters)",
                     add->n, W_MAX_CHUNKS);
    }
    /* the parameter section, twice: its size fixes the data block */
    pblock = (unsigned)(pstart / W_BLOCK) + 1u;
    data_block = (unsigned)(c->data_start / W_BLOCK) + 1u;
    for (i = 0; i < 2; i++) {
        ps.n = 0;
        if (build_params(buf, c, add, &lab, have_des ? &des : NULL, data_block, to_float, &ps, err)
            != 0) {
            goto out;
        }
        nblocks = (unsigned)((4u + ps.n + 2u + W_BLOCK - 1u) / W_BLOCK);
        if (pblock + nblocks > data_block) {
            data_block = pblock + nblocks;
        }
    }
    nblocks = (unsigned)((4u + ps.n + 2u + W_BLOCK - 1u) / W_BLOCK);
    if (nblocks > 255u || data_block > 65535u) {
        (void)wfail(err, "the parameter section would need %u blocks (at most 255)", nblocks);
        goto out;
    }
    terminate_links(&ps, proc);

    /* header: points, data block, scale when converted */
    memcpy(hdr, buf, W_BLOCK);
    enc_u16(proc, (unsigned)(c->npoints + add->n), hdr + 2);
    enc_u16(proc, data_block, hdr + 16);
    if (to_float) {
        (void)enc_f32(proc, -fabsf(c->scale), hdr + 12);
    }
    /* the header's analog words per frame: the layout written (where the
     * reader took the parameters' layout by the data section's size) */
    if (c->analog_words >= 0L && c->analog_words <= 65535L
        && dec_u16(proc, hdr + 4) != (unsigned)c->analog_words) {
        enc_u16(proc, (unsigned)c->analog_words, hdr + 4);
    }
    /* the header's last frame: the frames written (a header that says more
     * would have a reader take the last block's padding for frames) */
    {
        const unsigned first = dec_u16(proc, hdr + 6);
        if (c->nframes >= 1L && (long)first + c->nframes - 1L <= 65535L) {
            enc_u16(proc, (unsigned)((long)first + c->nframes - 1L), hdr + 8);
        }
    }
    /* frames */
    npts_bytes = 4u * (size_t)c->npoints * (size_t)old_word;
    for (f = 0; f < c->nframes; f++) {
        const unsigned char *fr = buf + c->data_start + (size_t)f * c->frame_bytes;
        const unsigned char *an = fr + npts_bytes;
        long k;
        if (!to_float) {
            put(&data, fr, npts_bytes);
        } else {
            for (k = 0; k < 4L * c->npoints; k++) {
                const int v = dec_i16(proc, fr + 2 * k);
                const float x = ((k & 3) == 3) ? (float)v : (float)v * c->scale;
                (void)enc_f32(proc, x, w);
                put(&data, w, 4u);
            }
        }
        for (i = 0; i < add->n; i++) {
            const float *p = add->xyz + ((size_t)f * (size_t)add->n + (size_t)i) * 3u;
            const int ok = isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
            int j;
            for (j = 0; j < 4; j++) {
                const float v = (j == 3) ? (ok ? 0.0f : -1.0f) : (ok ? p[j] : 0.0f);
                if (word == 4) {
                    if (enc_f32(proc, v, w) != 0) {
                        (void)wfail(err, "new point %s: %g cannot be stored as a DEC float",
                                    add->names[i], (double)v);
                        goto out;
                    }
                    put(&data, w, 4u);
                } else {
                    const long q = (j == 3) ? (long)v : lround((double)v / (double)c->scale);
                    enc_u16(proc, (unsigned)(q & 0xffff), w);
                    put(&data, w, 2u);
                }
            }
        }
        if (!to_float) {
            put(&data, an, (size_t)c->analog_words * (size_t)old_word);
        } else {
            for (k = 0; k < c->analog_words; k++) {
                const unsigned u = dec_u16(proc, an + 2 * k);
                const float v = unsigned_analog ? (float)u : (float)dec_i16(proc, an + 2 * k);
                (void)enc_f32(proc, v, w);
                put(&data, w, 4u);
            }
        }
    }
    if (data.oom || ps.oom) {
        (void)wfail(err, "out of memory");
        goto out;
    }
    fo = fopen(out_path, "wb");
    if (fo == NULL) {
        (void)wfail(err, "cannot write %s: %s", out_path, strerror(errno));
        goto out;
    }
    {
        static const unsigned char zero[W_BLOCK];
        unsigned char head[4];
        size_t written = 0, pad;
        hdr_gap = pstart - W_BLOCK; /* blocks between the header and the parameters */
        written += fwrite(hdr, 1u, W_BLOCK, fo);
        written += fwrite(buf + W_BLOCK, 1u, hdr_gap, fo);
        if (c->param_start > 0u) {
            memcpy(head, buf + c->param_start, 4u);
        } else { /* no parameter section before: a new one */
            head[0] = 1u;
            head[1] = 0x50u;
            head[3] = (unsigned char)proc;
        }
        head[2] = (unsigned char)nblocks;
        written += fwrite(head, 1u, 4u, fo);
        written += fwrite(ps.p, 1u, ps.n, fo);
        pad = ((size_t)data_block - 1u) * W_BLOCK - (W_BLOCK + hdr_gap + 4u + ps.n);
        while (pad > 0u) {
            const size_t m = pad < W_BLOCK ? pad : W_BLOCK;
            written += fwrite(zero, 1u, m, fo);
            pad -= m;
        }
        written += fwrite(data.p, 1u, data.n, fo);
        pad = (W_BLOCK - data.n % W_BLOCK) % W_BLOCK;
        written += fwrite(zero, 1u, pad, fo);
        if (fclose(fo) != 0 || written != ((size_t)data_block - 1u) * W_BLOCK + data.n + pad) {
            (void)wfail(err, "cannot write %s", out_path);
            goto out;
        }
    }
    if (to_float_out != NULL) {
        *to_float_out = to_float;
    }
    rc = 0;
out:
    family_free(&lab);
    family_free(&des);
    free(ps.p);
    free(data.p);
    return rc;
}

int c3d_write_added_file(const char *in_path, const char *out_path, const c3d_add_t *add,
                         int *to_float, char *err)
{
    unsigned char *buf;
    size_t len;
    c3d_t c;
    int rc;
    if (c3d_load_bytes(in_path, &buf, &len, err) != 0) {
        return -1;
    }
    rc = c3d_parse(buf, len, &c, err);
    if (rc == 0) {
        rc = c3d_write_added(buf, len, &c, add, out_path, to_float, err);
    }
    c3d_free(&c);
    free(buf);
    return rc;
}

/* ------------------------------------------------------------------ TRC */
static void trc_cell3(FILE *f, const float *p)
{
    if (isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])) {
        fprintf(f, "\t%.9g\t%.9g\t%.9g", (double)p[0], (double)p[1], (double)p[2]);
    } else {
        fputs("\t\t\t", f);
    }
}

int c3d_write_trc(const char *path, const c3d_t *c, const c3d_add_t *add, char *err)
{
    FILE *f;
    const int nadd = (add != NULL) ? add->n : 0;
    const char *base = strrchr(path, '/');
    const char *units = c->units[0] != '\0' ? c->units : "mm";
    long fr;
    int k;
    if (!(c->rate > 0.0f)) {
        return wfail(err, "a TRC file needs a frame rate; the recording has none");
    }
    f = fopen(path, "w");
    if (f == NULL) {
        return wfail(err, "cannot write %s: %s", path, strerror(errno));
    }
    fprintf(f, "PathFileType\t4\t(X/Y/Z)\t%s\n", base != NULL ? base + 1 : path);
    fprintf(f, "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\t"
               "OrigDataStartFrame\tOrigNumFrames\n");
    fprintf(f, "%.9g\t%.9g\t%ld\t%d\t%s\t%.9g\t%ld\t%ld\n", (double)c->rate, (double)c->rate,
            c->nframes, c->npoints + nadd, units, (double)c->rate, c->first_frame, c->nframes);
    fputs("Frame#\tTime", f);
    for (k = 0; k < c->npoints; k++) {
        fprintf(f, "\t%s\t\t", c->labels[k]);
    }
    for (k = 0; k < nadd; k++) {
        fprintf(f, "\t%s%s\t\t", add->prefix != NULL ? add->prefix : "", add->names[k]);
    }
    fputs("\n\t", f);
    for (k = 0; k < c->npoints + nadd; k++) {
        fprintf(f, "\tX%d\tY%d\tZ%d", k + 1, k + 1, k + 1);
    }
    fputs("\n\n", f);
    for (fr = 0; fr < c->nframes; fr++) {
        fprintf(f, "%ld\t%.9g", fr + 1, (double)fr / (double)c->rate);
        for (k = 0; k < c->npoints; k++) {
            trc_cell3(f, c->xyz + ((size_t)fr * (size_t)c->npoints + (size_t)k) * 3u);
        }
        for (k = 0; k < nadd; k++) {
            trc_cell3(f, add->xyz + ((size_t)fr * (size_t)nadd + (size_t)k) * 3u);
        }
        fputc('\n', f);
    }
    if (fclose(f) != 0) {
        return wfail(err, "cannot write %s", path);
    }
    return 0;
}
