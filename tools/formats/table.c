/* SPDX-License-Identifier: MIT */
/** @file table.c  The delimited-text reader of the `sfit` tool (see table.h). */
#include "table.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static int table_fail(table_t *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(t->err, sizeof t->err, fmt, ap);
    va_end(ap);
    return -1;
}

static void table_zero(table_t *t)
{
    memset(t, 0, sizeof *t);
    t->at_start = 1;
}

int table_open_file(table_t *t, const char *path)
{
    table_zero(t);
    if (strcmp(path, "-") == 0) {
        t->f = stdin;
        return 0;
    }
    t->f = fopen(path, "r");
    if (t->f == NULL) {
        return -1;
    }
    t->own = 1;
    /* fopen() accepts a directory on POSIX systems; the first read fails
     * (EISDIR). Read one byte now so that such an input is an open failure
     * (exit CLI_IO), not an empty file. */
    {
        int ch = getc(t->f);
        if (ch == EOF && ferror(t->f)) {
            fclose(t->f);
            t->f = NULL;
            t->own = 0;
            return -1;
        }
        if (ch != EOF) {
            (void)ungetc(ch, t->f);
        }
    }
    return 0;
}

void table_open_mem(table_t *t, const char *buf, size_t len)
{
    table_zero(t);
    t->mem = buf;
    t->memlen = len;
}

void table_close(table_t *t)
{
    if (t->own && t->f != NULL) {
        fclose(t->f);
    }
    if (t->names != NULL) {
        int i;
        for (i = 0; i < t->ncols; i++) {
            free(t->names[i]);
        }
        free(t->names);
    }
    free(t->line);
    free(t->cells);
    free(t->sel);
    table_zero(t);
}

/* Append one byte to the line buffer (at most TABLE_LINE_MAX; beyond, the
 * line is marked cut). */
static int put(table_t *t, size_t *n, int ch)
{
    if (*n + 1u >= t->linecap) {
        size_t nc;
        char *nl;
        if (t->linecap >= TABLE_LINE_MAX) {
            t->toolong = 1;
            return 0;
        }
        nc = (t->linecap == 0u) ? 256u : 2u * t->linecap;
        if (nc > TABLE_LINE_MAX) {
            nc = TABLE_LINE_MAX;
        }
        nl = realloc(t->line, nc);
        if (nl == NULL) {
            t->toolong = 1;
            return 0;
        }
        t->line = nl;
        t->linecap = nc;
    }
    t->line[(*n)++] = (char)ch;
    return 0;
}

static int get(table_t *t)
{
    if (t->f != NULL) {
        return fgetc(t->f);
    }
    if (t->pos >= t->memlen) {
        return EOF;
    }
    return (unsigned char)t->mem[t->pos++];
}

/* Read one physical line into t->line (without the newline). 0 at EOF. */
static int read_line(table_t *t)
{
    size_t n = 0;
    int ch, any = 0;
    t->toolong = 0;
    if (t->linecap == 0u) {
        (void)put(t, &n, 'x'); /* allocate */
        n = 0;
    }
    while ((ch = get(t)) != EOF) {
        any = 1;
        if (ch == '\n') {
            break;
        }
        if (ch == '\0') {
            ch = ' '; /* a NUL byte would cut the line short: read it as a blank */
        }
        (void)put(t, &n, ch);
    }
    if (t->line != NULL) {
        t->line[n] = '\0';
    }
    t->lineno++;
    if (any && t->at_start) {
        t->at_start = 0;
        if (n >= 3u && (unsigned char)t->line[0] == 0xefu && (unsigned char)t->line[1] == 0xbbu
            && (unsigned char)t->line[2] == 0xbfu) {
            memmove(t->line, t->line + 3, n - 2u); /* the BOM */
        }
    }
    return any && t->line != NULL;
}

static int is_blank_line(const char *s)
{
    return s[strspn(s, " \t\r\v\f")] == '\0';
}

