/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_skeleton.c
 * @brief `sfit skeleton`: every joint of a model over one recording, and an
 * SVG picture of the skeleton at one frame.
 *
 *   sfit skeleton MODEL FILE [--frame K] [--frames F:L] [--noise-var V|auto]
 *                 [--mode M] [--no-repair-swaps] [--svg OUT.svg] [--json]
 *
 * MODEL is a text file, one joint per line (blank lines and # comments
 * ignored):
 *   joint NAME PARENT_MARKERS CHILD_MARKERS [auto|sphere|planar]
 * with comma-separated marker lists. Two joints whose lists are the same
 * share that segment. The joints are computed as `sfit joint` computes
 * them (joint_run.h), each over FILE, after the label swaps within each
 * joint's parent and child markers are found and repaired (swaps.h).
 *
 * The picture (--svg): two orthographic views of frame K side by side,
 * the lab's vertical axis (the one along which the markers spread most at
 * that frame) pointing up, each view along one horizontal lab axis. Joint
 * centres are red and labelled, a hinge's axis a dashed red line through
 * its centre; a segment is a line between the centres of
 * its joints, or from its one joint centre to the centroid of its markers;
 * the model's markers are coloured dots, labelled; other C3D points are
 * small grey dots.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_joint.h"
#include "swaps.h"
#include "skel.h"
#include "svg.h"

#define SK_MAX_JOINTS 32
#define SK_LINE 4096

typedef struct sk_joint {
    char name[64];
    char *parent_list, *child_list; /* as written (for segment identity) */
    char *own_line, *own_lists;     /* allocations the pointers point into */
    char *names[FRAMES_MARKERS_MAX];
    int np, nc;
    sfit_mode_t mode;
    int has_mode;
    /* results */
    sfit_status_t st;
    const char *stage;
    joint_run_out_t out;
    swaps_joint_t swaps;
    int swaps_ok;
    int lab_ok;
    sfit_vec3_t lab;              /* centre in the lab frame at frame K */
    sfit_vec3_t axis_lab;
    sfit_vec3_t mk[FRAMES_MARKERS_MAX]; /* markers at frame K (parent, then child) */
} sk_joint_t;

typedef struct sk_model {
    sk_joint_t j[SK_MAX_JOINTS];
    int n;
    char *text; /* the model file's lines, owned */
} sk_model_t;

typedef struct sk_opts {
    const char *model, *file;
    char *svg;
    int json;
    long frame; /* -1: first frame of the range */
    joint_run_opts_t j;
} sk_opts_t;

static void sk_usage(FILE *f)
{
    fputs("usage: sfit skeleton MODEL FILE [--frame K] [--frames F:L] [--noise-var V|auto]\n"
          "                     [--mode auto|sphere|planar] [--no-repair-swaps]\n"
          "                     [--svg OUT.svg] [--json]\n"
          "  MODEL  text, one joint per line:  joint NAME PARENT_MARKERS CHILD_MARKERS [MODE]\n"
          "         (comma-separated marker lists; # starts a comment)\n"
          "  FILE   C3D file or wide table, as for `sfit joint`\n" CLI_JOINT_USAGE
          "         (a MODE in the model overrides --mode for that joint)\n"
          "  --frame K        frame of the picture and of the lab-frame centres\n"
          "                   (default: the first frame used)\n"
          "  --svg OUT.svg    draw the skeleton at frame K (two orthographic views)\n"
          "  --json           one JSON object on stdout\n"
          "The skeleton found in the data (segments, joints, tree; BVH, TRC, HTML):\n"
          "  sfit skeleton FILE.c3d... [--segments MAP] [--bvh OUT.bvh] ...\n"
          "  (its options: sfit skeleton FILE.c3d --help; docs/skeleton.md)\n",
          f);
}

