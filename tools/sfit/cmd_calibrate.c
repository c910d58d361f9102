/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_calibrate.c
 * `sfit calibrate MODEL FILES... -o SESSION.json`: every joint of a session
 * model from the functional trial its pattern names, kept in the parent
 * segment's template frame with its covariance, flags and a verdict
 * (docs/session.md).
 */
#include <errno.h>
#include <fnmatch.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "frames.h"
#include "session.h"
#include "session_calib.h"
#include "session_model.h"

#define CAL_FILES_MAX 64

static void calibrate_usage(FILE *f)
{
    fputs("usage: sfit calibrate MODEL FILES... -o SESSION.json [--json]\n"
          "  MODEL  a session model (docs/session.md): segments, joints, and the\n"
          "         functional trial of each joint (a file name or a glob on the basename)\n"
          "  FILES  the session's C3D files (or tables); each joint uses the one file its\n"
          "         pattern matches\n"
          "  -o SESSION.json  the calibrated session: per joint the parent markers'\n"
          "         template with the centre (and hinge axis) in it, the centre's\n"
          "         covariance, its 95 % ellipsoid, the flags and a verdict\n"
          "  --json  print the session on stdout as well (instead of the text report)\n"
          "Each joint is computed as `sfit joint FILE --parent P --child C` does\n"
          "(label swaps repaired, --mode from the joint's type).\n",
          f);
}

static const char *base_name(const char *p)
{
    const char *s = strrchr(p, '/');
    return s != NULL ? s + 1 : p;
}

/* Calibrate joint k of the model from file path; 0 or -1 (message on stderr). */
static int calibrate_joint(const session_model_t *m, int k, const char *path, session_joint_t *j,
                           char *units)
{
    const sm_joint_t *mj = &m->joint[k];
    const sm_segment_t *ps = &m->seg[mj->parent], *cs = &m->seg[mj->child];
    const char *names[2 * SM_MARKERS_MAX];
    const int np = ps->nmarkers, nc = cs->nmarkers;
    frames_data_t fr;
    char why[FRAMES_ERR_MAX], err[SM_ERR_MAX];
    int i, rc;

    for (i = 0; i < np; i++) {
        names[i] = ps->markers[i];
    }
    for (i = 0; i < nc; i++) {
        names[np + i] = cs->markers[i];
    }
    rc = frames_load(path, names, np + nc, &fr, why);
    if (rc != 0) {
        fprintf(stderr, "sfit: %s: %s: %s\n", mj->name, path, rc == -1 ? strerror(errno) : why);
        return -1;
    }
    if (units[0] == '\0') {
        (void)snprintf(units, 16, "%s", fr.units);
    }
    rc = session_calibrate_frames(&fr, m, k, path, j, err);
    if (rc != 0) {
        fprintf(stderr, "sfit: %s: %s: %s\n", mj->name, path, err);
    }
    frames_free(&fr);
    return rc;
}

int cli_cmd_calibrate(int argc, char **argv)
{
    const char *pos[CAL_FILES_MAX + 1];
    const char *out = NULL;
    int npos = 0, json = 0, k, i, failed = 0;
    const json_out_flag_t *sflags;
    size_t nsflags = 0;
    const cli_opt_t opts[] = {
        {.name = "-o", .kind = CLI_OPT_STRING, .dst = &out, .required = 1},
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &json},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0], .pos = pos,
                             .max_pos = CAL_FILES_MAX + 1, .min_pos = 2, .npos = &npos,
                             .extra = "at most 64 FILES",
                             .missing = "MODEL and at least one FILE are required",
                             .required = "-o SESSION.json is required",
                             .usage = calibrate_usage};
    static session_model_t m;
    static session_t s;
    char err[SM_ERR_MAX];
    FILE *f;
    const int prc = cli_parse(argc, argv, &args);
    if (prc >= 0) {
        return prc;
    }
    if (session_model_load(pos[0], &m, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        return CLI_IO;
    }
    memset(&s, 0, sizeof s);
    s.nseg = m.nseg;
    memcpy(s.seg, m.seg, sizeof s.seg);
    s.root = m.root;
    for (k = 0; k < m.njoint; k++) {
        const sm_joint_t *mj = &m.joint[k];
        const char *path = NULL;
        if (mj->pattern[0] == '\0') {
            fprintf(stderr, "sfit: %s: joint %s has no trial pattern (line %d)\n", pos[0],
                    mj->name, mj->line);
            failed++;
            continue;
        }
        for (i = 1; i < npos; i++) {
            if (fnmatch(mj->pattern, base_name(pos[i]), 0) == 0) {
                if (path != NULL) {
                    fprintf(stderr, "sfit: %s: pattern %s matches %s and %s: the first is used\n",
                            mj->name, mj->pattern, path, pos[i]);
                    break;
                }
                path = pos[i];
            }
        }
        if (path == NULL) {
            fprintf(stderr, "sfit: %s: no FILE matches its trial pattern %s\n", mj->name,
                    mj->pattern);
            failed++;
            continue;
        }
        if (calibrate_joint(&m, k, path, &s.joint[s.njoint], s.units) != 0) {
            failed++;
            continue;
        }
        s.njoint++;
    }
    if (s.njoint == 0) { /* a session without joints would place nothing */
        fprintf(stderr, "sfit: no joint of %s could be calibrated: %s not written\n", pos[0],
                out);
        if (json) {
            printf("{\"status\":\"failed\",\"message\":\"no joint could be calibrated\","
                   "\"joints\":[]}\n");
        }
        return CLI_FAIL;
    }
    sflags = names_flags(NAMES_SESSION, &nsflags);
    f = fopen(out, "w");
    if (f == NULL) {
        fprintf(stderr, "sfit: cannot write %s: %s\n", out, strerror(errno));
        return CLI_IO;
    }
    session_write_json(f, &s, sflags, nsflags);
    if (fclose(f) != 0) {
        fprintf(stderr, "sfit: cannot write %s\n", out);
        return CLI_IO;
    }
    if (json) {
        session_write_json(stdout, &s, sflags, nsflags);
    } else {
        for (k = 0; k < s.njoint; k++) {
            const session_joint_t *j = &s.joint[k];
            printf("%-10s %s, %ld of %ld frames, %s\n", j->name, base_name(j->trial),
                   j->frames_used, j->frames_total, j->hinge ? "hinge" : "ball");
            printf("           centre %.2f %.2f %.2f %s (%s template frame: origin at its "
                   "markers' centroid, lab axes at frame %ld)\n",
                   (double)j->center[0], (double)j->center[1], (double)j->center[2], s.units,
                   j->parent, j->ref_frame);
            printf("           %s\n", j->verdict);
        }
        printf("session    %s: %d of %d joints calibrated\n", out, s.njoint, m.njoint);
    }
    return failed > 0 ? CLI_FAIL : CLI_OK;
}
