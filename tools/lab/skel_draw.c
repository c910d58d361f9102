/* SPDX-License-Identifier: MIT */
/**
 * @file skel_draw.c
 * @brief Pictures of the found skeleton: an SVG at one frame (two
 * orthographic views) and a self-contained HTML page that plays it over
 * the markers (inline script, no network; docs/skeleton.md).
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json_out.h"
#include "skel.h"
#include "svg.h"

static const char *const k_colour[] = {"#2a6fdb", "#1b9e4b", "#e08a00", "#8e44ad",
                                       "#c0392b", "#16a085", "#7f8c8d", "#d35400"};
#define NCOL (int)(sizeof k_colour / sizeof k_colour[0])

/* Position of segment k's node (root: its origin; else its joint centre). */
static const double *node(const skel_t *s, long f, int k)
{
    const int j = s->parent_joint[k];
    if (k == s->root) {
        return &s->root_t[f * 3];
    }
    return j >= 0 ? &s->jc[((size_t)f * (size_t)s->njoint + (size_t)j) * 3u] : NULL;
}

static int finite3d(const double *p)
{
    return p != NULL && isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* Segment of marker m (-1: none). */
static int seg_of(const skel_t *s, int m)
{
    int k, i;
    for (k = 0; k < s->nseg; k++) {
        for (i = 0; i < s->seg[k].nm; i++) {
            if (s->seg[k].mk[i] == m) {
                return k;
            }
        }
    }
    return -1;
}

/* The picture's vertical: the lab axis along which the skeleton (its
 * nodes and end sites) spreads most, summed over (up to 500) frames; its
 * sign puts the end site of the leaf farthest from the root (in joints)
 * below the root on average. */
static void view_up(const skel_t *s, int *up, double *sign)
{
    const long nf = s->rec->nframes;
    const long step = nf > 500 ? nf / 500 : 1;
    double ext[3] = {0.0, 0.0, 0.0}, below = 0.0;
    int k, i, deep = -1, best = -1;
    long f;
    for (k = 0; k < s->nseg; k++) {
        int d = 0, c = k;
        if (!s->leaf[k]) {
            continue;
        }
        while (s->parent_joint[c] >= 0 && d < SKEL_MAX_SEG) {
            c = s->joint[s->parent_joint[c]].parent;
            d++;
        }
        if (d > best) {
            best = d;
            deep = k;
        }
    }
    for (f = 0; f < nf; f += step) {
        double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (k = 0; k < s->nseg; k++) {
            const double *p[2];
            int t;
            p[0] = node(s, f, k);
            p[1] = s->leaf[k] ? &s->ends[((size_t)f * (size_t)s->nseg + (size_t)k) * 3u] : NULL;
            for (t = 0; t < 2; t++) {
                for (i = 0; i < 3 && finite3d(p[t]); i++) {
                    lo[i] = p[t][i] < lo[i] ? p[t][i] : lo[i];
                    hi[i] = p[t][i] > hi[i] ? p[t][i] : hi[i];
                }
            }
        }
        for (i = 0; i < 3; i++) {
            ext[i] += hi[i] > lo[i] ? hi[i] - lo[i] : 0.0;
        }
    }
    *up = 2;
    for (i = 0; i < 3; i++) {
        if (ext[i] > ext[*up]) {
            *up = i;
        }
    }
    for (f = 0; deep >= 0 && f < nf; f += step) {
        const double *e = &s->ends[((size_t)f * (size_t)s->nseg + (size_t)deep) * 3u];
        if (finite3d(e)) {
            below += e[*up] - s->root_t[f * 3 + *up];
        }
    }
    *sign = below > 0.0 ? -1.0 : 1.0;
}

/* ------------------------------------------------------------------ SVG */

typedef struct view {
    int h, v;
    double sign; /* vertical = sign * p[v] */
    double x0, y0, lo_h, lo_v, scale, ph;
} view_t;

static void px(const view_t *w, const double *p, double *x, double *y)
{
    *x = w->x0 + 20.0 + (p[w->h] - w->lo_h) * w->scale;
    *y = w->y0 + w->ph - 20.0 - (w->sign * p[w->v] - w->lo_v) * w->scale;
}

int skel_write_svg(const skel_t *s, const char *path, long fr)
{
    static const char *const axn[3] = {"X", "Y", "Z"};
    int up, h1, h2;
    double sg;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    double pw, ph = 600.0, scale, span;
    view_t w[2];
    FILE *f;
    int m, i, k, v;
    view_up(s, &up, &sg);
    h1 = up == 0 ? 1 : 0;
    h2 = up == 2 ? 1 : 2;
    for (m = 0; m < s->rec->nmark; m++) {
        const float *p = skel_rec_at(s->rec, fr, m);
        for (i = 0; i < 3; i++) {
            const double x = (i == up ? sg : 1.0) * (double)p[i];
            if (isfinite(x)) {
                lo[i] = x < lo[i] ? x : lo[i];
                hi[i] = x > hi[i] ? x : hi[i];
            }
        }
    }
    for (k = 0; k < s->nseg; k++) {
        const double *p = node(s, fr, k);
        for (i = 0; i < 3 && finite3d(p); i++) {
            const double x = (i == up ? sg : 1.0) * p[i];
            lo[i] = x < lo[i] ? x : lo[i];
            hi[i] = x > hi[i] ? x : hi[i];
        }
    }
    span = hi[up] - lo[up];
    if (!(span > 0.0)) {
        fprintf(stderr, "sfit: nothing to draw at frame %ld\n", fr);
        return -1;
    }
    for (i = 0; i < 3; i++) {
        lo[i] -= 0.05 * span;
        hi[i] += 0.05 * span;
    }
    scale = (ph - 40.0) / (hi[up] - lo[up]);
    pw = ((hi[h1] - lo[h1]) > (hi[h2] - lo[h2]) ? hi[h1] - lo[h1] : hi[h2] - lo[h2]) * scale + 40.0;
    if (pw < 260.0) {
        pw = 260.0;
    }
    for (v = 0; v < 2; v++) {
        w[v].h = v == 0 ? h2 : h1;
        w[v].v = up;
        w[v].sign = sg;
        w[v].x0 = v == 0 ? 0.0 : pw + 20.0;
        w[v].y0 = 40.0;
        w[v].lo_h = lo[w[v].h];
        w[v].lo_v = lo[up];
        w[v].scale = scale;
        w[v].ph = ph;
    }
    f = svg_open(path, 2.0 * pw + 20.0, ph + 106.0);
    if (f == NULL) {
        return -1;
    }
    fputs("<style>text{font-family:sans-serif}.t{font-size:15px;font-weight:bold}"
          ".c{font-size:13px;fill:#333}.j{font-size:12px;fill:#b00;font-weight:bold}"
          ".b{stroke:#333;stroke-width:5;stroke-linecap:round}.fr{fill:#fafafa;stroke:#ccc}"
          ".u{stroke:#e80;stroke-width:4;stroke-dasharray:2 6;stroke-linecap:round}"
          ".jc{fill:#d00;stroke:#fff;stroke-width:1.5}.ax{stroke:#d00;stroke-width:2;"
          "stroke-dasharray:6 3}</style>\n",
          f);
    fprintf(f, "<text class=\"t\" x=\"10\" y=\"22\">sfit skeleton: frame %ld of %ld, %d segments, "
               "%d joints (lab frame, ",
            fr, s->rec->nframes, s->nseg, s->njoint);
    svg_esc(f, s->rec->units[0] ? s->rec->units : "units", 1);
    fputs(")</text>\n", f);
    for (v = 0; v < 2; v++) {
        double x, y, x2, y2;
        fprintf(f, "<rect class=\"fr\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\"/>\n",
                w[v].x0, w[v].y0, pw, ph);
        fprintf(f, "<text class=\"c\" x=\"%.1f\" y=\"%.1f\">view along %s: %s right, %s%s up</text>\n",
                w[v].x0 + 8.0, w[v].y0 + ph + 18.0, axn[v == 0 ? h1 : h2], axn[w[v].h],
                sg < 0.0 ? "-" : "", axn[up]);
        for (m = 0; m < s->rec->nmark; m++) {
            const float *p = skel_rec_at(s->rec, fr, m);
            const int g = seg_of(s, m);
            double d[3];
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                continue;
            }
            d[0] = (double)p[0];
            d[1] = (double)p[1];
            d[2] = (double)p[2];
            px(&w[v], d, &x, &y);
            fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>\n", x, y,
                    g >= 0 ? k_colour[g % NCOL] : "#bbb");
        }
        for (k = 0; k < s->nseg; k++) { /* bones */
            const int j = s->parent_joint[k];
            if (j >= 0) {
                const double *a = node(s, fr, s->joint[j].parent), *b = node(s, fr, k);
                if (finite3d(a) && finite3d(b)) {
                    px(&w[v], a, &x, &y);
                    px(&w[v], b, &x2, &y2);
                    svg_line(f, (s->joint[j].pr.flags & SKEL_F_UNTRUSTED) ? "u" : "b", x, y, x2, y2);
                }
            }
            if (s->leaf[k]) {
                const double *a = node(s, fr, k);
                const double *b = &s->ends[((size_t)fr * (size_t)s->nseg + (size_t)k) * 3u];
                if (finite3d(a) && finite3d(b)) {
                    px(&w[v], a, &x, &y);
                    px(&w[v], b, &x2, &y2);
                    fprintf(f, "<line class=\"b\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" "
                               "stroke-dasharray=\"8 5\"/>\n",
                            x, y, x2, y2);
                }
            }
        }
        for (k = 0; k < s->nseg; k++) {
            const double *a = node(s, fr, k);
            const int j = s->parent_joint[k];
            if (!finite3d(a) || (j < 0 && k != s->root)) {
                continue;
            }
            if (j >= 0 && s->joint[j].pr.type == SKEL_HINGE) {
                const double *q = &s->pose[((size_t)fr * (size_t)s->nseg
                                            + (size_t)s->joint[j].parent) * 12u];
                double ax[3], p0[3], p1[3];
                for (i = 0; i < 3; i++) {
                    ax[i] = q[i * 3] * s->joint[j].pr.axis_a[0] + q[i * 3 + 1] * s->joint[j].pr.axis_a[1]
                            + q[i * 3 + 2] * s->joint[j].pr.axis_a[2];
                    p0[i] = a[i] - 0.06 * span * ax[i];
                    p1[i] = a[i] + 0.06 * span * ax[i];
                }
                px(&w[v], p0, &x, &y);
                px(&w[v], p1, &x2, &y2);
                svg_line(f, "ax", x, y, x2, y2);
            }
            px(&w[v], a, &x, &y);
            fprintf(f, "<circle class=\"jc\" cx=\"%.1f\" cy=\"%.1f\" r=\"6\"/>\n", x, y);
            fprintf(f, "<text class=\"j\" x=\"%.1f\" y=\"%.1f\">", x + 9.0, y + 14.0);
            svg_esc(f, j >= 0 ? s->joint[j].name : s->seg[k].name, 1);
            fputs("</text>\n", f);
        }
    }
    fprintf(f, "<text class=\"c\" x=\"10\" y=\"%.0f\">red: joint centres (root: its segment's "
               "marker centroid); dark: bones (dashed: to a leaf's marker centroid);</text>\n"
               "<text class=\"c\" x=\"10\" y=\"%.0f\">orange dots: a bone whose joint is "
               "untrusted; dots: markers, coloured by segment (grey: none)</text>\n",
            ph + 80.0, ph + 96.0);
    return svg_close(f, path);
}

