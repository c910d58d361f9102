/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_apply.c
 * `sfit apply SESSION.json TRIAL.c3d -o OUT.c3d [--trc OUT.trc] [--svg OUT.svg]`:
 * every joint of a calibrated session placed in every frame of a trial
 * where its parent segment is registrable (>= 3 of its markers seen), and
 * written into a copy of the recording (docs/session.md).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "c3d_write.h"
#include "cli.h"
#include "frames.h"
#include "session.h"
#include "session_calib.h"
#include "svg.h"

#define CHI2_3_95 7.814727903251178

static void apply_usage(FILE *f)
{
    fputs("usage: sfit apply SESSION.json TRIAL.c3d -o OUT.c3d [--trc OUT.trc]\n"
          "                  [--svg OUT.svg] [--frame N] [--json]\n"
          "  SESSION.json  from `sfit calibrate`\n"
          "  TRIAL.c3d     any trial where the parents' markers are seen\n"
          "  -o OUT.c3d    TRIAL with each joint's points added (a hinge: the centre and\n"
          "                two axis points 100 mm either side); a frame where a parent\n"
          "                shows fewer than 3 markers gets an invalid sample (residual -1)\n"
          "  --trc OUT.trc an OpenSim marker file of the same\n"
          "  --svg OUT.svg the skeleton at a frame: segments between joint centres, the\n"
          "                markers, each joint's 95 % ellipsoid (projected, drawn x10,\n"
          "                x2 or x1 as their size allows)\n"
          "  --frame N     the frame of the picture (0-based; default: the first frame\n"
          "                where every joint is placed)\n"
          "  --json        one JSON object on stdout\n",
          f);
}

typedef struct apply_joint {
    long placed, missing;
    int loaded;           /* 0: a parent marker is not in the trial */
    sfit_mat3_t *rot;     /* per frame: the parent's rotation (for the ellipsoid) */
    session_place_cov_t pc; /* what the placement adds to the centre's uncertainty */
} apply_joint_t;

/* Place joint j in every frame; pts (nframes x npoints_total x 3) from column col. */
static int place_joint(const char *trial, const session_joint_t *j, float d, long nframes,
                       float *pts, int ntot, int col, apply_joint_t *aj)
{
    const char *names[SM_MARKERS_MAX];
    frames_data_t fr;
    char why[FRAMES_ERR_MAX];
    long placed;
    int i;
    for (i = 0; i < j->nmarkers; i++) {
        names[i] = j->markers[i];
    }
    aj->missing = nframes;
    if (frames_load(trial, names, j->nmarkers, &fr, why) != 0) {
        fprintf(stderr, "sfit: %s: %s: not placed in any frame\n", j->name, why);
        return 0;
    }
    if (fr.nframes != nframes) {
        frames_free(&fr);
        fprintf(stderr, "sfit: %s: the file changed while read\n", trial);
        return -1;
    }
    aj->loaded = 1;
    placed = session_place_frames(j, &fr, d, pts + (size_t)col * 3u, ntot, aj->rot, &aj->pc);
    frames_free(&fr);
    if (placed < 0) {
        fprintf(stderr, "sfit: %s: the session's template is degenerate\n", j->name);
        return -1;
    }
    aj->placed = placed;
    aj->missing = nframes - placed;
    return 0;
}

/* ------------------------------------------------------------------ SVG */

typedef struct view {
    double ex[3], ey[3]; /* screen right, screen up (lab, unit) */
    double x0, y0, s;    /* lab -> px: X = (p.ex - x0) s + m, Y = (y0 - p.ey) s + m */
} view_t;

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int finite3(const float *p)
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* Centroid of segment g's markers in the frame (0: none seen). */
static int seg_centroid(const c3d_t *c, long f, const sm_segment_t *g, double out[3])
{
    int k, n = 0, i;
    out[0] = out[1] = out[2] = 0.0;
    for (k = 0; k < g->nmarkers; k++) {
        const int idx = c3d_find(c, g->markers[k]);
        const float *p;
        if (idx < 0) {
            continue;
        }
        p = c->xyz + ((size_t)f * (size_t)c->npoints + (size_t)idx) * 3u;
        if (finite3(p) && !(p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f)) {
            for (i = 0; i < 3; i++) {
                out[i] += (double)p[i];
            }
            n++;
        }
    }
    for (i = 0; n > 0 && i < 3; i++) {
        out[i] /= n;
    }
    return n;
}

