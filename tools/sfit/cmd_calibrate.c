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
#include "cli_frames.h"
#include "cli_joint.h"
#include "cli_swaps.h"
#include "session.h"
#include "session_model.h"
#include "sfit/sfit_cluster.h"

#define CAL_FILES_MAX 64
#define CHI2_3_95 7.814727903251178 /* 95 % quantile of chi^2 with 3 degrees of freedom */
#define CHI2_2_95 5.991464547107979 /* ... with 2 (a hinge: normal to the axis) */

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

/* Symmetric 3x3 eigenvalues (double Jacobi), descending. */
static void sym3_eig(double a_in[3][3], double ev[3])
{
    double a[3][3];
    int sweep, p, q, i;
    memcpy(a, a_in, sizeof a);
    for (sweep = 0; sweep < 50; sweep++) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if (!(off > 1e-30 * (a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2]))) {
            break;
        }
        for (p = 0; p < 2; p++) {
            for (q = p + 1; q < 3; q++) {
                double th, t, c, s;
                if (a[p][q] == 0.0) {
                    continue;
                }
                th = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                t = (th >= 0.0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (i = 0; i < 3; i++) { /* columns p, q */
                    const double ip = a[i][p], iq = a[i][q];
                    a[i][p] = c * ip - s * iq;
                    a[i][q] = s * ip + c * iq;
                }
                for (i = 0; i < 3; i++) { /* rows p, q */
                    const double pi = a[p][i], qi = a[q][i];
                    a[p][i] = c * pi - s * qi;
                    a[q][i] = s * pi + c * qi;
                }
            }
        }
    }
    ev[0] = a[0][0];
    ev[1] = a[1][1];
    ev[2] = a[2][2];
    for (p = 0; p < 2; p++) { /* sort descending */
        for (q = p + 1; q < 3; q++) {
            if (ev[q] > ev[p]) {
                const double t = ev[p];
                ev[p] = ev[q];
                ev[q] = t;
            }
        }
    }
}