/* ----------------------------------------------------------------- HTML */

#define HTML_MAX_FRAMES 2000L

/* Number for the page's data: enough digits for mm and m alike. */
static void jnum6(FILE *f, double x)
{
    if (isfinite(x)) {
        fprintf(f, "%.6g", x);
    } else {
        fputs("null", f);
    }
}

/* Segment k's joint's 95 % ellipsoid in the lab at frame fr, packed xx yy
 * zz xy xz yz: chi2 (3 dof; a hinge, whose covariance is the part normal
 * to its axis: 2) times R_p C R_p^T, C the covariance in the parent
 * segment's frame. 0, or -1 (no joint, or no parent pose in the frame). */
static int lab_ellipsoid(const skel_t *s, long fr, int k, double e[6])
{
    const int j = s->parent_joint[k];
    const skel_joint_t *jt;
    const double *R;
    double T[9], q;
    int a, b, c;
    if (j < 0) {
        return -1;
    }
    jt = &s->joint[j];
    if (!s->pose_ok[(size_t)fr * (size_t)s->nseg + (size_t)jt->parent]) {
        return -1;
    }
    R = &s->pose[((size_t)fr * (size_t)s->nseg + (size_t)jt->parent) * 12u];
    q = jt->pr.type == SKEL_HINGE ? 5.991464547107979 : 7.814727903251178;
    for (a = 0; a < 3; a++) { /* T = R C */
        for (b = 0; b < 3; b++) {
            T[a * 3 + b] = 0.0;
            for (c = 0; c < 3; c++) {
                T[a * 3 + b] += R[a * 3 + c] * jt->pr.cov_a[c * 3 + b];
            }
        }
    }
    {
        static const int ia[6] = {0, 1, 2, 0, 0, 1}, ib[6] = {0, 1, 2, 1, 2, 2};
        for (a = 0; a < 6; a++) { /* (T R^T)[ia][ib] */
            double v = 0.0;
            for (c = 0; c < 3; c++) {
                v += T[ia[a] * 3 + c] * R[ib[a] * 3 + c];
            }
            e[a] = q * v;
            if (!isfinite(e[a])) {
                return -1;
            }
        }
    }
    return 0;
}

