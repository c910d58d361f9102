/* SPDX-License-Identifier: MIT */
/** @file svg.c  The SVG canvas (svg.h). */
#include "svg.h"

#include <errno.h>
#include <string.h>

FILE *svg_open(const char *path, double w, double h)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        fprintf(stderr, "sfit: cannot write %s: %s\n", path, strerror(errno));
        return NULL;
    }
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
               "viewBox=\"0 0 %.0f %.0f\">\n",
            w, h, w, h);
    return f;
}

void svg_esc(FILE *f, const char *s, int quote)
{
    for (; *s != '\0'; s++) {
        if (*s == '<') {
            fputs("&lt;", f);
        } else if (*s == '&') {
            fputs("&amp;", f);
        } else if (*s == '>') {
            fputs("&gt;", f);
        } else if (*s == '"' && quote != 0) {
            fputs("&quot;", f);
        } else {
            fputc(*s, f);
        }
    }
}

void svg_text(FILE *f, double x, double y, const char *cls, const char *s)
{
    fprintf(f, "<text class=\"%s\" x=\"%.1f\" y=\"%.1f\">", cls, x, y);
    svg_esc(f, s, 0);
    fputs("</text>\n", f);
}

void svg_line(FILE *f, const char *cls, double x1, double y1, double x2, double y2)
{
    fprintf(f, "<line class=\"%s\" x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/>\n", cls, x1,
            y1, x2, y2);
}

int svg_close(FILE *f, const char *path)
{
    fputs("</svg>\n", f);
    if (ferror(f) != 0) {
        (void)fclose(f);
        fprintf(stderr, "sfit: cannot write %s\n", path);
        return -1;
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "sfit: cannot write %s\n", path);
        return -1;
    }
    return 0;
}
