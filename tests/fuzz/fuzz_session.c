/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_session.c
 * @brief libFuzzer harness of the lab session's two parsers (host code,
 * compiled into the harness): the session model text
 * (tools/formats/session_model.c) and the calibrated session JSON
 * (tools/formats/session.c). Input: one selector byte (even: model, odd:
 * session), then the text. Contract: 0, or -1 with a message; a model
 * read has 1..32 segments of 3..8 markers, joints between two different
 * segments in range, the point count of its type and a root that is no
 * joint's child; a session read has finite templates and centres, a unit
 * hinge axis, and reads back the same after session_write_json.
 */
#include "../../tools/formats/session_model.c"
#include "../../tools/formats/session.c"
#include "../../tools/formats/json_out.c"
#include "../../tools/lab/names.c"

#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static session_model_t g_model;
static session_t g_s, g_s2;

static void check_model(const session_model_t *m)
{
    int i;
    FZ_CHECK(m->nseg >= 1 && m->nseg <= SM_SEGMENTS_MAX, "segment count");
    FZ_CHECK(m->njoint >= 0 && m->njoint <= SM_JOINTS_MAX, "joint count");
    FZ_CHECK(m->root >= 0 && m->root < m->nseg, "root in range");
    for (i = 0; i < m->nseg; i++) {
        FZ_CHECK(m->seg[i].nmarkers >= 3 && m->seg[i].nmarkers <= SM_MARKERS_MAX, "markers 3..8");
    }
    for (i = 0; i < m->njoint; i++) {
        const sm_joint_t *j = &m->joint[i];
        FZ_CHECK(j->parent >= 0 && j->parent < m->nseg && j->child >= 0 && j->child < m->nseg
                     && j->parent != j->child,
                 "joint segments");
        FZ_CHECK(j->child != m->root, "the root is no joint's child");
        FZ_CHECK(j->npoints == (j->type == SM_HINGE ? 3 : 1), "points of the type");
    }
}

static void check_session(const session_t *s)
{
    int i, k, c;
    FZ_CHECK(s->njoint >= 0 && s->njoint <= SM_JOINTS_MAX, "joint count");
    FZ_CHECK(s->root >= 0 && s->root < s->nseg, "root in range");
    for (i = 0; i < s->njoint; i++) {
        const session_joint_t *j = &s->joint[i];
        FZ_CHECK(j->nmarkers >= 3 && j->nmarkers <= SM_MARKERS_MAX, "parent markers 3..8");
        FZ_CHECK(j->npoints == (j->hinge ? 3 : 1), "points of the type");
        for (k = 0; k < j->nmarkers; k++) {
            for (c = 0; c < 3; c++) {
                FZ_CHECK(isfinite(j->tpl[k][c]), "template finite");
            }
        }
        for (c = 0; c < 3; c++) {
            FZ_CHECK(isfinite(j->center[c]), "centre finite");
        }
        if (j->hinge) {
            const double n = sqrt((double)j->axis[0] * (double)j->axis[0]
                                  + (double)j->axis[1] * (double)j->axis[1]
                                  + (double)j->axis[2] * (double)j->axis[2]);
            FZ_CHECK(fabs(n - 1.0) < 2e-3, "unit axis");
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char err[SM_ERR_MAX];
    int rc;
    if (size < 1u) {
        return 0;
    }
    err[0] = 'x';
    err[1] = '\0';
    if ((data[0] & 1u) == 0u) {
        rc = session_model_parse((const char *)data + 1, size - 1u, &g_model, err);
        FZ_CHECK(rc == 0 || (rc == -1 && err[0] != '\0' && strlen(err) < SM_ERR_MAX),
                 "model: 0, or -1 with a message");
        if (rc == 0) {
            check_model(&g_model);
        }
        return 0;
    }
    rc = session_parse((const char *)data + 1, size - 1u, &g_s, err);
    FZ_CHECK(rc == 0 || (rc == -1 && err[0] != '\0' && strlen(err) < SM_ERR_MAX),
             "session: 0, or -1 with a message");
    if (rc == 0) {
        FILE *f = tmpfile();
        char *buf;
        long n;
        size_t nfl = 0;
        const json_out_flag_t *fl = names_flags(NAMES_SESSION, &nfl);
        check_session(&g_s);
        if (f == NULL) {
            return 0;
        }
        session_write_json(f, &g_s, fl, nfl);
        n = ftell(f);
        buf = (n > 0) ? malloc((size_t)n) : NULL;
        if (buf != NULL && fseek(f, 0L, SEEK_SET) == 0 && fread(buf, 1, (size_t)n, f) == (size_t)n) {
            int i;
            rc = session_parse(buf, (size_t)n, &g_s2, err);
            FZ_CHECK(rc == 0, "a written session reads back");
            FZ_CHECK(g_s2.njoint == g_s.njoint && g_s2.nseg == g_s.nseg, "same counts");
            for (i = 0; i < g_s.njoint; i++) {
                FZ_CHECK(memcmp(g_s2.joint[i].center, g_s.joint[i].center, sizeof g_s.joint[i].center)
                             == 0
                             && memcmp(g_s2.joint[i].tpl, g_s.joint[i].tpl, sizeof g_s.joint[i].tpl)
                                    == 0,
                         "the same numbers read back");
            }
        }
        free(buf);
        fclose(f);
    }
    return 0;
}