/* A round length (1, 2 or 5 times a power of ten) near x. */
static double nice_len(double x)
{
    const double k = pow(10.0, floor(log10(x))), m = x / k;
    return (m < 1.5 ? 1.0 : (m < 3.5 ? 2.0 : (m < 7.5 ? 5.0 : 10.0))) * k;
}

/* The lab direction v in words: "+x", "-z", or its components. */
static void dir_words(const double v[3], char *out, size_t cap)
{
    int i;
    for (i = 0; i < 3; i++) {
        if (fabs(v[i]) > 0.985) {
            (void)snprintf(out, cap, "%c%c", v[i] > 0 ? '+' : '-', "xyz"[i]);
            return;
        }
    }
    (void)snprintf(out, cap, "(%.2f, %.2f, %.2f)", v[0], v[1], v[2]);
}

static int write_svg(const char *path, const session_t *s, const c3d_t *c, long f,
                     const float *pts, int ntot, const int *col, const apply_joint_t *aj,
                     const char *trial, const char *units)
{
    const double W = 640.0, H = 900.0, M = 40.0;
    double lab_cov[SM_JOINTS_MAX][2][2], mag = 10.0, biggest = 0.0, boxes[SM_JOINTS_MAX][4];
    int nbox = 0;
    unsigned char *in_model;
    double up[3] = {0, 0, 1}, lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
    double mean[3] = {0, 0, 0}, cxx[3][3] = {{0}};
    view_t v;
    FILE *o;
    int k, i, n = 0, deepest = -1, depth_max = -1;
    /* down: from the root's centroid to the centroid of the deepest segment */
    for (k = 0; k < s->nseg; k++) {
        int d = 0, g = k, guard = 0;
        while (g != s->root && guard++ < SM_SEGMENTS_MAX) {
            int q;
            for (q = 0; q < s->njoint && strcmp(s->joint[q].child, s->seg[g].name) != 0; q++) {
            }
            if (q == s->njoint) {
                break;
            }
            for (g = 0; g < s->nseg && strcmp(s->seg[g].name, s->joint[q].parent) != 0; g++) {
            }
            if (g == s->nseg) {
                break;
            }
            d++;
        }
        if (g == s->root && d > depth_max) {
            depth_max = d;
            deepest = k;
        }
    }
    if (deepest >= 0 && deepest != s->root) {
        double a[3], b[3];
        if (seg_centroid(c, f, &s->seg[s->root], a) > 0 && seg_centroid(c, f, &s->seg[deepest], b) > 0) {
            double len = 0.0;
            for (i = 0; i < 3; i++) {
                up[i] = a[i] - b[i];
                len += up[i] * up[i];
            }
            len = sqrt(len);
            for (i = 0; i < 3 && len > 0.0; i++) {
                up[i] /= len;
            }
        }
    }
    /* screen right: the markers' widest horizontal direction */
    for (k = 0; k < c->npoints; k++) {
        const float *p = c->xyz + ((size_t)f * (size_t)c->npoints + (size_t)k) * 3u;
        if (finite3(p) && !(p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f)) {
            for (i = 0; i < 3; i++) {
                mean[i] += (double)p[i];
            }
            n++;
        }
    }
    for (i = 0; i < 3 && n > 0; i++) {
        mean[i] /= n;
    }
    for (k = 0; k < c->npoints; k++) {
        const float *p = c->xyz + ((size_t)f * (size_t)c->npoints + (size_t)k) * 3u;
        double h[3], t;
        int a, b;
        if (!finite3(p) || (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f)) {
            continue;
        }
        for (i = 0; i < 3; i++) {
            h[i] = (double)p[i] - mean[i];
        }
        t = dot3(h, up);
        for (i = 0; i < 3; i++) {
            h[i] -= t * up[i];
        }
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                cxx[a][b] += h[a] * h[b];
            }
        }
    }
    { /* power iteration in the horizontal plane */
        double e[3] = {1.0, 0.3, 0.1}, t, len;
        int it;
        t = dot3(e, up);
        for (i = 0; i < 3; i++) {
            e[i] -= t * up[i];
        }
        for (it = 0; it < 100; it++) {
            double g[3];
            for (i = 0; i < 3; i++) {
                g[i] = dot3(cxx[i], e);
            }
            t = dot3(g, up);
            for (i = 0; i < 3; i++) {
                g[i] -= t * up[i];
            }
            len = sqrt(dot3(g, g));
            if (!(len > 0.0)) {
                break;
            }
            for (i = 0; i < 3; i++) {
                e[i] = g[i] / len;
            }
        }
        len = sqrt(dot3(e, e));
        if (!(len > 0.5)) { /* no spread: any horizontal direction */
            const double z[3] = {fabs(up[0]) < 0.9 ? 1.0 : 0.0, fabs(up[0]) < 0.9 ? 0.0 : 1.0, 0};
            t = dot3(z, up);
            for (i = 0; i < 3; i++) {
                e[i] = z[i] - t * up[i];
            }
            len = sqrt(dot3(e, e));
        }
        for (i = 0; i < 3; i++) {
            v.ex[i] = e[i] / len;
            v.ey[i] = up[i];
        }
    }
    /* extent: every marker and centre */
    for (k = 0; k < c->npoints + ntot; k++) {
        const float *p = (k < c->npoints)
                             ? c->xyz + ((size_t)f * (size_t)c->npoints + (size_t)k) * 3u
                             : pts + ((size_t)f * (size_t)ntot + (size_t)(k - c->npoints)) * 3u;
        double q[3], x, y;
        if (!finite3(p) || (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f)) {
            continue;
        }
        q[0] = (double)p[0];
        q[1] = (double)p[1];
        q[2] = (double)p[2];
        x = dot3(q, v.ex);
        y = dot3(q, v.ey);
        lo[0] = x < lo[0] ? x : lo[0];
        hi[0] = x > hi[0] ? x : hi[0];
        lo[1] = y < lo[1] ? y : lo[1];
        hi[1] = y > hi[1] ? y : hi[1];
    }
    if (!(hi[0] >= lo[0])) {
        lo[0] = lo[1] = 0.0;
        hi[0] = hi[1] = 1.0;
    }
    v.s = fmin((W - 2 * M) / fmax(hi[0] - lo[0], 1e-9), (H - 2 * M - 60) / fmax(hi[1] - lo[1], 1e-9));
    v.x0 = (lo[0] + hi[0]) / 2.0 - (W / 2.0 - M) / v.s;
    v.y0 = hi[1];
    /* each joint's 95 % ellipse in the view, and one magnification for all:
     * at most 10 and no ellipse wider than 45 px (stated in the caption) */
    for (k = 0; k < s->njoint; k++) {
        double lab[3][3], P[2][3];
        int r, t, u;
        const int ok = aj[k].rot != NULL && f < c->nframes;
        for (r = 0; r < 3; r++) { /* lab = R cov R^T */
            for (t = 0; t < 3; t++) {
                double sum = 0.0;
                for (u = 0; u < 9 && ok; u++) {
                    sum += (double)aj[k].rot[f].m[r * 3 + u / 3] * aj[k].pc.total[u / 3][u % 3]
                           * (double)aj[k].rot[f].m[t * 3 + u % 3];
                }
                lab[r][t] = sum;
            }
        }
        for (i = 0; i < 3; i++) {
            P[0][i] = v.ex[i];
            P[1][i] = v.ey[i];
        }
        for (r = 0; r < 2; r++) {
            for (t = 0; t < 2; t++) {
                double sum = 0.0;
                for (u = 0; u < 9; u++) {
                    sum += P[r][u / 3] * lab[u / 3][u % 3] * P[t][u % 3];
                }
                lab_cov[k][r][t] = sum;
            }
        }
        {
            const double tr = lab_cov[k][0][0] + lab_cov[k][1][1];
            const double det = lab_cov[k][0][0] * lab_cov[k][1][1] - lab_cov[k][0][1] * lab_cov[k][1][0];
            const double l1 = tr / 2.0 + sqrt(fmax(tr * tr / 4.0 - det, 0.0));
            const double semi = sqrt(CHI2_3_95 * fmax(l1, 0.0)) * v.s;
            biggest = isfinite(semi) && semi > biggest ? semi : biggest;
        }
    }
    while (mag > 1.0 && mag * biggest > 45.0) {
        mag = mag > 5.0 ? 5.0 : (mag > 2.0 ? 2.0 : 1.0);
    }
    in_model = calloc((size_t)c->npoints + 1u, 1u);
    if (in_model == NULL) {
        fprintf(stderr, "sfit: out of memory\n");
        return -1;
    }
    for (k = 0; k < s->nseg; k++) {
        for (i = 0; i < s->seg[k].nmarkers; i++) {
            const int idx = c3d_find(c, s->seg[k].markers[i]);
            if (idx >= 0) {
                in_model[idx] = 1u;
            }
        }
    }
    o = svg_open(path, W, H);
    if (o == NULL) {
        free(in_model);
        return -1;
    }
