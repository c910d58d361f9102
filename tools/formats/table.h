/* SPDX-License-Identifier: MIT */
/**
 * @file table.h
 * @brief The delimited-text reader of the `sfit` tool: one reader for every
 * command (fit, track, noise, coverage, joint, skeleton).
 *
 * Format, detected from the first non-blank line (a UTF-8 byte-order mark
 * before it is skipped):
 * - delimiter: tab if the line has one, else semicolon, else comma, else
 *   runs of blanks (spaces / tabs). With semicolons a decimal comma is read
 *   as a point ("1,5;2,25;3").
 * - header: the first non-blank line is a header when one of its cells is
 *   not a number; its cells name the columns (surrounding blanks and
 *   double quotes removed). Without a header the columns have no names.
 * - every later non-blank line is a data row; it must have as many cells as
 *   the header (or, without one, as the first row). Cells that are not
 *   selected are never parsed (a time column may hold any text).
 * - a blank cell in a selected column is a missing sample: NaN in the
 *   output and counted in `blank`; a selected cell that is not a number
 *   makes the row bad.
 *
 * Columns are selected by 1-based index or by header name (exact, then
 * case-insensitive), or for a wide motion-capture table by marker: the
 * three columns NAME<sep>X, NAME<sep>Y, NAME<sep>Z with <sep> one of
 * `_ . : - space` and the axis letter in either case (RASIS_X, RASIS.x,
 * RASIS:X, "RASIS X").
 *
 * Input from a file ('-' = stdin) or from memory (the fuzz harness).
 * Lines are limited to TABLE_LINE_MAX bytes (a longer one is a bad row),
 * rows to TABLE_MAX_COLS cells. Host only (allocates).
 */
#ifndef SFIT_TOOLS_TABLE_H
#define SFIT_TOOLS_TABLE_H

#include <stddef.h>
#include <stdio.h>

#define TABLE_LINE_MAX (1024u * 1024u)
#define TABLE_MAX_COLS 4096
#define TABLE_ERR_MAX 200

/** Result of table_next. */
enum { TABLE_EOF = -1, TABLE_ROW_OK = 0, TABLE_ROW_BAD = 1 };

typedef struct tab {
    /* source */
    FILE *f;
    int own; /* fclose on table_close */
    const char *mem;
    size_t memlen, pos;
    int at_start; /* BOM not yet looked for */
    char *line;
    size_t linecap;
    int toolong; /* the line in `line` was cut */
    /* format */
    char delim;   /* ',', '\t', ';' or ' ' (runs of blanks); 0 before table_start */
    int header;   /* 1: the first line named the columns */
    int ncols;    /* cells per row */
    char **names; /* ncols header names, NULL without a header */
    char **cells;
    int cellcap;
    int pending;  /* the first data row is already in `line` */
    /* selection */
    int nsel;
    int *sel; /* 0-based column of each selected value */
    /* state */
    unsigned long lineno; /**< physical line (1-based) of the last row returned */
    unsigned long rows;   /**< data rows returned so far (bad ones included) */
    int blank;            /**< blank selected cells of the last row */
    const char *why;      /**< why the last row is bad */
    char err[TABLE_ERR_MAX];
} table_t;

/** Open a file ('-' = stdin). -1 if it cannot be opened (errno kept). */
int table_open_file(table_t *t, const char *path);

/** Read from a memory buffer (not copied; must outlive t). */
void table_open_mem(table_t *t, const char *buf, size_t len);

/**
 * Read up to the first data row: delimiter, header, number of columns.
 * 0 on success (also for an empty input: ncols = 0); -1 with t->err on a
 * first line beyond the limits.
 */
int table_start(table_t *t);

/**
 * Select columns from a spec "a,b,c" of 1-based indices or header names
 * (NULL: the columns named x, y, z, or the only three columns). `want` is
 * the number of columns the spec must name (0: any number >= 1).
 * 0, or -1 with t->err.
 */
int table_select(table_t *t, const char *spec, int want);

/**
 * Find the x, y, z columns of marker `name` in the header (accepted names
 * above). 0 and idx[3] 0-based, or -1 with t->err.
 */
int table_find_marker(const table_t *t, const char *name, int idx[3]);

/** Select the given 0-based columns (n >= 1). 0, or -1 with t->err. */
int table_select_idx(table_t *t, const int *idx, int n);

/**
 * Next data row: TABLE_ROW_OK with t->nsel values in vals (NaN for a blank
 * cell, counted in t->blank), TABLE_ROW_BAD (t->why says why) or TABLE_EOF.
 */
int table_next(table_t *t, float *vals);

/** Release everything (closes an owned file). */
void table_close(table_t *t);

/** Parse a whole cell as a number (blanks around allowed). 0 on success. */
int table_parse_number(const char *s, int decimal_comma, float *out);

#endif /* SFIT_TOOLS_TABLE_H */
