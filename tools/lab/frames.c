/* SPDX-License-Identifier: MIT */
/** @file frames.c  Named marker trajectories from C3D or a wide table (frames.h). */
#include "frames.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "table.h"

int frames_parse_range(const char *s, long *first, long *last)
{
    char *end;
    long a, b;
    errno = 0;
    a = strtol(s, &end, 10);
    if (end == s || *end != ':' || a < 0) {
        return 1;
    }
    s = end + 1;
    b = strtol(s, &end, 10); /* errno of an overflow of F is still set */
    if (end == s || *end != '\0' || b < a || errno != 0) {
        return 2;
    }
    *first = a;
    *last = b;
    return 0;
}

int frames_split_list(char *s, char **items, int max)
{
    int n = 0;
    for (;;) {
        char *comma = strchr(s, ',');
        if (comma != NULL) {
            *comma = '\0';
        }
        if (*s == '\0' || n >= max) {
            return -1;
        }
        items[n++] = s;
        if (comma == NULL) {
            return n;
        }
        s = comma + 1;
    }
}

void frames_free(frames_data_t *fr)
{
    free(fr->xyz);
    free(fr->all_labels);
    free(fr->all_xyz);
    memset(fr, 0, sizeof *fr);
}

/* C3D: the name ends in .c3d, or the header's key byte is 0x50 and the
 * parameter section's processor byte is 84..86. 1 yes, 0 no, -1 no file. */
static int is_c3d_file(const char *path)
{
    unsigned char head[2] = {0, 0};
    const size_t len = strlen(path);
    FILE *f = fopen(path, "rb");
    int proc = -1;
    if (f == NULL) {
        return -1;
    }
    if (len >= 4u && (strcmp(path + len - 4u, ".c3d") == 0 || strcmp(path + len - 4u, ".C3D") == 0)) {
        fclose(f);
        return 1;
    }
    if (fread(head, 1u, 2u, f) == 2u && c3d_sniff(head, 2u)
        && fseek(f, ((long)head[0] - 1L) * 512L + 3L, SEEK_SET) == 0) {
        proc = fgetc(f);
    }
    fclose(f);
    return proc >= 84 && proc <= 86;
}

/* 1 when path's warnings were printed already by this process (the last
 * 16 files remembered), else remembers it and gives 0. */
static int warned_before(const char *path)
{
    static char seen[16][256];
    static unsigned next;
    unsigned i;
    for (i = 0; i < 16u; i++) {
        if (seen[i][0] != '\0' && strncmp(seen[i], path, sizeof seen[i] - 1u) == 0) {
            return 1;
        }
    }
    (void)snprintf(seen[next % 16u], sizeof seen[0], "%s", path);
    next++;
    return 0;
}

static int load_c3d(const char *path, const char *const *names, int n, frames_data_t *out,
                    char *why)
{
    c3d_t c;
    char err[C3D_ERR_MAX];
    int k;
    int idx[FRAMES_MARKERS_MAX];
    long f;
    if (c3d_read_file(path, &c, err) != 0) {
        (void)snprintf(why, FRAMES_ERR_MAX, "%s", err);
        return -2;
    }
    if (!warned_before(path)) { /* a file read for several joints warns once */
        for (k = 0; k < c.nwarn; k++) { /* what was read differently from one source */
            fprintf(stderr, "sfit: warning: %s: %s\n", path, c.warnings[k]);
        }
    }
    for (k = 0; k < n; k++) {
        idx[k] = c3d_find(&c, names[k]);
        if (idx[k] < 0) {
            (void)snprintf(why, FRAMES_ERR_MAX, "no marker labelled '%s' in the C3D file",
                           names[k]);
            c3d_free(&c);
            return -2;
        }
    }
    out->is_c3d = 1;
    out->nmarkers = n;
    out->nframes = c.nframes;
    out->rate = c.rate;
    (void)snprintf(out->units, sizeof out->units, "%s", c.units);
    out->xyz = malloc(((size_t)c.nframes * (size_t)n + 1u) * sizeof *out->xyz);
    if (out->xyz == NULL) {
        c3d_free(&c);
        (void)snprintf(why, FRAMES_ERR_MAX, "out of memory");
        return -2;
    }
    for (f = 0; f < c.nframes; f++) {
        for (k = 0; k < n; k++) {
            const float *p = c.xyz + ((size_t)f * (size_t)c.npoints + (size_t)idx[k]) * 3u;
            sfit_vec3_t *d = &out->xyz[(size_t)f * (size_t)n + (size_t)k];
            if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f) {
                d->v[0] = d->v[1] = d->v[2] = NAN; /* (0, 0, 0): "missing" in some systems */
                out->zero_missing++;
                continue;
            }
            d->v[0] = p[0];
            d->v[1] = p[1];
            d->v[2] = p[2];
        }
    }
    /* keep every point for pictures */
    out->nall = c.npoints;
    out->all_labels = c.labels;
    out->all_xyz = c.xyz;
    c.labels = NULL;
    c.xyz = NULL;
    c3d_free(&c);
    return 0;
}

