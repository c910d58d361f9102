/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_skeleton.c
 * @brief libFuzzer harness of the host library's skeleton from unlabelled markers
 * (`sfit skeleton FILE...` without a map: tools/lab/skel_*.c, compiled into
 * the harness). The input describes a recording: a chain of 2 to 6 rigid
 * segments with 1 to 4 markers each (so groups of 1, 2 and more markers),
 * turning about joints with amplitudes and frequencies from the input,
 * marker noise, occlusion runs, and then raw samples written over any
 * marker in any frame (every NaN, Inf, huge value). The whole no-map path
 * runs on it: grouping, poses, the attachment of 2-marker groups, pair
 * costs, tree, forward kinematics, and every writer (to /dev/null).
 * Contract: skel_from_data returns segments in the tree or -1 with a
 * message; on success the tree's indices are in range, every joint's
 * centre and cost are finite, and the joint centres of the motion are
 * finite in every frame; every writer returns 0.
 */
#include "../../tools/formats/c3d.c"
#include "../../tools/formats/c3d_param.c"
#include "../../tools/formats/c3d_write.c"
#include "../../tools/formats/json_out.c"
#include "../../tools/formats/svg.c"
#include "../../tools/lab/skel_draw.c"
#include "../../tools/lab/skel_group.c"
#include "../../tools/lab/skel_pair.c"
#include "../../tools/lab/skel_tree.c"
#include "../../tools/lab/skel_write.c"

#include "fuzz_common.h"

#define FZ_SK_MAX_SEG 6
#define FZ_SK_MAX_MK 4
#define FZ_SK_MAX_FRAMES 160

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* rotation about unit axis u by angle a (row-major) */
static void fz_rot(const double u[3], double a, double r[9])
{
    const double c = cos(a), s = sin(a), t = 1.0 - c;
    r[0] = t * u[0] * u[0] + c;
    r[1] = t * u[0] * u[1] - s * u[2];
    r[2] = t * u[0] * u[2] + s * u[1];
    r[3] = t * u[0] * u[1] + s * u[2];
    r[4] = t * u[1] * u[1] + c;
    r[5] = t * u[1] * u[2] - s * u[0];
    r[6] = t * u[0] * u[2] - s * u[1];
    r[7] = t * u[1] * u[2] + s * u[0];
    r[8] = t * u[2] * u[2] + c;
}

static void fz_mul(const double a[9], const double b[9], double c[9])
{
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            c[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
        }
    }
}

