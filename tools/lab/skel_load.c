/* SPDX-License-Identifier: MIT */
/**
 * @file skel_load.c
 * @brief The trials of a session (several C3D files, frames concatenated)
 * and the session model's segment / joint / root lines (SESSION_MODEL.md
 * format; the full parser of `sfit calibrate` is issue 29's).
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "skel.h"

/* 2^SFIT_COORD_MAX_EXP (sfit_config.h): larger coordinates are refused by the library */
#define SKEL_COORD_MAX ((float)(1UL << SFIT_COORD_MAX_EXP))

static int find_label(const skel_rec_t *r, const char *name)
{
    int i;
    for (i = 0; i < r->nmark; i++) {
        if (strcmp(r->label[i], name) == 0) {
            return i;
        }
    }
    return -1;
}

void skel_rec_free(skel_rec_t *r)
{
    free(r->label);
    free(r->xyz);
    memset(r, 0, sizeof *r);
}

int skel_rec_load(skel_rec_t *r, const char *const *files, int nfiles, const char *const *names,
                  int n, long step, char *why)
{
    c3d_t *c;
    char err[C3D_ERR_MAX];
    int k, i;
    long total = 0;
    memset(r, 0, sizeof *r);
    if (nfiles < 1 || nfiles > SKEL_MAX_FILES || step < 1) {
        (void)snprintf(why, SKEL_ERR, "1 to %d files", SKEL_MAX_FILES);
        return -1;
    }
    c = calloc((size_t)nfiles, sizeof *c);
    r->label = calloc(SKEL_MAX_MARK, sizeof *r->label);
    if (c == NULL || r->label == NULL) {
        free(c);
        skel_rec_free(r);
        (void)snprintf(why, SKEL_ERR, "out of memory");
        return -1;
    }
    r->nfiles = nfiles;
    for (i = 0; i < n; i++) {
        if (r->nmark >= SKEL_MAX_MARK) {
            (void)snprintf(why, SKEL_ERR, "more than %d markers", SKEL_MAX_MARK);
            goto fail;
        }
        if (find_label(r, names[i]) < 0) {
            (void)snprintf(r->label[r->nmark++], SKEL_NAME, "%s", names[i]);
        }
    }
    for (k = 0; k < nfiles; k++) {
        r->file[k] = files[k];
        if (c3d_read_file(files[k], &c[k], err) != 0) {
            (void)snprintf(why, SKEL_ERR, "%.80s: %.170s", files[k], err);
            goto fail;
        }
        if (k == 0) {
            r->rate = c[k].rate / (float)step;
            (void)snprintf(r->units, sizeof r->units, "%s", c[k].units);
        }
        if (n == 0) {
            for (i = 0; i < c[k].npoints; i++) {
                if (c[k].labels[i][0] != '\0' && find_label(r, c[k].labels[i]) < 0) {
                    if (r->nmark >= SKEL_MAX_MARK) {
                        (void)snprintf(why, SKEL_ERR, "more than %d markers", SKEL_MAX_MARK);
                        goto fail;
                    }
                    (void)snprintf(r->label[r->nmark++], SKEL_NAME, "%s", c[k].labels[i]);
                }
            }
        }
        r->start[k] = total;
        total += (c[k].nframes + step - 1) / step;
    }
    r->start[nfiles] = total;
    r->nframes = total;
    if (total < 1 || r->nmark < 1) {
        (void)snprintf(why, SKEL_ERR, "no frame or no marker");
        goto fail;
    }
    r->xyz = malloc((size_t)total * (size_t)r->nmark * 3u * sizeof *r->xyz);
    if (r->xyz == NULL) {
        (void)snprintf(why, SKEL_ERR, "out of memory");
        goto fail;
    }
    for (i = 0; i < r->nmark; i++) { /* every marker asked for is in some file */
        int found = 0;
        for (k = 0; k < nfiles && !found; k++) {
            found = c3d_find(&c[k], r->label[i]) >= 0;
        }
        if (!found) {
            (void)snprintf(why, SKEL_ERR, "marker %s is in none of the files", r->label[i]);
            goto fail;
        }
    }
    for (k = 0; k < nfiles; k++) {
        int col[SKEL_MAX_MARK];
        long f, g;
        int seen = 0;
        for (i = 0; i < r->nmark; i++) {
            col[i] = c3d_find(&c[k], r->label[i]);
            seen += col[i] >= 0;
        }
        if (seen == 0) {
            (void)snprintf(why, SKEL_ERR, "%s: none of the markers", files[k]);
            goto fail;
        }
        for (f = 0, g = r->start[k]; f < c[k].nframes; f += step, g++) {
            for (i = 0; i < r->nmark; i++) {
                float *dst = r->xyz + ((size_t)g * (size_t)r->nmark + (size_t)i) * 3u;
                if (col[i] >= 0) {
                    memcpy(dst, c[k].xyz + ((size_t)f * (size_t)c[k].npoints + (size_t)col[i]) * 3u,
                           3u * sizeof *dst);
                    /* beyond the library's coordinate range or not finite: unseen */
                    if (isnan(dst[0]) || isnan(dst[1]) || isnan(dst[2])) {
                        dst[0] = dst[1] = dst[2] = NAN; /* missing */
                    } else if (!(fabsf(dst[0]) < SKEL_COORD_MAX)
                               || !(fabsf(dst[1]) < SKEL_COORD_MAX)
                               || !(fabsf(dst[2]) < SKEL_COORD_MAX)) {
                        dst[0] = dst[1] = dst[2] = NAN;
                        r->dropped++;
                    }
                } else {
                    dst[0] = dst[1] = dst[2] = NAN;
                }
            }
        }
    }
    for (k = 0; k < nfiles; k++) {
        c3d_free(&c[k]);
    }
    free(c);
    return 0;
fail:
    for (k = 0; k < nfiles; k++) {
        c3d_free(&c[k]);
    }
    free(c);
    skel_rec_free(r);
    return -1;
}

