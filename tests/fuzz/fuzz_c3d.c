/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_c3d.c
 * @brief libFuzzer harness of the CLI's C3D reader (tools/sfit/c3d.c): the
 * input is the file. Contract: c3d_parse returns 0 or -1; -1 leaves a
 * non-empty message and an empty result; 0 gives labels that are
 * NUL-terminated and printable, nframes * npoints points every one of which
 * can be read (ASan checks the bounds), and c3d_find finds the first labels.
 * The reader is host code; it is compiled into the harness here.
 */
#include "../../tools/sfit/c3d.c"

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    c3d_t c;
    char err[C3D_ERR_MAX];
    const int rc = c3d_parse(data, size, &c, err);
    FZ_CHECK(rc == 0 || rc == -1, "c3d_parse returns 0 or -1");
    if (rc != 0) {
        FZ_CHECK(err[0] != '\0' && strlen(err) < C3D_ERR_MAX, "an error has a message");
        FZ_CHECK(c.labels == NULL && c.xyz == NULL && c.npoints == 0, "failure: empty result");
    } else {
        size_t i, n;
        int k;
        volatile float sink = 0.0f;
        FZ_CHECK(c.npoints >= 0 && c.nframes >= 0, "counts are not negative");
        FZ_CHECK(c.processor >= 84 && c.processor <= 86, "known processor type");
        FZ_CHECK(c.scale != 0.0f && isfinite(c.scale), "scale finite, non-zero");
        FZ_CHECK(c.rate >= 0.0f && isfinite(c.rate), "rate finite, >= 0");
        FZ_CHECK(strlen(c.units) < sizeof c.units, "units terminated");
        n = (size_t)c.nframes * (size_t)c.npoints * 3u;
        FZ_CHECK(c.npoints == 0 || n / (size_t)c.npoints / 3u == (size_t)c.nframes,
                 "no overflow in the point count");
        FZ_CHECK((size_t)c.nframes * (size_t)c.npoints <= size, "points bounded by the file");
        for (i = 0; i < n; i++) {
            sink += c.xyz[i]; /* every point readable */
        }
        (void)sink;
        for (k = 0; k < c.npoints; k++) {
            size_t len, j;
            FZ_CHECK(memchr(c.labels[k], '\0', C3D_LABEL_MAX) != NULL, "label terminated");
            len = strlen(c.labels[k]);
            for (j = 0; j < len; j++) {
                FZ_CHECK(c.labels[k][j] >= 0x20 && c.labels[k][j] < 0x7f, "label printable");
            }
            if (k < 16) { /* c3d_find is linear: keep the check linear */
                FZ_CHECK(c3d_find(&c, c.labels[k]) >= 0, "the label is found");
            }
        }
    }
    c3d_free(&c);
    FZ_CHECK(c.labels == NULL && c.xyz == NULL, "freed");
    return 0;
}