/* -1 to go on, or the exit status (cli_parse). */
static int sk_parse(int argc, char **argv, sk_opts_t *o)
{
    const char *pos[2] = {NULL, NULL};
    const cli_opt_t opts[] = {
        CLI_JOINT_OPTS(&o->j),
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--svg", .kind = CLI_OPT_STRING, .dst = &o->svg},
        {.name = "--frame", .kind = CLI_OPT_INDEX, .dst = &o->frame,
         .err = "--frame needs a whole number >= 0"},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .pos = pos, .max_pos = 2, .min_pos = 2,
                             .extra = "MODEL and FILE expected",
                             .missing = "MODEL and FILE are required", .usage = sk_usage};
    int rc;
    memset(o, 0, sizeof *o);
    o->frame = -1;
    joint_run_opts_default(&o->j);
    rc = cli_parse(argc, argv, &args);
    o->model = pos[0];
    o->file = pos[1];
    return rc;
}

/* Read the model file. 0, -1 cannot open, -2 malformed (message in why). */
static int sk_load_model(const char *path, sk_model_t *m, char *why, size_t whylen)
{
    FILE *f = fopen(path, "r");
    char line[SK_LINE];
    unsigned long lineno = 0;
    memset(m, 0, sizeof *m);
    if (f == NULL) {
        return -1;
    }
    /* keep every line's text: the joints point into it */
    while (fgets(line, sizeof line, f) != NULL) {
        const size_t len = strlen(line);
        char *tok[6];
        int nt = 0;
        char *p, *copy;
        sk_joint_t *j;
        lineno++;
        if (len == sizeof line - 1u && line[len - 1u] != '\n') {
            (void)snprintf(why, whylen, "line %lu: line too long", lineno);
            fclose(f);
            return -2;
        }
        p = strchr(line, '#');
        if (p != NULL) {
            *p = '\0';
        }
        if (line[strspn(line, " \t\r\n")] == '\0') {
            continue;
        }
        if (m->n >= SK_MAX_JOINTS) {
            (void)snprintf(why, whylen, "more than %d joints", SK_MAX_JOINTS);
            fclose(f);
            return -2;
        }
        copy = malloc(len + 1u);
        if (copy == NULL) {
            (void)snprintf(why, whylen, "out of memory");
            fclose(f);
            return -2;
        }
        memcpy(copy, line, len + 1u);
        for (p = strtok(copy, " \t\r\n"); p != NULL && nt < 6; p = strtok(NULL, " \t\r\n")) {
            tok[nt++] = p;
        }
        j = &m->j[m->n];
        memset(j, 0, sizeof *j);
        if (nt < 4 || nt > 5 || strcmp(tok[0], "joint") != 0) {
            (void)snprintf(why, whylen,
                           "line %lu: expected: joint NAME PARENT_MARKERS CHILD_MARKERS [MODE]",
                           lineno);
            free(copy);
            fclose(f);
            return -2;
        }
        (void)snprintf(j->name, sizeof j->name, "%s", tok[1]);
        j->parent_list = tok[2];
        j->child_list = tok[3];
        if (nt == 5) {
            j->has_mode = 1;
            if (cli_parse_mode(tok[4], &j->mode) != 0) {
                (void)snprintf(why, whylen, "line %lu: MODE is auto, sphere or planar", lineno);
                free(copy);
                fclose(f);
                return -2;
            }
        }
        /* split copies of the lists (the originals name the segments) */
        {
            const size_t lp = strlen(tok[2]), lc = strlen(tok[3]);
            char *lists = malloc(lp + lc + 2u);
            if (lists == NULL) {
                (void)snprintf(why, whylen, "out of memory");
                free(copy);
                fclose(f);
                return -2;
            }
            memcpy(lists, tok[2], lp + 1u);
            memcpy(lists + lp + 1u, tok[3], lc + 1u);
            j->np = frames_split_list(lists, j->names, SFIT_CLUSTER_MAX_MARKERS);
            j->nc = (j->np < 0) ? -1
                                : frames_split_list(lists + lp + 1u, j->names + j->np,
                                                 SFIT_JOINT_MAX_CHILD);
            if (j->np < 3 || j->nc < 1) {
                (void)snprintf(why, whylen,
                               "line %lu: 3 to %d parent markers and 1 to %d child markers", lineno, SFIT_CLUSTER_MAX_MARKERS, SFIT_JOINT_MAX_CHILD);
                free(lists);
                free(copy);
                fclose(f);
                return -2;
            }
            j->own_lists = lists;
        }
        j->own_line = copy;
        m->n++;
    }
    fclose(f);
    if (m->n == 0) {
        (void)snprintf(why, whylen, "no joint");
        return -2;
    }
    return 0;
}