/* The player's script, one string per line (tools/lab/skel_view.js,
 * embedded by the build: tools/lab/embed_js.cmake). */
#include "skel_view_js.h"

int skel_write_html(const skel_t *s, const char *path)
{
    const long nf = s->rec->nframes;
    const long stride = (nf + HTML_MAX_FRAMES - 1) / HTML_MAX_FRAMES;
    FILE *f = fopen(path, "w");
    long fr;
    int k, m, i, first, nell = 0, ell[SKEL_MAX_SEG];
    size_t line;
    if (f == NULL) {
        fprintf(stderr, "sfit: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width\">\n"
          "<title>sfit skeleton</title>\n<style>\n"
          "body{font-family:sans-serif;margin:8px;background:#fff;color:#222}\n"
          "#bar{margin:4px 0;white-space:nowrap;overflow:hidden}\n"
          "#bar input[type=range]{width:380px;vertical-align:middle}\n"
          "#info{margin:2px 0 4px 0;font-size:14px;height:18px;white-space:nowrap;overflow:hidden}\n"
          "canvas{border:1px solid #ccc;background:#fbfbfb;touch-action:none;cursor:grab}\n"
          "#legend{font-size:13px;max-width:900px}\n"
          "#state{display:none}\n</style></head><body>\n"
          "<div id=\"bar\"><button id=\"play\">play</button> frame <input id=\"fr\" "
          "type=\"range\" min=\"0\" value=\"0\"> <button id=\"reset\">reset view</button> "
          "ellipsoids <select id=\"ell\"><option value=\"1\">x1</option><option "
          "value=\"5\">x5</option><option value=\"10\">x10</option><option "
          "value=\"0\">off</option></select></div>\n"
          "<div id=\"info\"></div>\n"
          "<canvas id=\"cv\" width=\"900\" height=\"600\"></canvas>\n"
          "<div id=\"legend\"></div><pre id=\"state\"></pre>\n"
          "<script>\nconst D=",
          f);
    /* data */
    {
        int up;
        double sg;
        view_up(s, &up, &sg);
        fprintf(f, "{\"rate\":%g,\"stride\":%ld,\"nframes\":%ld,\"up\":%d,\"sgn\":%g,\"units\":",
                (double)s->rec->rate, stride, nf, up, sg);
    }
    json_out_str(f, s->rec->units, JSON_OUT_HTML);
    fputs(",\"trials\":[", f);
    for (i = 0; i < s->rec->nfiles; i++) {
        const char *name = s->rec->file[i], *slash = strrchr(name, '/');
        fprintf(f, "%s{\"name\":", i ? "," : "");
        json_out_str(f, slash != NULL ? slash + 1 : name, JSON_OUT_HTML);
        fprintf(f, ",\"start\":%ld,\"frames\":%ld}", s->rec->start[i],
                s->rec->start[i + 1] - s->rec->start[i]);
    }
    fputs("],\"seg\":[", f);
    for (k = 0; k < s->nseg; k++) {
        const int j = s->parent_joint[k];
        ell[k] = (j >= 0 && k != s->root) ? nell++ : -1;
        fprintf(f, "%s{\"name\":", k ? "," : "");
        json_out_str(f, s->seg[k].name, JSON_OUT_HTML);
        fprintf(f, ",\"joint\":");
        json_out_str(f, j >= 0 ? s->joint[j].name : (k == s->root ? s->seg[k].name : ""),
                     JSON_OUT_HTML);
        fprintf(f, ",\"parent\":%d,\"in\":%d,\"leaf\":%d,\"ell\":%d,\"colour\":\"%s\"}",
                j >= 0 ? s->joint[j].parent : -1, (k == s->root || j >= 0) ? 1 : 0, s->leaf[k],
                ell[k], k_colour[k % NCOL]);
    }
    fputs("],\"mseg\":[", f);
    for (m = 0; m < s->rec->nmark; m++) {
        fprintf(f, "%s%d", m ? "," : "", seg_of(s, m));
    }
    fputs("],\n\"f\":[", f);
    first = 1;
    for (fr = 0; fr < nf; fr += stride) {
        /* per frame: nodes (per segment), end sites (per segment), markers,
         * then each joint's lab ellipsoid (6 numbers, null when unknown) */
        fprintf(f, "%s[", first ? "" : ",\n");
        first = 0;
        for (k = 0; k < s->nseg; k++) {
            const double *p = node(s, fr, k);
            for (i = 0; i < 3; i++) {
                fputs(k || i ? "," : "", f);
                jnum6(f, p != NULL ? p[i] : (double)NAN);
            }
        }
        for (k = 0; k < s->nseg; k++) {
            const double *p = &s->ends[((size_t)fr * (size_t)s->nseg + (size_t)k) * 3u];
            for (i = 0; i < 3; i++) {
                fputc(',', f);
                jnum6(f, p[i]);
            }
        }
        for (m = 0; m < s->rec->nmark; m++) {
            const float *p = skel_rec_at(s->rec, fr, m);
            for (i = 0; i < 3; i++) {
                fputc(',', f);
                jnum6(f, (double)p[i]);
            }
        }
        for (k = 0; k < s->nseg; k++) {
            double e[6];
            const int ok = ell[k] >= 0 && lab_ellipsoid(s, fr, k, e) == 0;
            if (ell[k] < 0) {
                continue;
            }
            for (i = 0; i < 6; i++) {
                fputc(',', f);
                jnum6(f, ok ? e[i] : (double)NAN);
            }
        }
        fputc(']', f);
    }
    fputs("]};\n", f);
    for (line = 0; skel_view_js[line] != NULL; line++) {
        fputs(skel_view_js[line], f);
    }
    fputs("</script></body></html>\n", f);
    if (ferror(f) != 0 || fclose(f) != 0) {
        fprintf(stderr, "sfit: cannot write %s\n", path);
        return -1;
    }
    return 0;
}