#define PX(q) ((dot3((q), v.ex) - v.x0) * v.s + M)
#define PY(q) ((v.y0 - dot3((q), v.ey)) * v.s + M + 50)
    fprintf(o, "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
               "<text x=\"%.0f\" y=\"20\" font-family=\"sans-serif\" font-size=\"14\" "
               "font-weight=\"bold\">%s, frame %ld</text>\n"
               "<text x=\"%.0f\" y=\"37\" font-family=\"sans-serif\" font-size=\"12\" "
               "fill=\"#555\">joint centres (red), their 95 %% ellipsoids (orange, drawn x%g), "
               "segments (blue);</text>\n"
               "<text x=\"%.0f\" y=\"52\" font-family=\"sans-serif\" font-size=\"12\" "
               "fill=\"#555\">markers of the model (dark grey), other markers (light grey)"
               "</text>\n",
            M, trial, f, M, mag, M);
    {
        /* the view: its direction and vertical in lab axes, and a scale bar */
        double toward[3], len = nice_len(110.0 / v.s);
        char a[48], b[48];
        toward[0] = v.ex[1] * v.ey[2] - v.ex[2] * v.ey[1];
        toward[1] = v.ex[2] * v.ey[0] - v.ex[0] * v.ey[2];
        toward[2] = v.ex[0] * v.ey[1] - v.ex[1] * v.ey[0];
        dir_words(toward, a, sizeof a);
        dir_words(v.ey, b, sizeof b);
        fprintf(o, "<text x=\"%.0f\" y=\"%.0f\" font-family=\"sans-serif\" font-size=\"12\" "
                   "fill=\"#555\">orthographic view from lab %s (toward the viewer), up = lab "
                   "%s</text>\n",
                M, H - 14.0, a, b);
        fprintf(o, "<path d=\"M %.1f %.1f v 8 h %.1f v -8\" fill=\"none\" stroke=\"#222\" "
                   "stroke-width=\"2.5\"/>\n<text x=\"%.1f\" y=\"%.1f\" font-family=\"sans-serif\" "
                   "font-size=\"12\">%g %s</text>\n",
                W - M - len * v.s, H - 44.0, len * v.s, W - M - len * v.s, H - 50.0, len,
                units);
    }
    /* markers */
    for (k = 0; k < c->npoints; k++) {
        const float *p = c->xyz + ((size_t)f * (size_t)c->npoints + (size_t)k) * 3u;
        double q[3];
        if (!finite3(p) || (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f)) {
            continue;
        }
        q[0] = (double)p[0];
        q[1] = (double)p[1];
        q[2] = (double)p[2];
        fprintf(o, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"%s\"><title>%s</title></circle>\n",
                PX(q), PY(q), in_model[k] ? "#777" : "#ccc", c->labels[k]);
    }
    /* segments: a joint to the joints of its child segment, or to the child's markers */
    for (k = 0; k < s->njoint; k++) {
        const float *a = pts + ((size_t)f * (size_t)ntot + (size_t)col[k]) * 3u;
        double qa[3];
        int q, linked = 0;
        if (!finite3(a)) {
            continue;
        }
        qa[0] = (double)a[0];
        qa[1] = (double)a[1];
        qa[2] = (double)a[2];
        for (q = 0; q < s->njoint; q++) {
            const float *b = pts + ((size_t)f * (size_t)ntot + (size_t)col[q]) * 3u;
            if (strcmp(s->joint[q].parent, s->joint[k].child) == 0) {
                linked = 1;
                if (finite3(b)) {
                    double qb[3] = {(double)b[0], (double)b[1], (double)b[2]};
                    fprintf(o, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
                               "stroke=\"#1f5fbf\" stroke-width=\"7\" stroke-linecap=\"round\"/>\n",
                            PX(qa), PY(qa), PX(qb), PY(qb));
                }
            }
            if (q > k && strcmp(s->joint[q].parent, s->joint[k].parent) == 0 && finite3(b)) {
                double qb[3] = {(double)b[0], (double)b[1], (double)b[2]}; /* two joints of one segment */
                fprintf(o, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
                           "stroke=\"#1f5fbf\" stroke-width=\"7\" stroke-linecap=\"round\"/>\n",
                        PX(qa), PY(qa), PX(qb), PY(qb));
            }
        }
        if (!linked) {
            int g;
            double qb[3];
            for (g = 0; g < s->nseg && strcmp(s->seg[g].name, s->joint[k].child) != 0; g++) {
            }
            if (g < s->nseg && seg_centroid(c, f, &s->seg[g], qb) > 0) {
                fprintf(o, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
                           "stroke=\"#1f5fbf\" stroke-width=\"7\" stroke-linecap=\"round\"/>\n",
                        PX(qa), PY(qa), PX(qb), PY(qb));
            }
        }
    }
    /* joint centres and their ellipsoids, then the labels where they
     * overlap no other label (else moved down) */
    for (k = 0; k < s->njoint; k++) {
        const float *a = pts + ((size_t)f * (size_t)ntot + (size_t)col[k]) * 3u;
        double qa[3], tr, det, l1, l2, ang;
        if (!finite3(a)) {
            continue;
        }
        qa[0] = (double)a[0];
        qa[1] = (double)a[1];
        qa[2] = (double)a[2];
        tr = lab_cov[k][0][0] + lab_cov[k][1][1];
        det = lab_cov[k][0][0] * lab_cov[k][1][1] - lab_cov[k][0][1] * lab_cov[k][1][0];
        l1 = tr / 2.0 + sqrt(fmax(tr * tr / 4.0 - det, 0.0));
        l2 = fmax(tr - l1, 0.0);
        ang = 0.5 * atan2(2.0 * lab_cov[k][0][1], lab_cov[k][0][0] - lab_cov[k][1][1])
              * 57.29577951308232;
        fprintf(o, "<ellipse cx=\"%.1f\" cy=\"%.1f\" rx=\"%.2f\" ry=\"%.2f\" "
                   "transform=\"rotate(%.1f %.1f %.1f)\" fill=\"#ffb000\" fill-opacity=\"0.45\" "
                   "stroke=\"#b06000\"/>\n",
                PX(qa), PY(qa), mag * sqrt(CHI2_3_95 * l1) * v.s,
                mag * sqrt(CHI2_3_95 * l2) * v.s, -ang, PX(qa), PY(qa));
    }
    for (k = 0; k < s->njoint; k++) {
        const session_joint_t *j = &s->joint[k];
        const float *a = pts + ((size_t)f * (size_t)ntot + (size_t)col[k]) * 3u;
        double qa[3], x, y, w;
        int b, moved = 1, guard = 0;
        if (!finite3(a)) {
            continue;
        }
        qa[0] = (double)a[0];
        qa[1] = (double)a[1];
        qa[2] = (double)a[2];
        x = PX(qa) + 12.0;
        y = PY(qa) - 4.0;
        w = 7.5 * (double)strlen(j->name) + 4.0;
        while (moved && guard++ < 20) {
            moved = 0;
            for (b = 0; b < nbox; b++) {
                if (x < boxes[b][2] && x + w > boxes[b][0] && y - 12.0 < boxes[b][3]
                    && y + 3.0 > boxes[b][1]) {
                    y = boxes[b][3] + 13.0;
                    moved = 1;
                }
            }
        }
        boxes[nbox][0] = x;
        boxes[nbox][1] = y - 12.0;
        boxes[nbox][2] = x + w;
        boxes[nbox][3] = y + 3.0;
        nbox++;
        fprintf(o, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"#d01010\"><title>%s</title>"
                   "</circle>\n<text x=\"%.1f\" y=\"%.1f\" font-family=\"sans-serif\" "
                   "font-size=\"13\" font-weight=\"bold\" fill=\"#b00000\" stroke=\"white\" "
                   "stroke-width=\"3\" paint-order=\"stroke\">%s</text>\n",
                PX(qa), PY(qa), j->points[0], x, y, j->name);
    }