static void sk_free(sk_model_t *m)
{
    int k;
    for (k = 0; k < m->n; k++) {
        free(m->j[k].own_line);
        free(m->j[k].own_lists);
        joint_run_free(&m->j[k].out);
        if (m->j[k].swaps_ok) {
            swaps_joint_free(&m->j[k].swaps);
        }
    }
}

/* ------------------------------------------------------------------ SVG */

typedef struct sk_view {
    int h, v;     /* lab axes drawn horizontally and vertically */
    double x0, y0; /* panel origin (px) */
} sk_view_t;

typedef struct sk_canvas {
    double lo[3], hi[3]; /* bounds of what is drawn, per lab axis */
    double scale;        /* px per unit */
    double pw, ph;       /* panel size (px) */
    sk_view_t view[2];
} sk_canvas_t;

static void bound(sk_canvas_t *c, const sfit_vec3_t *p)
{
    int i;
    for (i = 0; i < 3; i++) {
        const double x = (double)p->v[i];
        if (isfinite(x)) {
            if (x < c->lo[i]) {
                c->lo[i] = x;
            }
            if (x > c->hi[i]) {
                c->hi[i] = x;
            }
        }
    }
}

static int finite3(const sfit_vec3_t *p)
{
    return isfinite(p->v[0]) && isfinite(p->v[1]) && isfinite(p->v[2]);
}

static void proj(const sk_canvas_t *c, int w, const sfit_vec3_t *p, double *x, double *y)
{
    const sk_view_t *v = &c->view[w];
    *x = v->x0 + 20.0 + ((double)p->v[v->h] - c->lo[v->h]) * c->scale;
    *y = v->y0 + c->ph - 20.0 - ((double)p->v[v->v] - c->lo[v->v]) * c->scale;
}

static sfit_vec3_t centroid(const sfit_vec3_t *p, int n)
{
    sfit_vec3_t c = {{0.0f, 0.0f, 0.0f}};
    int k, i, m = 0;
    for (k = 0; k < n; k++) {
        if (finite3(&p[k])) {
            for (i = 0; i < 3; i++) {
                c.v[i] += p[k].v[i];
            }
            m++;
        }
    }
    for (i = 0; i < 3; i++) {
        c.v[i] = (m > 0) ? c.v[i] / (float)m : NAN;
    }
    return c;
}

static void line(FILE *f, const sk_canvas_t *c, int w, const sfit_vec3_t *a, const sfit_vec3_t *b,
                 const char *cls)
{
    double x1, y1, x2, y2;
    if (!finite3(a) || !finite3(b)) {
        return;
    }
    proj(c, w, a, &x1, &y1);
    proj(c, w, b, &x2, &y2);
    svg_line(f, cls, x1, y1, x2, y2);
}

/* Segment lines of view w: per distinct marker list, between its joints'
 * centres, or from its only joint's centre to its markers' centroid. */