/* a small signed offset from one byte: -127..128 times `unit` */
static double fz_off(fz_in_t *in, double unit)
{
    return ((double)fz_u8(in) - 127.0) * unit;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in = {data, size, 0u};
    skel_rec_t rec;
    skel_t *s;
    skel_groups_t *grp;
    char why[SKEL_ERR];
    int nseg, nmk[FZ_SK_MAX_SEG], nm = 0, k, i, m, intree;
    long nf, f;
    double loc[FZ_SK_MAX_SEG][FZ_SK_MAX_MK][3], jpos[FZ_SK_MAX_SEG][3], ax[FZ_SK_MAX_SEG][3];
    double amp[FZ_SK_MAX_SEG], freq[FZ_SK_MAX_SEG], noise;
    unsigned mode;
    memset(&rec, 0, sizeof rec);
    nseg = 2 + (int)(fz_u8(&in) % (FZ_SK_MAX_SEG - 1));
    nf = 12 + (long)(fz_u8(&in) % (FZ_SK_MAX_FRAMES - 11));
    mode = fz_u8(&in);
    noise = (double)(fz_u8(&in) % 16u) * 0.1;
    for (k = 0; k < nseg; k++) {
        double n2 = 0.0;
        nmk[k] = 1 + (int)(fz_u8(&in) % FZ_SK_MAX_MK);
        for (i = 0; i < nmk[k]; i++) {
            for (m = 0; m < 3; m++) {
                loc[k][i][m] = fz_off(&in, 1.0);
            }
        }
        for (m = 0; m < 3; m++) {
            jpos[k][m] = fz_off(&in, 2.0); /* joint to the parent, in the parent's frame */
            ax[k][m] = fz_off(&in, 1.0) + (m == (k % 3) ? 200.0 : 0.0);
            n2 += ax[k][m] * ax[k][m];
        }
        for (m = 0; m < 3; m++) {
            ax[k][m] /= sqrt(n2);
        }
        amp[k] = (double)fz_u8(&in) / 255.0 * 1.5;
        freq[k] = 0.02 + (double)fz_u8(&in) / 255.0 * 0.3;
        nm += nmk[k];
    }
    rec.nfiles = 1;
    rec.file[0] = "fuzz.c3d";
    rec.start[0] = 0;
    rec.start[1] = nf;
    rec.nframes = nf;
    rec.nmark = nm;
    rec.rate = 100.0f;
    (void)snprintf(rec.units, sizeof rec.units, "mm");
    rec.label = calloc((size_t)nm, sizeof *rec.label);
    rec.xyz = malloc((size_t)nf * (size_t)nm * 3u * sizeof *rec.xyz);
    s = calloc(1u, sizeof *s);
    grp = calloc(1u, sizeof *grp);
    if (rec.label == NULL || rec.xyz == NULL || s == NULL || grp == NULL) {
        free(rec.label);
        free(rec.xyz);
        free(s);
        free(grp);
        return 0;
    }
    for (i = 0; i < nm; i++) {
        (void)snprintf(rec.label[i], SKEL_NAME, "M%03d", i);
    }
    /* the chain's motion; markers interleaved over the segments (mode bit 0) */
    {
        uint32_t st = 12345u + (uint32_t)size;
        for (f = 0; f < nf; f++) {
            double g[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p[3] = {0.0, 0.0, 1000.0};
            int mi = 0;
            p[0] += (mode & 2u) ? 0.0 : 3.0 * (double)f;
            for (k = 0; k < nseg; k++) {
                double r[9], gn[9], w[3];
                if (k > 0) { /* the joint: p += g jpos, then turn */
                    for (m = 0; m < 3; m++) {
                        w[m] = g[m * 3] * jpos[k][0] + g[m * 3 + 1] * jpos[k][1]
                               + g[m * 3 + 2] * jpos[k][2];
                    }
                    for (m = 0; m < 3; m++) {
                        p[m] += w[m];
                    }
                }
                fz_rot(ax[k], (mode & 4u) ? 0.0 : amp[k] * sin(freq[k] * (double)f + (double)k),
                       r);
                fz_mul(g, r, gn);
                memcpy(g, gn, sizeof g);
                for (i = 0; i < nmk[k]; i++, mi++) {
                    const int col = (mode & 1u) ? (mi * 7) % nm : mi;
                    float *x = &rec.xyz[((size_t)f * (size_t)nm + (size_t)col) * 3u];
                    for (m = 0; m < 3; m++) {
                        double e;
                        st = st * 1664525u + 1013904223u;
                        e = ((double)(st >> 8) / 16777216.0 - 0.5) * 2.0 * noise;
                        x[m] = (float)(p[m] + g[m * 3] * loc[k][i][0] + g[m * 3 + 1] * loc[k][i][1]
                                       + g[m * 3 + 2] * loc[k][i][2] + e);
                    }
                }
            }
        }
    }
    /* occlusion runs, then raw samples over any marker in any frame */
    while (fz_more(&in)) {
        const unsigned op = fz_u8(&in);
        const long f0 = (long)(fz_u32(&in) % (uint32_t)nf);
        const int mk = (int)(fz_u8(&in) % (unsigned)nm);
        if ((op & 1u) == 0u) {
            const long len = (long)(fz_u8(&in) % 64u);
            for (f = f0; f < nf && f < f0 + len; f++) {
                float *x = &rec.xyz[((size_t)f * (size_t)nm + (size_t)mk) * 3u];
                x[0] = x[1] = x[2] = NAN;
            }
        } else {
            float *x = &rec.xyz[((size_t)f0 * (size_t)nm + (size_t)mk) * 3u];
            x[(op >> 1) % 3u] = fz_raw(&in);
        }
    }
    /* what skel_rec_load does with a sample the library cannot take */
    for (i = 0; i < nm * (int)nf; i++) {
        float *x = &rec.xyz[(size_t)i * 3u];
        if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])
            || fabsf(x[0]) >= 0x1p40f || fabsf(x[1]) >= 0x1p40f || fabsf(x[2]) >= 0x1p40f) {
            x[0] = x[1] = x[2] = NAN;
        }
    }
    s->rec = &rec;
    why[0] = '\0';
    intree = skel_from_data(s, grp, NULL, why);
    if (intree < 0) {
        FZ_CHECK(why[0] != '\0' && memchr(why, '\0', SKEL_ERR) != NULL, "failure has a message");
    } else {
        FZ_CHECK(intree >= 1 && intree <= s->nseg && s->nseg <= SKEL_MAX_SEG, "tree size");
        FZ_CHECK(s->root >= 0 && s->root < s->nseg, "root in range");
        FZ_CHECK(s->njoint == intree - 1, "a tree: joints = segments - 1");
        for (k = 0; k < s->njoint; k++) {
            const skel_joint_t *j = &s->joint[k];
            FZ_CHECK(j->parent >= 0 && j->parent < s->nseg && j->child >= 0
                         && j->child < s->nseg && j->parent != j->child,
                     "joint segments in range");
            for (m = 0; m < 3; m++) {
                FZ_CHECK(isfinite(j->pr.ca[m]) && isfinite(j->pr.cb[m]), "centre finite");
            }
            FZ_CHECK(isfinite(j->pr.rms), "cost finite");
        }
        for (k = 0; k < grp->n; k++) {
            FZ_CHECK(grp->size[k] >= 1 && grp->size[k] <= nm, "group size");
        }
        if (skel_motion(s, why) == 0) {
            for (i = 0; i < (int)nf * s->njoint * 3; i++) {
                FZ_CHECK(isfinite(s->jc[i]), "joint centres of the motion finite");
            }
            FZ_CHECK(skel_write_bvh(s, "/dev/null") == 0, "bvh written");
            FZ_CHECK(skel_write_trc(s, "/dev/null") == 0, "trc written");
            FZ_CHECK(skel_write_centres(s, "/dev/null") == 0, "centres written");
            FZ_CHECK(skel_write_svg(s, "/dev/null", nf - 1) == 0, "svg written");
            FZ_CHECK(skel_write_html(s, "/dev/null") == 0, "html written");
        } else {
            FZ_CHECK(why[0] != '\0', "motion failure has a message");
        }
    }
    skel_free(s);
    free(s);
    free(grp);
    free(rec.label);
    free(rec.xyz);
    return 0;
}