#undef PX
#undef PY
    free(in_model);
    return svg_close(o, path);
}

int cli_cmd_apply(int argc, char **argv)
{
    const char *pos[2] = {NULL, NULL};
    const char *out = NULL, *trc = NULL, *svg = NULL, *frame_s = NULL;
    int json = 0;
    const cli_opt_t opts[] = {
        {.name = "-o", .kind = CLI_OPT_STRING, .dst = &out, .required = 1},
        {.name = "--trc", .kind = CLI_OPT_STRING, .dst = &trc},
        {.name = "--svg", .kind = CLI_OPT_STRING, .dst = &svg},
        {.name = "--frame", .kind = CLI_OPT_STRING, .dst = &frame_s},
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &json},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0], .pos = pos,
                             .max_pos = 2, .min_pos = 2, .extra = "SESSION.json and one TRIAL",
                             .missing = "SESSION.json and TRIAL are required",
                             .required = "-o OUT.c3d is required", .usage = apply_usage};
    static session_t s;
    apply_joint_t aj[SM_JOINTS_MAX];
    int col[SM_JOINTS_MAX];
    const char *names[3 * SM_JOINTS_MAX];
    static char desc_buf[3 * SM_JOINTS_MAX][SESSION_DESC_MAX];
    const char *descs[3 * SM_JOINTS_MAX];
    char err[C3D_ERR_MAX > SM_ERR_MAX ? C3D_ERR_MAX : SM_ERR_MAX], prefix[C3D_LABEL_MAX];
    unsigned char *buf = NULL;
    size_t len = 0, k;
    c3d_t c;
    c3d_add_t add;
    float *pts = NULL;
    float d = 100.0f;
    long frame = -1, f;
    int ntot = 0, i, rc = CLI_FAIL, to_float = 0, all_missing = 0;
    const int prc = cli_parse(argc, argv, &args);
    if (prc >= 0) {
        return prc;
    }
    if (frame_s != NULL) {
        char *e;
        errno = 0;
        frame = strtol(frame_s, &e, 10);
        if (*e != '\0' || e == frame_s || errno != 0 || frame < 0) {
            fprintf(stderr, "sfit: --frame needs a whole number >= 0\n");
            apply_usage(stderr);
            return CLI_USAGE;
        }
    }
    if (session_read(pos[0], &s, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        return CLI_IO;
    }
    if (s.njoint == 0) {
        fprintf(stderr, "sfit: %s: the session has no calibrated joint\n", pos[0]);
        return CLI_FAIL;
    }
    memset(&c, 0, sizeof c);
    memset(aj, 0, sizeof aj);
    if (c3d_load_bytes(pos[1], &buf, &len, err) != 0 || c3d_parse(buf, len, &c, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        free(buf);
        return CLI_IO;
    }
    if (c.nframes < 1) {
        fprintf(stderr, "sfit: %s has no frame\n", pos[1]);
        goto out;
    }
    if (frame >= c.nframes) {
        fprintf(stderr, "sfit: --frame %ld: %s has %ld frames\n", frame, pos[1], c.nframes);
        rc = CLI_USAGE;
        goto out;
    }
    if (strcmp(c.units, s.units) != 0) {
        fprintf(stderr, "sfit: %s is in '%s', the session in '%s'\n", pos[1], c.units, s.units);
        goto out;
    }
    if (strcmp(c.units, "m") == 0) {
        d = 0.1f;
    } else if (strcmp(c.units, "cm") == 0) {
        d = 10.0f;
    }
    for (i = 0; i < s.njoint; i++) {
        int q;
        col[i] = ntot;
        for (q = 0; q < s.joint[i].npoints; q++) {
            session_point_desc(&s.joint[i], q, desc_buf[ntot], sizeof desc_buf[ntot]);
            descs[ntot] = desc_buf[ntot];
            names[ntot++] = s.joint[i].points[q];
        }
    }
    pts = malloc((size_t)c.nframes * (size_t)ntot * 3u * sizeof *pts);
    if (pts == NULL) {
        fprintf(stderr, "sfit: out of memory\n");
        goto out;
    }
    for (k = 0; k < (size_t)c.nframes * (size_t)ntot * 3u; k++) {
        pts[k] = NAN;
    }
    for (i = 0; i < s.njoint; i++) {
        aj[i].rot = calloc((size_t)c.nframes, sizeof *aj[i].rot);
        if (aj[i].rot == NULL
            || place_joint(pos[1], &s.joint[i], d, c.nframes, pts, ntot, col[i], &aj[i])
                   != 0) {
            goto out;
        }
        all_missing += aj[i].placed == 0;
    }
    c3d_label_prefix(&c, c3d_find(&c, s.joint[0].markers[0]), prefix, sizeof prefix);
    memset(&add, 0, sizeof add);
    add.n = ntot;
    add.names = names;
    add.descs = descs;
    add.xyz = pts;
    add.prefix = prefix;
    if (c3d_write_added(buf, len, &c, &add, out, &to_float, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        rc = CLI_IO;
        goto out;
    }
    if (trc != NULL && c3d_write_trc(trc, &c, &add, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        rc = CLI_IO;
        goto out;
    }
    if (svg != NULL) {
        if (frame < 0) {
            for (f = 0; f < c.nframes && frame < 0; f++) {
                for (i = 0; i < s.njoint && finite3(pts + ((size_t)f * (size_t)ntot + (size_t)col[i]) * 3u); i++) {
                }
                if (i == s.njoint) {
                    frame = f;
                }
            }
            if (frame < 0) {
                frame = 0;
            }
        }
        char tname[128];
        {
            const char *slash = strrchr(pos[1], '/');
            size_t q;
            (void)snprintf(tname, sizeof tname, "%s", slash != NULL ? slash + 1 : pos[1]);
            for (q = 0; tname[q] != '\0'; q++) { /* plain text in the SVG */
                if (strchr("<>&\"", tname[q]) != NULL) {
                    tname[q] = '_';
                }
            }
        }
        if (write_svg(svg, &s, &c, frame, pts, ntot, col, aj, tname,
                      c.units[0] != '\0' ? c.units : "units") != 0) {
            rc = CLI_IO;
            goto out;
        }
    }
    if (json) {
        printf("{\"status\":\"ok\",\"trial\":");
        json_out_str(stdout, pos[1], 0);
        printf(",\"frames\":%ld,\"storage\":\"%s\",\"joints\":[", c.nframes,
               to_float ? "float (converted)" : "kept");
        for (i = 0; i < s.njoint; i++) {
            printf("%s{\"name\":", i > 0 ? "," : "");
            json_out_str(stdout, s.joint[i].name, 0);
            printf(",\"placed\":%ld,\"invalid\":%ld,\"parent_in_trial\":%s", aj[i].placed,
                   aj[i].missing, aj[i].loaded ? "true" : "false");
            printf(",\"placement\":");
            fflush(stdout);
            session_place_json(stdout, &aj[i].pc, s.joint[i].nmarkers);
            printf("}");
        }
        printf("],\"svg_frame\":%ld}\n", svg != NULL ? frame : -1L);
    } else {
        printf("trial      %s (%ld frames, %s)\n", pos[1], c.nframes, c.units);
        for (i = 0; i < s.njoint; i++) {
            printf("%-10s %s: placed in %ld frames, %ld invalid (parent not registrable)",
                   s.joint[i].name, s.joint[i].points[0], aj[i].placed, aj[i].missing);
            if (aj[i].placed > 0) {
                printf("; 95 %% %.1f x %.1f x %.1f %s (calibration %.1f x %.1f x %.1f, "
                       "placement %.1f x %.1f x %.1f)",
                       aj[i].pc.semi_total[0], aj[i].pc.semi_total[1], aj[i].pc.semi_total[2], c.units,
                       s.joint[i].semi95_model[0], s.joint[i].semi95_model[1],
                       s.joint[i].semi95_model[2], aj[i].pc.semi_frame[0], aj[i].pc.semi_frame[1],
                       aj[i].pc.semi_frame[2]);
            }
            printf("\n");
        }
        printf("written    %s%s%s%s%s", out, trc != NULL ? ", " : "", trc != NULL ? trc : "",
               svg != NULL ? ", " : "", svg != NULL ? svg : "");
        if (svg != NULL) {
            printf(" (picture at frame %ld)", frame);
        }
        printf("\n");
    }
    rc = all_missing > 0 ? CLI_FAIL : CLI_OK;
    if (all_missing > 0) {
        fprintf(stderr, "sfit: %d joint(s) could not be placed in any frame\n", all_missing);
    }
out:
    for (i = 0; i < s.njoint; i++) {
        free(aj[i].rot);
    }
    free(pts);
    c3d_free(&c);
    free(buf);
    return rc;
}