static void draw_segments(FILE *f, const sk_canvas_t *c, int w, const sk_model_t *m)
{
    int a, b;
    for (a = 0; a < m->n; a++) {
        int side;
        for (side = 0; side < 2; side++) {
            const char *list = side == 0 ? m->j[a].parent_list : m->j[a].child_list;
            int first = -1, cnt = 0, seen = 0;
            /* draw each segment once: at its first occurrence */
            for (b = 0; b < m->n && !seen; b++) {
                int s2;
                for (s2 = 0; s2 < 2; s2++) {
                    const char *l2 = s2 == 0 ? m->j[b].parent_list : m->j[b].child_list;
                    if ((b < a || (b == a && s2 < side)) && strcmp(l2, list) == 0) {
                        seen = 1;
                    }
                }
            }
            if (seen) {
                continue;
            }
            for (b = 0; b < m->n; b++) {
                if (!m->j[b].lab_ok) {
                    continue;
                }
                if (strcmp(m->j[b].parent_list, list) == 0 || strcmp(m->j[b].child_list, list) == 0) {
                    if (first >= 0) {
                        line(f, c, w, &m->j[first].lab, &m->j[b].lab, "seg");
                    } else {
                        first = b;
                    }
                    cnt++;
                }
            }
            if (cnt == 1) {
                const sk_joint_t *j = &m->j[first];
                const int ofs = (strcmp(j->parent_list, list) == 0) ? 0 : j->np;
                const int n = (ofs == 0) ? j->np : j->nc;
                const sfit_vec3_t cen = centroid(&j->mk[ofs], n);
                line(f, c, w, &j->lab, &cen, "seg");
            }
        }
    }
}