/* ----------------------------------------------------------------- map */

static int split_list(char *s, char out[][SKEL_NAME], int max)
{
    int n = 0;
    char *p = s;
    for (;;) {
        char *q = strchr(p, ',');
        if (q != NULL) {
            *q = '\0';
        }
        if (*p == '\0' || n >= max || strlen(p) >= SKEL_NAME) {
            return -1;
        }
        (void)snprintf(out[n++], SKEL_NAME, "%s", p);
        if (q == NULL) {
            return n;
        }
        p = q + 1;
    }
}

int skel_map_load(const char *path, skel_map_t *m, char *why)
{
    FILE *f = fopen(path, "r");
    char line[4096];
    unsigned long lineno = 0;
    memset(m, 0, sizeof *m);
    if (f == NULL) {
        return -1;
    }
    while (fgets(line, sizeof line, f) != NULL) {
        char *tok[8];
        int nt = 0;
        char *p;
        lineno++;
        p = strchr(line, '#');
        if (p != NULL) {
            *p = '\0';
        }
        for (p = strtok(line, " \t\r\n"); p != NULL && nt < 8; p = strtok(NULL, " \t\r\n")) {
            tok[nt++] = p;
        }
        if (nt == 0) {
            continue;
        }
        if (strcmp(tok[0], "segment") == 0 && nt == 3 && m->nseg >= SKEL_MAX_SEG) {
            (void)snprintf(why, SKEL_ERR, "line %lu: more than %d segments", lineno,
                           SKEL_MAX_SEG);
            fclose(f);
            return -2;
        }
        if (strcmp(tok[0], "segment") == 0 && nt == 3 && strlen(tok[1]) < SKEL_NAME) {
            const int k = m->nseg;
            int d;
            for (d = 0; d < k; d++) {
                if (strcmp(m->seg[d], tok[1]) == 0) {
                    (void)snprintf(why, SKEL_ERR, "line %lu: segment %s given twice", lineno,
                                   tok[1]);
                    fclose(f);
                    return -2;
                }
            }
            (void)snprintf(m->seg[k], SKEL_NAME, "%s", tok[1]);
            m->nm[k] = split_list(tok[2], m->mk[k], SFIT_CLUSTER_MAX_MARKERS * 4);
            if (m->nm[k] < 3) {
                (void)snprintf(why, SKEL_ERR, "line %lu: a segment needs 3 to %d markers", lineno, SFIT_CLUSTER_MAX_MARKERS * 4);
                fclose(f);
                return -2;
            }
            m->nseg++;
        } else if (strcmp(tok[0], "root") == 0 && nt == 2 && strlen(tok[1]) < SKEL_NAME) {
            (void)snprintf(m->root, SKEL_NAME, "%s", tok[1]);
        } else if (strcmp(tok[0], "landmarks") == 0 && nt == 3) {
            /* the session's centre convention (sfit calibrate); the skeleton
             * reports the functional centres */
        } else if (strcmp(tok[0], "joint") == 0 && (nt == 6 || nt == 7)
                   && m->njoint < SKEL_MAX_SEG && strlen(tok[1]) < SKEL_NAME
                   && strlen(tok[2]) < SKEL_NAME && strlen(tok[3]) < SKEL_NAME
                   && (strcmp(tok[4], "auto") == 0 || strcmp(tok[4], "ball") == 0
                       || strcmp(tok[4], "hinge") == 0)) {
            const int k = m->njoint++;
            (void)snprintf(m->jname[k], SKEL_NAME, "%s", tok[1]);
            (void)snprintf(m->jpar[k], SKEL_NAME, "%s", tok[2]);
            (void)snprintf(m->jchi[k], SKEL_NAME, "%s", tok[3]);
            (void)snprintf(m->jtype[k], sizeof m->jtype[k], "%s", tok[4]);
            (void)snprintf(m->jtrial[k], SKEL_NAME, "%s", nt == 7 ? tok[6] : "");
        } else {
            (void)snprintf(why, SKEL_ERR,
                           "line %lu: expected `segment NAME M1,M2,M3[,...]`, `joint NAME PARENT "
                           "CHILD auto|ball|hinge POINTS [TRIALS]`, `landmarks JOINT M1,M2` or "
                           "`root SEGMENT`",
                           lineno);
            fclose(f);
            return -2;
        }
    }
    fclose(f);
    if (m->nseg < 2) {
        (void)snprintf(why, SKEL_ERR, "fewer than 2 segments");
        return -2;
    }
    return 0;
}
