/* SPDX-License-Identifier: MIT */
/**
 * @file c3d_param.c
 * @brief The C3D reader's parameter section and point labels (c3d.h,
 * docs/c3d.md; the layout is described in c3d.c). Every read goes through
 * the bounds-checked readers of c3d_in.h.
 */
#include "c3d_in.h"

#include <stdlib.h>

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

/* Walk the whole parameter section once, bounded by `bound` (its declared
 * size, or the data section's start when the entries run past that size).
 * A link that leads nowhere, where neither the other byte order nor the
 * entry's own length gives a next entry, ends the walk (`end`). */
int c3d_walk_params(const c3d_in_t *in, size_t start, size_t bound, c3d_t *c,
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
int c3d_param_number_at(const c3d_in_t *in, const c3d_entry_t *p, size_t i, double *v)
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
long c3d_param_count(const c3d_in_t *in, const c3d_entry_t *p)
{
    double v;
    if (c3d_param_number_at(in, p, 0u, &v) != 0) {
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
long c3d_param_field(const c3d_in_t *in, const c3d_entry_t *p)
{
    double lo, hi;
    if (p == NULL || p->type != 2 || c3d_param_number_at(in, p, 0u, &lo) != 0
        || c3d_param_number_at(in, p, 1u, &hi) != 0) {
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
void c3d_copy_label(const unsigned char *s, size_t len, char *dst, size_t size)
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

void c3d_read_labels(const c3d_in_t *in, c3d_t *c)
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
            c3d_copy_label(in->b + l->data + i * len, len, c->labels[next++], C3D_LABEL_MAX);
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
int c3d_rename_duplicates(c3d_t *c)
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