static int write_svg(const sk_opts_t *o, const frames_data_t *all, const sk_model_t *m, long k)
{
    static const char *const axis_name[3] = {"X", "Y", "Z"};
    sk_canvas_t c;
    FILE *f;
    int i, a, w, up = 2, h1, h2;
    double span[3], best = -1.0, pan_w, pan_h;
    for (i = 0; i < 3; i++) {
        c.lo[i] = HUGE_VAL;
        c.hi[i] = -HUGE_VAL;
    }
    if (all != NULL && all->all_xyz != NULL && k < all->nframes) {
        for (i = 0; i < all->nall; i++) {
            bound(&c, (const sfit_vec3_t *)(const void *)(all->all_xyz
                                                          + ((size_t)k * (size_t)all->nall
                                                             + (size_t)i) * 3u));
        }
    }
    for (a = 0; a < m->n; a++) {
        for (i = 0; i < m->j[a].np + m->j[a].nc; i++) {
            bound(&c, &m->j[a].mk[i]);
        }
        if (m->j[a].lab_ok) {
            bound(&c, &m->j[a].lab);
        }
    }
    for (i = 0; i < 3; i++) {
        span[i] = (c.hi[i] >= c.lo[i]) ? c.hi[i] - c.lo[i] : 0.0;
        if (span[i] > best) {
            best = span[i];
            up = i;
        }
    }
    if (!(best > 0.0)) {
        fprintf(stderr, "sfit: nothing to draw at frame %ld\n", k);
        return -1;
    }
    h1 = (up + 1) % 3;
    h2 = (up + 2) % 3;
    if (h1 > h2) {
        const int t = h1;
        h1 = h2;
        h2 = t;
    }
    /* 5 % margin around everything */
    for (i = 0; i < 3; i++) {
        const double pad = 0.05 * best;
        c.lo[i] -= pad;
        c.hi[i] += pad;
        span[i] = c.hi[i] - c.lo[i];
    }
    c.scale = 560.0 / span[up];
    pan_h = 560.0 + 40.0;
    pan_w = (span[h1] > span[h2] ? span[h1] : span[h2]) * c.scale + 40.0;
    if (pan_w < 260.0) {
        pan_w = 260.0;
    }
    c.pw = pan_w;
    c.ph = pan_h;
    c.view[0].h = h2; /* view along h1 */
    c.view[0].v = up;
    c.view[0].x0 = 0.0;
    c.view[0].y0 = 40.0;
    c.view[1].h = h1; /* view along h2 */
    c.view[1].v = up;
    c.view[1].x0 = pan_w + 20.0;
    c.view[1].y0 = 40.0;
    f = svg_open(o->svg, 2.0 * pan_w + 20.0, pan_h + 100.0);
    if (f == NULL) {
        return -1;
    }
    fputs("<style>\n"
          "  text { font-family: sans-serif; }\n"
          "  .title { font-size: 15px; font-weight: bold; }\n"
          "  .view { font-size: 13px; fill: #333; }\n"
          "  .lbl { font-size: 10px; fill: #225; }\n"
          "  .jlbl { font-size: 13px; fill: #b00; font-weight: bold; }\n"
          "  .seg { stroke: #444; stroke-width: 4; stroke-linecap: round; }\n"
          "  .frame { fill: #fafafa; stroke: #ccc; }\n"
          "  .ctx { fill: #bbb; }\n"
          "  .par { fill: #2a6fdb; }\n"
          "  .chi { fill: #1b9e4b; }\n"
          "  .jc { fill: #d00; stroke: #fff; stroke-width: 1.5; }\n"
          "  .axis { stroke: #d00; stroke-width: 2; stroke-dasharray: 6 3; }\n"
          "</style>\n",
          f);
    {
        char title[256];
        (void)snprintf(title, sizeof title, "sfit skeleton: %s, frame %ld (lab frame, %s)",
                       o->file, k, all != NULL && all->units[0] != '\0' ? all->units : "units");
        svg_text(f, 10.0, 22.0, "title", title);
    }
    for (w = 0; w < 2; w++) {
        const sk_view_t *v = &c.view[w];
        char cap[96];
        fprintf(f, "<rect class=\"frame\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\"/>\n",
                v->x0, v->y0, pan_w, pan_h);
        (void)snprintf(cap, sizeof cap, "view along %s: %s right, %s up",
                       axis_name[w == 0 ? h1 : h2], axis_name[v->h], axis_name[v->v]);
        svg_text(f, v->x0 + 8.0, v->y0 + pan_h + 20.0, "view", cap);
        if (all != NULL && all->all_xyz != NULL && k < all->nframes) {
            for (i = 0; i < all->nall; i++) {
                const sfit_vec3_t *p = (const sfit_vec3_t *)(const void *)(
                    all->all_xyz + ((size_t)k * (size_t)all->nall + (size_t)i) * 3u);
                double x, y;
                if (finite3(p)) {
                    proj(&c, w, p, &x, &y);
                    fprintf(f, "<circle class=\"ctx\" cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\"/>\n", x, y);
                }
            }
        }
        draw_segments(f, &c, w, m);
        for (a = 0; a < m->n; a++) {
            const sk_joint_t *j = &m->j[a];
            for (i = 0; i < j->np + j->nc; i++) {
                double x, y;
                if (!finite3(&j->mk[i])) {
                    continue;
                }
                proj(&c, w, &j->mk[i], &x, &y);
                fprintf(f, "<circle class=\"%s\" cx=\"%.1f\" cy=\"%.1f\" r=\"4\"/>\n",
                        i < j->np ? "par" : "chi", x, y);
                svg_text(f, x + 5.0, y - 4.0, "lbl", j->names[i]);
            }
        }
        for (a = 0; a < m->n; a++) {
            const sk_joint_t *j = &m->j[a];
            double x, y;
            if (!j->lab_ok) {
                continue;
            }
            if (j->out.res.fit.mode == SFIT_MODE_PLANAR) { /* the hinge axis */
                const float half = (float)(0.08 * span[up]);
                sfit_vec3_t p0, p1;
                for (i = 0; i < 3; i++) {
                    p0.v[i] = j->lab.v[i] - half * j->axis_lab.v[i];
                    p1.v[i] = j->lab.v[i] + half * j->axis_lab.v[i];
                }
                line(f, &c, w, &p0, &p1, "axis");
            }
            proj(&c, w, &j->lab, &x, &y);
            fprintf(f, "<circle class=\"jc\" cx=\"%.1f\" cy=\"%.1f\" r=\"7\"/>\n", x, y);
            svg_text(f, x + 10.0, y + 16.0, "jlbl", j->name);
        }
    }
    fprintf(f, "<text class=\"view\" x=\"10\" y=\"%.0f\">red: joint centres (sfit), dashed: hinge axis; blue: "
               "parent markers; green: child markers; grey: other markers</text>\n",
            pan_h + 90.0);
    return svg_close(f, o->svg);
}