static int load_table(const char *path, const char *const *names, int n, frames_data_t *out,
                      char *why)
{
    table_t t;
    int cols[3 * FRAMES_MARKERS_MAX];
    float vals[3 * FRAMES_MARKERS_MAX];
    size_t cap = 0;
    int k, rc;
    if (table_open_file(&t, path) != 0) {
        return -1;
    }
    if (table_start(&t) != 0) {
        (void)snprintf(why, FRAMES_ERR_MAX, "%s", t.err);
        table_close(&t);
        return -2;
    }
    if (!t.header) {
        (void)snprintf(why, FRAMES_ERR_MAX,
                       "neither a C3D file nor a table with a header naming the markers' "
                       "columns (NAME_X, NAME_Y, NAME_Z)");
        table_close(&t);
        return -2;
    }
    for (k = 0; k < n; k++) {
        if (table_find_marker(&t, names[k], &cols[3 * k]) != 0) {
            (void)snprintf(why, FRAMES_ERR_MAX,
                           "no columns %s_X, %s_Y, %s_Z (or %s.x, %s:X, ...) in the header",
                           names[k], names[k], names[k], names[k], names[k]);
            table_close(&t);
            return -2;
        }
    }
    if (table_select_idx(&t, cols, 3 * n) != 0) {
        (void)snprintf(why, FRAMES_ERR_MAX, "%s", t.err);
        table_close(&t);
        return -2;
    }
    out->nmarkers = n;
    while ((rc = table_next(&t, vals)) != TABLE_EOF) {
        sfit_vec3_t *row;
        if ((size_t)out->nframes == cap) {
            const size_t nc = (cap == 0u) ? 1024u : 2u * cap;
            sfit_vec3_t *nx = realloc(out->xyz, nc * (size_t)n * sizeof *nx);
            if (nx == NULL) {
                table_close(&t);
                (void)snprintf(why, FRAMES_ERR_MAX, "out of memory");
                return -2;
            }
            out->xyz = nx;
            cap = nc;
        }
        row = &out->xyz[(size_t)out->nframes * (size_t)n];
        for (k = 0; k < 3 * n; k++) {
            row[k / 3].v[k % 3] = (rc == TABLE_ROW_OK) ? vals[k] : NAN;
        }
        if (rc != TABLE_ROW_OK) {
            out->bad_rows++;
        }
        out->nframes++;
    }
    table_close(&t);
    return 0;
}

int frames_load(const char *path, const char *const *names, int n, frames_data_t *out,
                    char *why)
{
    int c3d, rc;
    memset(out, 0, sizeof *out);
    why[0] = '\0';
    if (n < 1 || n > FRAMES_MARKERS_MAX) {
        (void)snprintf(why, FRAMES_ERR_MAX, "1 to %d markers", FRAMES_MARKERS_MAX);
        return -2;
    }
    c3d = (strcmp(path, "-") == 0) ? 0 : is_c3d_file(path);
    if (c3d < 0) {
        return -1;
    }
    rc = c3d ? load_c3d(path, names, n, out, why) : load_table(path, names, n, out, why);
    if (rc != 0) {
        const int e = errno;
        frames_free(out);
        errno = e;
    }
    return rc;
}