/* The rotation vector (axis * angle, rad) of a proper rotation (row-major). */
static void rot_log(double r[3][3], double w[3])
{
    const double c = (r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0;
    const double th = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
    const double s = sin(th);
    const double k = (s > 1e-9) ? th / (2.0 * s) : 0.5;
    w[0] = k * (r[2][1] - r[1][2]);
    w[1] = k * (r[0][2] - r[2][0]);
    w[2] = k * (r[1][0] - r[0][1]);
}

/* Rotation range of the child relative to the parent, about the parent
 * frame's x, y, z (degrees): the spread (max - min) of the rotation vector
 * of R_rel(f) R_rel(ref)^T over the frames used. */
static void rotation_range(const cli_frames_t *fr, int np, int nc, const cli_joint_out_t *jo,
                           double range[3])
{
    sfit_cluster_t child;
    sfit_vec3_t *blk;
    double rref[3][3], lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
    int have_ref = 0;
    long f;
    size_t used = 0;
    int i, k, m;
    range[0] = range[1] = range[2] = 0.0;
    if (nc < 3) {
        return;
    }
    blk = malloc((size_t)fr->nframes * (size_t)nc * sizeof *blk);
    if (blk == NULL) {
        return;
    }
    for (f = 0; f < fr->nframes; f++) {
        for (k = 0; k < nc; k++) {
            blk[(size_t)f * (size_t)nc + (size_t)k] = *cli_frames_at(fr, f, np + k);
        }
    }
    if (sfit_cluster_from_frames(&child, blk, (size_t)fr->nframes, (size_t)nc, &used) != SFIT_OK) {
        free(blk);
        return;
    }
    for (f = 0; f < fr->nframes; f++) {
        sfit_pose_t pp, pc;
        double rel[3][3], d[3][3], w[3];
        if (!jo->ok[f]
            || sfit_cluster_register(&jo->j.parent, cli_frames_at(fr, f, 0), (size_t)np, &pp,
                                     NULL) != SFIT_OK
            || sfit_cluster_register(&child, blk + (size_t)f * (size_t)nc, (size_t)nc, &pc,
                                     NULL) != SFIT_OK) {
            continue;
        }
        for (i = 0; i < 3; i++) { /* rel = Rp^T Rc */
            for (k = 0; k < 3; k++) {
                double s = 0.0;
                for (m = 0; m < 3; m++) {
                    s += (double)pp.r.m[m * 3 + i] * (double)pc.r.m[m * 3 + k];
                }
                rel[i][k] = s;
            }
        }
        if (!have_ref) {
            memcpy(rref, rel, sizeof rref);
            have_ref = 1;
        }
        for (i = 0; i < 3; i++) { /* d = rel rref^T */
            for (k = 0; k < 3; k++) {
                double s = 0.0;
                for (m = 0; m < 3; m++) {
                    s += rel[i][m] * rref[k][m];
                }
                d[i][k] = s;
            }
        }
        rot_log(d, w);
        for (i = 0; i < 3; i++) {
            const double deg = w[i] * 57.29577951308232;
            lo[i] = deg < lo[i] ? deg : lo[i];
            hi[i] = deg > hi[i] ? deg : hi[i];
        }
    }
    free(blk);
    if (have_ref) {
        for (i = 0; i < 3; i++) {
            range[i] = hi[i] - lo[i];
        }
    }
}

/* The marker noise: the parent registrations' residuals over the frames
 * used, E sum |res|^2 = (3 M - 6) sigma^2 per frame. */
static double marker_var(const cli_frames_t *fr, int np, const cli_joint_out_t *jo)
{
    double num = 0.0, den = 0.0;
    long f;
    for (f = 0; f < fr->nframes; f++) {
        sfit_pose_t p;
        sfit_cluster_fit_t fit;
        if (jo->ok[f]
            && sfit_cluster_register(&jo->j.parent, cli_frames_at(fr, f, 0), (size_t)np, &p, &fit)
                   == SFIT_OK
            && fit.used > 2u) {
            num += (double)fit.rms * (double)fit.rms * (double)fit.used;
            den += 3.0 * (double)fit.used - 6.0;
        }
    }
    return den > 0.0 ? num / den : 0.0;
}

/* The centre's covariance (library: sfit_joint_center_cov, the frames that gave the fit). */
static int center_cov(const cli_frames_t *fr, int np, int nc, const cli_joint_out_t *jo,
                      double var, double cov[3][3])
{
    sfit_vec3_t *pb = malloc((size_t)fr->nframes * (size_t)np * sizeof *pb);
    sfit_vec3_t *cb = malloc((size_t)fr->nframes * (size_t)nc * sizeof *cb);
    sfit_mat3_t c;
    long f;
    int k, i, rc = -1;
    if (pb != NULL && cb != NULL) {
        for (f = 0; f < fr->nframes; f++) {
            for (k = 0; k < np; k++) {
                pb[(size_t)f * (size_t)np + (size_t)k] = *cli_frames_at(fr, f, k);
            }
            for (k = 0; k < nc; k++) {
                cb[(size_t)f * (size_t)nc + (size_t)k] = *cli_frames_at(fr, f, np + k);
            }
        }
        if (sfit_joint_center_cov(&jo->j, &jo->res, pb, cb, (size_t)fr->nframes, (float)var, &c)
            == SFIT_OK) {
            for (i = 0; i < 3; i++) {
                for (k = 0; k < 3; k++) {
                    cov[i][k] = (double)c.m[i * 3 + k];
                }
            }
            rc = 0;
        }
    }
    free(pb);
    free(cb);
    return rc;
}

/* A verdict in plain words. */
static void verdict(session_joint_t *j, const char *u)
{
    static const char *ax[3] = {"x", "y", "z"};
    const double big = j->semi95[0];
    char advice[96];
    int order[3] = {0, 1, 2}, a, b;
    for (a = 0; a < 2; a++) { /* order: ranges descending */
        for (b = a + 1; b < 3; b++) {
            if (j->range_deg[order[b]] > j->range_deg[order[a]]) {
                const int t = order[a];
                order[a] = order[b];
                order[b] = t;
            }
        }
    }
    if (j->flags & SFIT_FLAG_UNTRUSTED) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted fit (too little motion for the noise): record more motion");
    } else if (j->hinge && j->range_deg[order[0]] < 30.0) {
        (void)snprintf(advice, sizeof advice, "flexion range %.0f degrees: record more flexion",
                       j->range_deg[order[0]]);
    } else if (!j->hinge && j->range_deg[order[1]] < 20.0) {
        (void)snprintf(advice, sizeof advice,
                       "only %.0f degrees about lab %s: record more motion about that axis",
                       j->range_deg[order[1]], ax[order[1]]);
    } else if (big > 10.0 && strcmp(u, "mm") == 0) {
        (void)snprintf(advice, sizeof advice, "uncertain by more than 10 mm: record more motion");
    } else {
        (void)snprintf(advice, sizeof advice, "good");
    }
    if (j->hinge) {
        (void)snprintf(j->verdict, sizeof j->verdict,
                       "%s (hinge): 95 %% ellipse normal to the axis %.1f x %.1f %s; rotation "
                       "range about lab x/y/z %.0f/%.0f/%.0f degrees: %s",
                       j->name, j->semi95[0], j->semi95[1], u, j->range_deg[0], j->range_deg[1],
                       j->range_deg[2], advice);
    } else {
        (void)snprintf(j->verdict, sizeof j->verdict,
                       "%s (ball): 95 %% ellipsoid %.1f x %.1f x %.1f %s; rotation range about "
                       "lab x/y/z %.0f/%.0f/%.0f degrees: %s",
                       j->name, j->semi95[0], j->semi95[1], j->semi95[2], u, j->range_deg[0],
                       j->range_deg[1], j->range_deg[2], advice);
    }
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
    cli_frames_t fr;
    cli_joint_opts_t o;
    cli_joint_out_t jo;
    cli_swaps_joint_t sw;
    char why[CLI_FRAMES_ERR_MAX];
    double ev[3], var;
    int i, rc;

    memset(j, 0, sizeof *j);
    for (i = 0; i < np; i++) {
        names[i] = ps->markers[i];
    }
    for (i = 0; i < nc; i++) {
        names[np + i] = cs->markers[i];
    }
    rc = cli_frames_load(path, names, np + nc, &fr, why);
    if (rc != 0) {
        fprintf(stderr, "sfit: %s: %s: %s\n", mj->name, path, rc == -1 ? strerror(errno) : why);
        return -1;
    }
    if (units[0] == '\0') {
        (void)snprintf(units, 16, "%s", fr.units);
    }
    if (cli_swaps_joint_run(&fr, np, nc, 0, -1, 1, &sw) != 0) {
        fprintf(stderr, "sfit: %s: label swap check: out of memory\n", mj->name);
        cli_frames_free(&fr);
        return -1;
    }
    cli_joint_opts_default(&o);
    o.mode = mj->type == SM_BALL ? SFIT_MODE_SPHERE
                                 : (mj->type == SM_HINGE ? SFIT_MODE_PLANAR : SFIT_MODE_AUTO);
    if (cli_joint_run(&fr, np, nc, &o, &jo) != SFIT_OK) {
        fprintf(stderr, "sfit: %s: %s: the joint failed at the %s stage (%s): %s\n", mj->name,
                path, jo.stage, sfit_status_str(jo.st), cli_status_message(jo.st));
        cli_joint_free(&jo);
        cli_swaps_joint_free(&sw);
        cli_frames_free(&fr);
        return -1;
    }
    (void)snprintf(j->name, sizeof j->name, "%s", mj->name);
    (void)snprintf(j->parent, sizeof j->parent, "%s", ps->name);
    (void)snprintf(j->child, sizeof j->child, "%s", cs->name);
    (void)snprintf(j->trial, sizeof j->trial, "%s", path);
    j->hinge = jo.res.fit.mode == SFIT_MODE_PLANAR;
    j->npoints = j->hinge ? 3 : 1;
    for (i = 0; i < 3; i++) {
        (void)snprintf(j->points[i], SM_NAME_MAX, "%s", mj->points[i]);
        j->center[i] = jo.res.fit.center.v[i];
        j->axis[i] = j->hinge ? jo.res.fit.axis.v[i] : 0.0f;
    }
    if (mj->type == SM_BALL && j->hinge) { /* cannot happen: the mode was forced */
        j->hinge = 0;
    }
    j->nmarkers = np;
    for (i = 0; i < np; i++) {
        (void)snprintf(j->markers[i], SM_NAME_MAX, "%s", ps->markers[i]);
        j->tpl[i][0] = jo.j.parent.pos[i].v[0];
        j->tpl[i][1] = jo.j.parent.pos[i].v[1];
        j->tpl[i][2] = jo.j.parent.pos[i].v[2];
    }
    j->flags = jo.res.fit.flags;
    j->frames_used = jo.used;
    j->frames_total = fr.nframes;
    var = marker_var(&fr, np, &jo);
    j->marker_sigma = sqrt(var);
    if (center_cov(&fr, np, nc, &jo, var, j->cov) != 0) {
        fprintf(stderr, "sfit: %s: the centre's covariance could not be computed\n", mj->name);
        j->flags |= SFIT_FLAG_UNTRUSTED;
    }
    sym3_eig(j->cov, ev);
    for (i = 0; i < 3; i++) {
        const double q = j->hinge ? CHI2_2_95 : CHI2_3_95;
        j->semi95[i] = ev[i] > 0.0 ? sqrt(q * ev[i]) : 0.0;
    }
    rotation_range(&fr, np, nc, &jo, j->range_deg);
    verdict(j, fr.units[0] != '\0' ? fr.units : "units");
    cli_joint_free(&jo);
    cli_swaps_joint_free(&sw);
    cli_frames_free(&fr);
    return 0;
}