/* ------------------------------------------------------------- command */

static void print_joint_json(const sk_joint_t *j)
{
    const sfit_multi_result_t *r = &j->out.res.fit;
    int k;
    printf("{\"name\":");
    json_out_str(stdout, j->name, 0);
    if (j->st != SFIT_OK) {
        printf(",\"status\":\"%s\",\"message\":\"%s\",\"stage\":\"%s\"}", sfit_status_str(j->st),
               names_status_message(j->st, NAMES_CLI), j->stage);
        return;
    }
    printf(",\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"frames_used\":%ld,"
           "\"frames_rejected\":%ld,\"reference_frame\":%ld,\"center\":",
           j->out.pair_used ? j->out.method_name : r->method == SFIT_METHOD_UGDK ? "ugdk" : "gdke",
           r->mode == SFIT_MODE_PLANAR ? "planar" : "sphere", j->out.used, j->out.rejected,
           j->out.ref_frame);
    json_out_vec(stdout, r->center.v);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf(",\"axis\":");
        json_out_vec(stdout, r->axis.v);
    }
    printf(",\"center_lab\":");
    if (j->lab_ok) {
        json_out_vec(stdout, j->lab.v);
    } else {
        printf("null");
    }
    printf(",\"flags\":");
    cli_joint_print_flags_json(&j->out);
    cli_joint_print_pair_json(&j->out);
    printf(",\"residual_mean\":%.9g,\"radii\":[", (double)j->out.res.residual_mean);
    for (k = 0; k < j->nc; k++) {
        printf("%s%.9g", k > 0 ? "," : "", (double)j->out.radii[k]);
    }
    printf("]");
    if (j->swaps_ok) {
        cli_swaps_json(&j->swaps, (const char *const *)j->names, j->np);
    }
    printf("}");
}

static void print_joint_human(const sk_joint_t *j, long frame, const char *units)
{
    const sfit_multi_result_t *r = &j->out.res.fit;
    if (j->st != SFIT_OK) {
        printf("%-12s failed at the %s stage (%s): %s\n", j->name, j->stage,
               sfit_status_str(j->st), names_status_message(j->st, NAMES_CLI));
        return;
    }
    printf("%-12s %s, %ld frames used, %ld rejected, registration residual %.3g\n", j->name,
           r->mode == SFIT_MODE_PLANAR ? "hinge" : "ball joint", j->out.used, j->out.rejected,
           (double)j->out.res.residual_mean);
    printf("  centre       %.4f %.4f %.4f (parent frame: template frame, reference frame %ld)\n",
           (double)r->center.v[0], (double)r->center.v[1], (double)r->center.v[2],
           j->out.ref_frame);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf("  axis         %.5f %.5f %.5f (parent frame)\n", (double)r->axis.v[0],
               (double)r->axis.v[1], (double)r->axis.v[2]);
    }
    cli_joint_print_pair_text(&j->out, "units", "  ");
    if (j->lab_ok) {
        printf("  centre (lab) %.4f %.4f %.4f at frame %ld\n", (double)j->lab.v[0],
               (double)j->lab.v[1], (double)j->lab.v[2], frame);
    } else {
        printf("  centre (lab) n/a at frame %ld (parent not registrable there)\n", frame);
    }
    if (j->swaps_ok) {
        cli_swaps_human(&j->swaps, (const char *const *)j->names, j->np, units,
                              "  label swaps  ", "               ");
    }
}