int table_parse_number(const char *s, int decimal_comma, float *out)
{
    char buf[64];
    size_t n;
    char *end;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    n = strlen(s);
    while (n > 0u && (s[n - 1u] == ' ' || s[n - 1u] == '\t' || s[n - 1u] == '\r')) {
        n--;
    }
    if (n == 0u || n >= sizeof buf) {
        return -1;
    }
    memcpy(buf, s, n);
    buf[n] = '\0';
    if (decimal_comma) {
        char *c = strchr(buf, ',');
        if (c != NULL) {
            *c = '.';
        }
    }
    *out = strtof(buf, &end);
    return (end == buf || *end != '\0') ? -1 : 0;
}

/* Trim blanks and one pair of double quotes, in place. */
static char *trim(char *s)
{
    size_t n;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    n = strlen(s);
    while (n > 0u && (s[n - 1u] == ' ' || s[n - 1u] == '\t' || s[n - 1u] == '\r'
                      || s[n - 1u] == '\v' || s[n - 1u] == '\f')) {
        s[--n] = '\0';
    }
    if (n >= 2u && s[0] == '"' && s[n - 1u] == '"') {
        s[n - 1u] = '\0';
        s++;
    }
    return s;
}

/* Split t->line into t->cells. Returns the count, or -1 past TABLE_MAX_COLS. */
static int split(table_t *t)
{
    char *p = t->line;
    int n = 0;
    for (;;) {
        char *start, *stop;
        if (n == t->cellcap) {
            int nc = (t->cellcap == 0) ? 16 : 2 * t->cellcap;
            char **np;
            if (n >= TABLE_MAX_COLS) {
                return -1;
            }
            if (nc > TABLE_MAX_COLS) {
                nc = TABLE_MAX_COLS;
            }
            np = realloc(t->cells, (size_t)nc * sizeof *np);
            if (np == NULL) {
                return -1;
            }
            t->cells = np;
            t->cellcap = nc;
        }
        if (t->delim == ' ') {
            p += strspn(p, " \t\r\v\f");
            if (*p == '\0') {
                return n;
            }
            start = p;
            p += strcspn(p, " \t\r\v\f");
            if (*p != '\0') {
                *p++ = '\0';
            }
            t->cells[n++] = trim(start);
            continue;
        }
        start = p;
        stop = strchr(p, t->delim);
        if (stop != NULL) {
            *stop = '\0';
            p = stop + 1;
        }
        t->cells[n++] = trim(start);
        if (stop == NULL) {
            return n;
        }
    }
}

/* Does a tab-separated cell of s hold a blank between other characters? */
static int table_cell_has_inner_blank(const char *s)
{
    while (*s != '\0') {
        const size_t len = strcspn(s, "\t");
        size_t a = 0, b = len, i;
        while (a < b && (s[a] == ' ' || s[a] == '\r')) {
            a++;
        }
        while (b > a && (s[b - 1u] == ' ' || s[b - 1u] == '\r')) {
            b--;
        }
        for (i = a; i < b; i++) {
            if (s[i] == ' ') {
                return 1;
            }
        }
        s += len;
        if (*s == '\t') {
            s++;
        }
    }
    return 0;
}

/* Every blank-separated token of s is a number. */
static int all_numbers(const char *s)
{
    for (;;) {
        char tok[64];
        size_t len;
        float v;
        s += strspn(s, " \t\r");
        if (*s == '\0') {
            return 1;
        }
        len = strcspn(s, " \t\r");
        if (len >= sizeof tok) {
            return 0;
        }
        memcpy(tok, s, len);
        tok[len] = '\0';
        if (table_parse_number(tok, 0, &v) != 0) {
            return 0;
        }
        s += len;
    }
}

/* Tab, unless a tab cell holds blanks between numbers (a blank-separated
 * line with tabs mixed in); then semicolon, comma, blanks. */