int cli_cmd_calibrate(int argc, char **argv)
{
    const char *pos[CAL_FILES_MAX + 1];
    const char *out = NULL;
    int npos = 0, json = 0, k, i, failed = 0;
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
    f = fopen(out, "w");
    if (f == NULL) {
        fprintf(stderr, "sfit: cannot write %s: %s\n", out, strerror(errno));
        return CLI_IO;
    }
    session_write_json(f, &s);
    if (fclose(f) != 0) {
        fprintf(stderr, "sfit: cannot write %s\n", out);
        return CLI_IO;
    }
    if (json) {
        session_write_json(stdout, &s);
    } else {
        for (k = 0; k < s.njoint; k++) {
            const session_joint_t *j = &s.joint[k];
            printf("%-10s %s, %ld of %ld frames, %s\n", j->name, base_name(j->trial),
                   j->frames_used, j->frames_total, j->hinge ? "hinge" : "ball");
            printf("           centre %.2f %.2f %.2f %s (%s template frame)\n",
                   (double)j->center[0], (double)j->center[1], (double)j->center[2], s.units,
                   j->parent);
            printf("           %s\n", j->verdict);
        }
        printf("session    %s: %d of %d joints calibrated\n", out, s.njoint, m.njoint);
    }
    return failed > 0 ? CLI_FAIL : CLI_OK;
}
