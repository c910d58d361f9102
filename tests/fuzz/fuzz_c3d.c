/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_c3d.c
 * @brief libFuzzer harness of the host library's C3D reader (tools/formats/c3d.c): the
 * input is the file. Contract: c3d_parse returns 0 or -1; -1 leaves a
 * non-empty message and an empty result; 0 gives labels that are
 * NUL-terminated and printable, nframes * npoints points every one of which
 * can be read (ASan checks the bounds), and c3d_find finds the first labels.
 * Warnings are terminated; the parameter entries lie inside the input.
 * Every file read is also given to the writer (c3d_write.c) with one added
 * point, written to /dev/null: 0 or -1 with a message, never a crash.
 * The reader and writer are host code; they are compiled into the harness.
 */
#include "../../tools/formats/c3d.c"
#include "../../tools/formats/c3d_param.c"
#include "../../tools/formats/c3d_write.c"

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
        FZ_CHECK(c.nwarn >= 0 && c.nwarn <= C3D_WARNINGS_MAX, "warning count");
        for (k = 0; k < c.nwarn; k++) {
            FZ_CHECK(memchr(c.warnings[k], '\0', C3D_WARN_MAX) != NULL, "warning terminated");
        }
        for (k = 0; k < c.nentries; k++) {
            const c3d_entry_t *e = &c.entries[k];
            FZ_CHECK(e->off < e->body && e->body <= e->end && e->end <= size, "entry inside");
            FZ_CHECK(e->type == 0 || e->is_group || e->data + e->count * (size_t)(e->type < 0 ? 1 : e->type) <= size,
                     "parameter data inside");
        }
        FZ_CHECK(c.data_start + (size_t)c.nframes * c.frame_bytes <= size || c.frame_bytes == 0u,
                 "frames inside");
        if (c.nframes <= 4096 && c.npoints <= 4096) {
            static const char *const nm[1] = {"JC"};
            float xyz[3 * 4096];
            char werr[C3D_ERR_MAX];
            c3d_add_t add;
            int wrc;
            long fi;
            for (fi = 0; fi < 3 * c.nframes; fi++) {
                xyz[fi] = (fi % 5 == 0) ? NAN : (float)fi;
            }
            memset(&add, 0, sizeof add);
            add.n = 1;
            add.names = nm;
            add.xyz = xyz;
            add.prefix = "S:";
            wrc = c3d_write_added(data, size, &c, &add, "/dev/null", NULL, werr);
            FZ_CHECK(wrc == 0 || (wrc == -1 && werr[0] != '\0'), "writer: 0 or -1 with a message");
        }
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