/* 1 when the file at path is a session model (a `segment NAME MARKERS` line
 * before any `joint` line), 0 otherwise (the joint-by-joint form, a C3D file,
 * or a file that cannot be read: the form that opens it says why). */
static int sk_is_session_model(const char *path)
{
    FILE *f = fopen(path, "r");
    char line[SK_LINE];
    int is = 0, lines = 0;
    if (f == NULL) {
        return 0;
    }
    while (fgets(line, sizeof line, f) != NULL && lines < 10000) {
        const char *p = line;
        lines++;
        while (*p == ' ' || *p == '\t') {
            p++;
        }
        if (strncmp(p, "segment", 7) == 0 && (p[7] == ' ' || p[7] == '\t')) {
            is = 1;
            break;
        }
        if (strncmp(p, "joint", 5) == 0 && (p[5] == ' ' || p[5] == '\t')) {
            break;
        }
        if ((unsigned char)p[0] >= 0x80u || (p[0] != '\0' && p[0] < ' ' && p[0] != '\n'
                                                 && p[0] != '\r')) {
            break; /* binary (a C3D file) */
        }
    }
    fclose(f);
    return is;
}

/* `sfit skeleton MODEL TRIALS...` with a session model: the same as
 * `sfit skeleton TRIALS... --segments MODEL`. -1 when the first file is not a
 * session model, else the exit status. */
static int sk_session_form(int argc, char **argv)
{
    int i, first = -1, rc;
    char **av;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--segments") == 0) {
            return -1;
        }
    }
    for (i = 1; i < argc; i++) {
        if (argv[i][0] == '-') {
            if (strcmp(argv[i], "--svg") == 0 || strcmp(argv[i], "--frame") == 0
                || strcmp(argv[i], "--frames") == 0 || strcmp(argv[i], "--noise-var") == 0
                || strcmp(argv[i], "--mode") == 0 || strcmp(argv[i], "--method") == 0
                || strcmp(argv[i], "--root") == 0 || strcmp(argv[i], "--step") == 0
                || strcmp(argv[i], "--bvh") == 0 || strcmp(argv[i], "--trc") == 0
                || strcmp(argv[i], "--html") == 0 || strcmp(argv[i], "--centres") == 0) {
                i++;
            }
            continue;
        }
        first = i;
        break;
    }
    if (first < 0 || !sk_is_session_model(argv[first])) {
        return -1;
    }
    av = malloc(((size_t)argc + 2u) * sizeof *av);
    if (av == NULL) {
        fprintf(stderr, "sfit: out of memory\n");
        return CLI_FAIL;
    }
    {
        static char seg_opt[] = "--segments";
        int n = 0;
        for (i = 0; i < argc; i++) {
            if (i != first) {
                av[n++] = argv[i];
            }
        }
        av[n++] = seg_opt;
        av[n++] = argv[first];
        av[n] = NULL;
        rc = skel_cmd(n, av);
    }
    free(av);
    return rc;
}

/* `sfit skeleton --help` with no file: both forms, every option. */
static int sk_help_only(int argc, char **argv)
{
    return argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0);
}