static char detect_delim(const char *s)
{
    if (strchr(s, '\t') != NULL) {
        return (table_cell_has_inner_blank(s) && all_numbers(s)) ? ' ' : '\t';
    }
    if (strchr(s, ';') != NULL) {
        return ';';
    }
    if (strchr(s, ',') != NULL) {
        return ',';
    }
    return ' ';
}

int table_start(table_t *t)
{
    int n, i, header = 0;
    do {
        if (!read_line(t)) {
            t->ncols = 0; /* empty input */
            return 0;
        }
    } while (is_blank_line(t->line));
    if (t->toolong) {
        return table_fail(t, "line %lu longer than %u bytes", t->lineno, (unsigned)TABLE_LINE_MAX);
    }
    t->delim = detect_delim(t->line);
    {
        /* split a copy: a data line is split again by table_next */
        char *copy = malloc(strlen(t->line) + 1u);
        char *keep = t->line;
        if (copy == NULL) {
            return table_fail(t, "out of memory");
        }
        strcpy(copy, keep);
        t->line = copy;
        n = split(t);
        if (n < 0) {
            t->line = keep;
            free(copy);
            return table_fail(t, "line %lu has more than %d cells", t->lineno, TABLE_MAX_COLS);
        }
        for (i = 0; i < n; i++) {
            float v;
            if (t->cells[i][0] != '\0' && table_parse_number(t->cells[i], t->delim == ';', &v) != 0) {
                header = 1;
            }
        }
        t->ncols = n;
        if (header) {
            t->names = calloc((size_t)n, sizeof *t->names);
            for (i = 0; t->names != NULL && i < n; i++) {
                t->names[i] = malloc(strlen(t->cells[i]) + 1u);
                if (t->names[i] == NULL) {
                    break;
                }
                strcpy(t->names[i], t->cells[i]);
            }
            if (t->names == NULL || i < n) {
                t->line = keep;
                free(copy);
                return table_fail(t, "out of memory");
            }
        }
        t->line = keep;
        free(copy);
    }
    t->header = header;
    t->pending = !header;
    if (!header) {
        t->lineno--; /* table_next counts it again */
    }
    return 0;
}

static int name_eq(const char *a, const char *b, int fold)
{
    if (!fold) {
        return strcmp(a, b) == 0;
    }
    while (*a != '\0' && tolower((unsigned char)*a) == tolower((unsigned char)*b)) {
        a++;
        b++;
    }
    return *a == '\0' && *b == '\0';
}

static int find_name(const table_t *t, const char *name)
{
    int fold, i;
    if (t->names == NULL) {
        return -1;
    }
    for (fold = 0; fold < 2; fold++) {
        for (i = 0; i < t->ncols; i++) {
            if (name_eq(t->names[i], name, fold)) {
                return i;
            }
        }
    }
    return -1;
}

int table_select_idx(table_t *t, const int *idx, int n)
{
    int i;
    int *s;
    if (n < 1 || n > TABLE_MAX_COLS) {
        return table_fail(t, "no column selected");
    }
    for (i = 0; i < n; i++) {
        if (idx[i] < 0 || idx[i] >= t->ncols) {
            return table_fail(t, "column %d does not exist (the file has %d)", idx[i] + 1, t->ncols);
        }
    }
    s = realloc(t->sel, (size_t)n * sizeof *s);
    if (s == NULL) {
        return table_fail(t, "out of memory");
    }
    memcpy(s, idx, (size_t)n * sizeof *s);
    t->sel = s;
    t->nsel = n;
    return 0;
}

