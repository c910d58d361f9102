/* SPDX-License-Identifier: MIT */
/**
 * @file skel_write.c
 * @brief The skeleton's BVH and TRC files (docs/skeleton.md).
 *
 * BVH: one node per segment in the tree, named after the segment (a
 * bone's rotation is its segment's); the ROOT is the root segment at its
 * markers' centroid, OFFSET 0 0 0, channels Xposition Yposition Zposition
 * Zrotation Xrotation Yrotation; every JOINT sits at its joint centre,
 * OFFSET = that centre minus the parent node's, in the parent segment's
 * frame, channels Zrotation Xrotation Yrotation (R = Rz Ry Rx applied in
 * that order: R = Rz(z) Rx(x) Ry(y), degrees); a leaf ends in an End Site
 * at its markers' centroid. Units: the recording's (the C3D POINT:UNITS).
 */
#include <errno.h>
#include <math.h>
#include <string.h>

#include <stdlib.h>

#include "c3d_write.h"
#include "skel.h"

static int close_checked(FILE *f, const char *path)
{
    if (ferror(f) != 0 || fclose(f) != 0) {
        fprintf(stderr, "sfit: cannot write %s\n", path);
        return -1;
    }
    return 0;
}

static FILE *open_out(const char *path)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "sfit: cannot write %s: %s\n", path, strerror(errno));
    }
    return f;
}

static void indent(FILE *f, int d)
{
    int i;
    for (i = 0; i < d; i++) {
        fputc('\t', f);
    }
}

/* Depth-first hierarchy, without recursion: an explicit stack. */
static void bvh_hierarchy(const skel_t *s, FILE *f, int *dfs, int *ndfs)
{
    int stack[SKEL_MAX_SEG], next[SKEL_MAX_SEG], depth = 0, i;
    stack[0] = s->root;
    next[0] = 0;
    fprintf(f, "HIERARCHY\nROOT %s\n{\n\tOFFSET 0.000000 0.000000 0.000000\n"
               "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n",
            s->seg[s->root].name);
    dfs[(*ndfs)++] = s->root;
    while (depth >= 0) {
        const int p = stack[depth];
        int c = -1;
        for (i = next[depth]; i < s->njoint; i++) {
            if (s->joint[i].parent == p) {
                c = s->joint[i].child;
                next[depth] = i + 1;
                break;
            }
        }
        if (c < 0) {
            int leaf = 1;
            for (i = 0; i < s->njoint; i++) {
                leaf &= (s->joint[i].parent != p);
            }
            if (leaf) {
                indent(f, depth + 1);
                fputs("End Site\n", f);
                indent(f, depth + 1);
                fputs("{\n", f);
                indent(f, depth + 2);
                fprintf(f, "OFFSET %.6f %.6f %.6f\n", s->end_site[p][0], s->end_site[p][1],
                        s->end_site[p][2]);
                indent(f, depth + 1);
                fputs("}\n", f);
            }
            indent(f, depth);
            fputs("}\n", f);
            depth--;
            continue;
        }
        {
            const int j = s->parent_joint[c];
            const int jp = s->parent_joint[p];
            double off[3];
            for (i = 0; i < 3; i++) {
                off[i] = s->joint[j].pr.ca[i] - (jp >= 0 ? s->joint[jp].pr.cb[i] : 0.0);
            }
            indent(f, depth + 1);
            fprintf(f, "JOINT %s\n", s->seg[c].name);
            indent(f, depth + 1);
            fputs("{\n", f);
            indent(f, depth + 2);
            fprintf(f, "OFFSET %.6f %.6f %.6f\n", off[0], off[1], off[2]);
            indent(f, depth + 2);
            fputs("CHANNELS 3 Zrotation Xrotation Yrotation\n", f);
            dfs[(*ndfs)++] = c;
            depth++;
            stack[depth] = c;
            next[depth] = 0;
        }
    }
}

int skel_write_bvh(const skel_t *s, const char *path)
{
    FILE *f = open_out(path);
    int dfs[SKEL_MAX_SEG], ndfs = 0, k;
    long fr;
    if (f == NULL) {
        return -1;
    }
    bvh_hierarchy(s, f, dfs, &ndfs);
    fprintf(f, "MOTION\nFrames: %ld\nFrame Time: %.8f\n", s->rec->nframes,
            s->rec->rate > 0.0f ? 1.0 / (double)s->rec->rate : 1.0);
    for (fr = 0; fr < s->rec->nframes; fr++) {
        fprintf(f, "%.6f %.6f %.6f", s->root_t[fr * 3], s->root_t[fr * 3 + 1],
                s->root_t[fr * 3 + 2]);
        for (k = 0; k < ndfs; k++) {
            double e[3];
            skel_euler_zxy(&s->rel[((size_t)fr * (size_t)s->nseg + (size_t)dfs[k]) * 9u], e);
            fprintf(f, " %.7f %.7f %.7f", e[0], e[1], e[2]);
        }
        fputc('\n', f);
    }
    return close_checked(f, path);
}