int cli_cmd_skeleton(int argc, char **argv)
{
    sk_opts_t o;
    sk_model_t *m;
    frames_data_t keep; /* the first joint's load: context points for the picture */
    char why[FRAMES_ERR_MAX];
    long frame = 0;
    int a, rc = CLI_OK, failed = 0, have_keep = 0;

    if (sk_help_only(argc, argv)) {
        char *av[3] = {argv[0], argv[1], NULL};
        (void)skel_cmd(2, av);
        fputs("\nThe joint-by-joint form (each joint's parent and child markers listed in\n"
              "MODEL instead of a session model's segments):\n",
              stdout);
        sk_usage(stdout);
        return CLI_OK;
    }
    {
        const int src = sk_session_form(argc, argv);
        if (src >= 0) {
            return src;
        }
    }
    if (skel_cmd_wanted(argc, argv)) {
        return skel_cmd(argc, argv);
    }
    {
        const int prc = sk_parse(argc, argv, &o);
        if (prc >= 0) {
            return prc;
        }
    }
    m = calloc(1u, sizeof *m);
    if (m == NULL) {
        fprintf(stderr, "sfit: out of memory\n");
        return CLI_FAIL;
    }
    rc = sk_load_model(o.model, m, why, sizeof why);
    if (rc != 0) {
        sk_free(m);
        free(m);
        return cli_input_failed(rc, o.model, why, o.json);
    }
    memset(&keep, 0, sizeof keep);
    for (a = 0; a < m->n; a++) {
        sk_joint_t *j = &m->j[a];
        joint_run_opts_t jo = o.j;
        frames_data_t fr;
        int i;
        rc = frames_load(o.file, (const char *const *)j->names, j->np + j->nc, &fr, why);
        if (rc != 0) {
            if (have_keep) {
                frames_free(&keep);
            }
            sk_free(m);
            free(m);
            return cli_input_failed(rc, o.file, why, o.json);
        }
        if (a == 0) {
            frame = (o.frame >= 0) ? o.frame : o.j.first;
            if (frame >= fr.nframes || o.j.first >= fr.nframes) {
                (void)snprintf(why, sizeof why, "frame %ld: the file has %ld frames",
                               frame >= fr.nframes ? frame : o.j.first, fr.nframes);
                frames_free(&fr);
                sk_free(m);
                free(m);
                return cli_input_failed(-2, o.file, why, o.json);
            }
        }
        if (j->has_mode) {
            jo.mode = j->mode;
        }
        j->swaps_ok = (swaps_joint_run(&fr, j->np, j->nc, jo.first, jo.last,
                                           !jo.no_repair_swaps, &j->swaps) == 0);
        j->st = joint_run(&fr, j->np, j->nc, &jo, &j->out);
        j->stage = j->out.stage;
        for (i = 0; i < j->np + j->nc; i++) {
            j->mk[i] = *frames_at(&fr, frame, i);
        }
        if (j->st == SFIT_OK) {
            j->lab_ok = (joint_run_lab(&fr, j->np, &j->out, frame, &j->lab, &j->axis_lab) == SFIT_OK);
        } else {
            failed++;
        }
        if (a == 0) {
            keep = fr;
            have_keep = 1;
        } else {
            frames_free(&fr);
        }
    }
    if (o.json) {
        printf("{\"status\":\"%s\",\"frame\":%ld,\"joints\":[", failed ? "joint_failed" : "ok",
               frame);
        for (a = 0; a < m->n; a++) {
            if (a > 0) {
                printf(",");
            }
            print_joint_json(&m->j[a]);
        }
        printf("]");
        if (o.svg != NULL) {
            printf(",\"svg\":");
            json_out_str(stdout, o.svg, 0);
        }
        printf("}\n");
    } else {
        printf("file         %s, model %s, %d joints\n", o.file, o.model, m->n);
        for (a = 0; a < m->n; a++) {
            print_joint_human(&m->j[a], frame,
                              keep.units[0] != '\0' ? keep.units : "units");
        }
    }
    rc = failed ? CLI_FAIL : CLI_OK;
    if (o.svg != NULL && write_svg(&o, &keep, m, frame) != 0) {
        rc = CLI_IO;
    }
    if (o.svg != NULL && !o.json && rc != CLI_IO) {
        printf("picture      %s (frame %ld)\n", o.svg, frame);
    }
    frames_free(&keep);
    sk_free(m);
    free(m);
    return rc;
}