int table_select(table_t *t, const char *spec, int want)
{
    int idx[TABLE_MAX_COLS > 64 ? 64 : TABLE_MAX_COLS];
    int n = 0;
    if (t->ncols == 0) {
        return 0; /* empty input: nothing to select, no row will come */
    }
    if (spec == NULL) {
        const int ix = find_name(t, "x"), iy = find_name(t, "y"), iz = find_name(t, "z");
        if (want == 3 && ix >= 0 && iy >= 0 && iz >= 0) {
            idx[0] = ix;
            idx[1] = iy;
            idx[2] = iz;
            return table_select_idx(t, idx, 3);
        }
        if (want == 3 && t->ncols == 3) {
            idx[0] = 0;
            idx[1] = 1;
            idx[2] = 2;
            return table_select_idx(t, idx, 3);
        }
        return table_fail(t, "%d columns%s: choose x,y,z with --cols (names or 1-based indices)",
                        t->ncols, t->header ? " and none named x, y, z" : "");
    }
    while (*spec != '\0') {
        char item[128];
        const size_t len = strcspn(spec, ",");
        char *it, *end;
        long v;
        if (len >= sizeof item || n >= (int)(sizeof idx / sizeof idx[0])) {
            return table_fail(t, "--cols: item too long or too many items");
        }
        memcpy(item, spec, len);
        item[len] = '\0';
        it = trim(item);
        spec += len;
        if (*spec == ',') {
            spec++;
        }
        v = strtol(it, &end, 10);
        if (end != it && *end == '\0') {
            if (v < 1 || v > t->ncols) {
                return table_fail(t, "--cols: column %ld does not exist (1 to %d)", v, t->ncols);
            }
            idx[n++] = (int)v - 1;
        } else {
            const int k = find_name(t, it);
            if (k < 0) {
                return table_fail(t, "--cols: no column named '%s'%s", it,
                                t->header ? "" : " (the file has no header)");
            }
            idx[n++] = k;
        }
    }
    if (want > 0 && n != want) {
        return table_fail(t, "--cols: %d columns named, %d expected", n, want);
    }
    return table_select_idx(t, idx, n);
}

/* Does header name `col` read NAME<sep><axis>? */
static int marker_col(const char *col, const char *name, char axis)
{
    const size_t n = strlen(name);
    size_t i;
    if (strlen(col) != n + 2u) {
        return 0;
    }
    for (i = 0; i < n; i++) {
        if (tolower((unsigned char)col[i]) != tolower((unsigned char)name[i])) {
            return 0;
        }
    }
    return strchr("_.:- ", col[n]) != NULL && col[n] != '\0'
           && tolower((unsigned char)col[n + 1u]) == axis;
}

int table_find_marker(const table_t *t, const char *name, int idx[3])
{
    static const char axes[3] = {'x', 'y', 'z'};
    int a, i;
    if (t->names == NULL) {
        return -1;
    }
    for (a = 0; a < 3; a++) {
        idx[a] = -1;
        for (i = 0; i < t->ncols && idx[a] < 0; i++) {
            if (marker_col(t->names[i], name, axes[a])) {
                idx[a] = i;
            }
        }
        if (idx[a] < 0) {
            return -1;
        }
    }
    return 0;
}

int table_next(table_t *t, float *vals)
{
    int n, i;
    t->blank = 0;
    t->why = NULL;
    if (t->ncols == 0) {
        return TABLE_EOF;
    }
    if (t->pending) {
        t->pending = 0;
        t->lineno++;
    } else {
        do {
            if (!read_line(t)) {
                return TABLE_EOF;
            }
        } while (is_blank_line(t->line) && !t->toolong);
    }
    t->rows++;
    if (t->toolong) {
        t->why = "line too long";
        return TABLE_ROW_BAD;
    }
    n = split(t);
    if (n < 0) {
        t->why = "too many cells";
        return TABLE_ROW_BAD;
    }
    if (n != t->ncols) {
        t->why = (n < t->ncols) ? "fewer cells than the header / first row"
                                : "more cells than the header / first row";
        return TABLE_ROW_BAD;
    }
    for (i = 0; i < t->nsel; i++) {
        const char *c = t->cells[t->sel[i]];
        if (c[0] == '\0') {
            vals[i] = NAN;
            t->blank++;
        } else if (table_parse_number(c, t->delim == ';', &vals[i]) != 0) {
            t->why = "a selected cell is not a number";
            return TABLE_ROW_BAD;
        }
    }
    return TABLE_ROW_OK;
}
