/* SPDX-License-Identifier: MIT */
/**
 * @file svg.h
 * @brief The one SVG canvas of the host tools: the document's frame (XML
 * declaration, root element with its size, the end), text escaping and the
 * two elements every picture draws (a text with a class, a line with a
 * class). Each picture (`sfit apply --svg`, `sfit skeleton --svg` of a
 * model or of the data) writes its own content between svg_open and
 * svg_close. Host only.
 */
#ifndef SFIT_SVG_H
#define SFIT_SVG_H

#include <stdio.h>

/**
 * Create `path` and write the XML declaration and the root element of a
 * w x h picture (viewBox 0 0 w h, whole numbers). NULL if the file cannot
 * be created, with "sfit: cannot write PATH: REASON" on stderr.
 */
FILE *svg_open(const char *path, double w, double h);

/** Write s with <, & and > (and " when quote is not 0) as XML entities. */
void svg_esc(FILE *f, const char *s, int quote);

/** <text class="cls" x="X" y="Y">s</text> (s escaped, one decimal). */
void svg_text(FILE *f, double x, double y, const char *cls, const char *s);

/** <line class="cls" x1=.. y1=.. x2=.. y2=../> (one decimal). */
void svg_line(FILE *f, const char *cls, double x1, double y1, double x2, double y2);

/**
 * Write the end of the document and close f. 0; -1 if a write failed,
 * with "sfit: cannot write PATH" on stderr.
 */
int svg_close(FILE *f, const char *path);

#endif /* SFIT_SVG_H */