/* TRC (OpenSim marker file) of the joint centres: the root node and every
 * joint, by the TRC writer of issue 27 (c3d_write.h) with no recorded marker. */
int skel_write_trc(const skel_t *s, const char *path)
{
    const long nf = s->rec->nframes;
    const int np = s->njoint + 1;
    const char **names = malloc((size_t)np * sizeof *names);
    float *xyz = malloc((size_t)nf * (size_t)np * 3u * sizeof *xyz);
    c3d_t c;
    c3d_add_t add;
    char err[C3D_ERR_MAX];
    long fr;
    int k, i, rc;
    if (names == NULL || xyz == NULL) {
        free(names);
        free(xyz);
        fprintf(stderr, "sfit: out of memory\n");
        return -1;
    }
    names[0] = s->seg[s->root].name;
    for (k = 0; k < s->njoint; k++) {
        names[k + 1] = s->joint[k].name;
    }
    for (fr = 0; fr < nf; fr++) {
        float *row = xyz + (size_t)fr * (size_t)np * 3u;
        for (i = 0; i < 3; i++) {
            row[i] = (float)s->root_t[fr * 3 + i];
        }
        for (k = 0; k < s->njoint; k++) {
            for (i = 0; i < 3; i++) {
                row[(k + 1) * 3 + i] =
                    (float)s->jc[((size_t)fr * (size_t)s->njoint + (size_t)k) * 3u + (size_t)i];
            }
        }
    }
    memset(&c, 0, sizeof c);
    c.nframes = nf;
    c.first_frame = 1;
    c.rate = s->rec->rate > 0.0f ? s->rec->rate : 1.0f;
    (void)snprintf(c.units, sizeof c.units, "%s", s->rec->units);
    memset(&add, 0, sizeof add);
    add.n = np;
    add.names = names;
    add.xyz = xyz;
    rc = c3d_write_trc(path, &c, &add, err);
    if (rc != 0) {
        fprintf(stderr, "sfit: %s\n", err);
    }
    free(names);
    free(xyz);
    return rc;
}

/* Every joint's centre as its parent segment carries it (R_p c_p + t_p) per
 * frame, and a hinge's axis (R_p w): the data, before the skeleton's fixed
 * bone lengths (the TRC); blank where the parent has no pose. */
int skel_write_centres(const skel_t *s, const char *path)
{
    FILE *f = open_out(path);
    long fr;
    int k, i;
    if (f == NULL) {
        return -1;
    }
    fputs("frame", f);
    for (k = 0; k < s->njoint; k++) {
        const char *n = s->joint[k].name;
        fprintf(f, ",%s_X,%s_Y,%s_Z", n, n, n);
        if (s->joint[k].pr.type == SKEL_HINGE) {
            fprintf(f, ",%s_AX,%s_AY,%s_AZ", n, n, n);
        }
    }
    fputc('\n', f);
    for (fr = 0; fr < s->rec->nframes; fr++) {
        fprintf(f, "%ld", fr);
        for (k = 0; k < s->njoint; k++) {
            const skel_joint_t *j = &s->joint[k];
            const int ok = s->pose_ok[(size_t)fr * (size_t)s->nseg + (size_t)j->parent];
            const double *q = &s->pose[((size_t)fr * (size_t)s->nseg + (size_t)j->parent) * 12u];
            const int nv = j->pr.type == SKEL_HINGE ? 2 : 1;
            int v;
            for (v = 0; v < nv; v++) {
                const double *x = v == 0 ? j->pr.ca : j->pr.axis_a;
                for (i = 0; i < 3; i++) {
                    if (ok) {
                        fprintf(f, ",%.6f", q[i * 3] * x[0] + q[i * 3 + 1] * x[1] + q[i * 3 + 2] * x[2]
                                                + (v == 0 ? q[9 + i] : 0.0));
                    } else {
                        fputc(',', f);
                    }
                }
            }
        }
        fputc('\n', f);
    }
    return close_checked(f, path);
}
