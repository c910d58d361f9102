/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_table.c
 * @brief libFuzzer harness of the host library's delimited-text reader
 * (tools/formats/table.c). Input: one selector byte, then the text.
 * Selector % 6: column choice NULL (x,y,z by name or the only three),
 * "x,y,z", "2,3,4", "1", "A,b,3" (names and an index, any count), or the
 * columns of marker "M" (M_X / M.x / M:X ...). Contract: table_start and the
 * selection return 0 or -1 (with a message); table_next returns OK, BAD
 * (with a reason) or EOF, at most once per input line; an OK row has a
 * value per selected column, NaN for each blank cell; line numbers grow.
 * The reader is host code; it is compiled into the harness here.
 */
#include "../../tools/formats/table.c"

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const specs[5] = {NULL, "x,y,z", "2,3,4", "1", "A,b,3"};
    table_t t;
    float vals[64];
    unsigned long rows = 0, last_line = 0, newlines = 1;
    size_t i;
    int sel, rc, want = 3;
    if (size < 1u) {
        return 0;
    }
    sel = data[0] % 6;
    for (i = 1; i < size; i++) {
        newlines += (data[i] == '\n');
    }
    table_open_mem(&t, (const char *)data + 1, size - 1u);
    rc = table_start(&t);
    FZ_CHECK(rc == 0 || (rc == -1 && t.err[0] != '\0'), "table_start: 0, or -1 with a message");
    if (rc != 0) {
        table_close(&t);
        return 0;
    }
    FZ_CHECK(t.ncols >= 0 && t.ncols <= TABLE_MAX_COLS, "column count in range");
    FZ_CHECK(t.ncols == 0 || t.delim == ',' || t.delim == ';' || t.delim == '\t' || t.delim == ' ',
             "a known delimiter");
    if (sel == 5) {
        int idx[3];
        rc = table_find_marker(&t, "M", idx);
        if (rc == 0) {
            FZ_CHECK(idx[0] >= 0 && idx[0] < t.ncols && idx[1] >= 0 && idx[1] < t.ncols
                         && idx[2] >= 0 && idx[2] < t.ncols,
                     "marker columns exist");
            rc = table_select_idx(&t, idx, 3);
        }
    } else {
        want = (sel == 4) ? 0 : (sel == 3 ? 1 : 3);
        rc = table_select(&t, specs[sel], want);
    }
    FZ_CHECK(rc == 0 || rc == -1, "selection: 0 or -1");
    if (rc != 0 || t.ncols == 0) {
        table_close(&t);
        return 0;
    }
    FZ_CHECK(t.nsel >= 1 && t.nsel <= 64, "selection size");
    for (;;) {
        int k, nans = 0;
        rc = table_next(&t, vals);
        if (rc == TABLE_EOF) {
            break;
        }
        rows++;
        FZ_CHECK(rows <= newlines, "at most one row per line");
        FZ_CHECK(t.lineno > last_line && t.lineno <= newlines, "line numbers grow");
        last_line = t.lineno;
        if (rc == TABLE_ROW_BAD) {
            FZ_CHECK(t.why != NULL && t.why[0] != '\0', "a bad row has a reason");
            continue;
        }
        FZ_CHECK(rc == TABLE_ROW_OK, "OK, BAD or EOF");
        for (k = 0; k < t.nsel; k++) {
            nans += isnan(vals[k]) ? 1 : 0;
        }
        FZ_CHECK(t.blank >= 0 && t.blank <= nans, "a NaN for every blank cell");
    }
    FZ_CHECK(t.rows == rows, "rows counted");
    table_close(&t);
    return 0;
}
