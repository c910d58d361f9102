/* SPDX-License-Identifier: MIT */
/**
 * @file session_calib.c
 * The computing part of `sfit calibrate` and `sfit apply` on loaded
 * frames, shared with the Python binding (session_calib.h).
 */
#include "session_calib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_joint.h"
#include "cli_swaps.h"
#include "sfit/sfit_cluster.h"

#define CHI2_3_95 7.814727903251178 /* 95 % quantile of chi^2 with 3 degrees of freedom */
#define CHI2_2_95 5.991464547107979 /* ... with 2 (a hinge: normal to the axis) */

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
    char advice[128];
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
    if ((j->flags & SFIT_FLAG_UNTRUSTED) && (j->flags & SFIT_PAIR_FLAG_MISFIT)) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted: soft-tissue motion far above the marker noise, not in the "
                       "ellipsoid");
    } else if ((j->flags & SFIT_FLAG_UNTRUSTED) && (j->flags & SFIT_PAIR_FLAG_AXIS_FREE)) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted: the motion does not fix the hinge axis: record more flexion");
    } else if ((j->flags & SFIT_FLAG_UNTRUSTED) && (j->flags & SFIT_PAIR_FLAG_AMBIGUOUS)) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted: ball or hinge cannot be told apart: give the joint's type");
    } else if (j->flags & SFIT_FLAG_UNTRUSTED) {
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

int session_calibrate_frames(cli_frames_t *fr, const session_model_t *m, int k,
                             const char *trial, session_joint_t *j, char *err)
{
    const sm_joint_t *mj = &m->joint[k];
    const sm_segment_t *ps = &m->seg[mj->parent], *cs = &m->seg[mj->child];
    const int np = ps->nmarkers, nc = cs->nmarkers;
    const char *path = trial;
    cli_joint_opts_t o;
    cli_joint_out_t jo;
    cli_swaps_joint_t sw;
    double ev[3], var;
    int i;

    memset(j, 0, sizeof *j);
    err[0] = '\0';
    if (fr->nmarkers != np + nc || fr->nframes < 1) {
        (void)snprintf(err, SM_ERR_MAX, "%d markers expected (parent and child), %d given",
                       np + nc, fr->nmarkers);
        return -1;
    }
    if (cli_swaps_joint_run(fr, np, nc, 0, -1, 1, &sw) != 0) {
        (void)snprintf(err, SM_ERR_MAX, "label swap check: out of memory");
        return -1;
    }
    cli_joint_opts_default(&o);
    o.mode = mj->type == SM_BALL ? SFIT_MODE_SPHERE
                                 : (mj->type == SM_HINGE ? SFIT_MODE_PLANAR : SFIT_MODE_AUTO);
    if (cli_joint_run(fr, np, nc, &o, &jo) != SFIT_OK) {
        (void)snprintf(err, SM_ERR_MAX, "the joint failed at the %s stage (%s): %s", jo.stage,
                       sfit_status_str(jo.st), cli_status_message(jo.st));
        cli_joint_free(&jo);
        cli_swaps_joint_free(&sw);
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
    j->frames_total = fr->nframes;
    var = marker_var(fr, np, &jo);
    j->marker_sigma = sqrt(var);
    if (jo.pair_used) {
        /* the pair module's (the default method, docs/pair.md): its centre,
         * its covariance (marker noise from both clusters' registration
         * residuals) and its flags */
        int q;
        j->flags = jo.pair.flags;
        j->marker_sigma = sqrt((double)jo.pair.marker_var);
        for (i = 0; i < 3; i++) {
            for (q = 0; q < 3; q++) {
                j->cov[i][q] = (double)jo.pair.center_cov.m[i * 3 + q];
            }
        }
    } else if (center_cov(fr, np, nc, &jo, var, j->cov) != 0) {
        j->flags |= SFIT_FLAG_UNTRUSTED;
    }
    sym3_eig(j->cov, ev);
    for (i = 0; i < 3; i++) {
        const double q = j->hinge ? CHI2_2_95 : CHI2_3_95;
        j->semi95[i] = ev[i] > 0.0 ? sqrt(q * ev[i]) : 0.0;
    }
    rotation_range(fr, np, nc, &jo, j->range_deg);
    verdict(j, fr->units[0] != '\0' ? fr->units : "units");
    cli_joint_free(&jo);
    cli_swaps_joint_free(&sw);
    return 0;
}

long session_place_frames(const session_joint_t *j, cli_frames_t *fr, float d, float *pts,
                          int stride, sfit_mat3_t *rot)
{
    sfit_cluster_t cl;
    sfit_vec3_t tpl[SM_MARKERS_MAX];
    cli_swaps_t sw;
    long f, placed = 0;
    int i, k;
    if (fr->nmarkers != j->nmarkers || j->nmarkers < 3 || j->nmarkers > SM_MARKERS_MAX) {
        return -1;
    }
    for (i = 0; i < j->nmarkers; i++) {
        for (k = 0; k < 3; k++) {
            tpl[i].v[k] = j->tpl[i][k];
        }
    }
    if (sfit_cluster_init(&cl, tpl, (size_t)j->nmarkers) != SFIT_OK) {
        return -1;
    }
    /* the parent's label swaps, repaired as `sfit joint` does */
    if (fr->nframes > 0 && cli_swaps_run(fr->xyz, fr->nframes, fr->nmarkers, 0, fr->nmarkers, 0,
                                         fr->nframes - 1, 1, &sw) == 0) {
        cli_swaps_free(&sw);
    }
    for (f = 0; f < fr->nframes; f++) {
        sfit_pose_t pose;
        sfit_vec3_t c, a;
        float *p = pts + (size_t)f * (size_t)stride * 3u;
        if (sfit_cluster_register(&cl, cli_frames_at(fr, f, 0), (size_t)j->nmarkers, &pose, NULL)
                != SFIT_OK
            || sfit_cluster_to_global(&pose, (const sfit_vec3_t *)j->center, &c) != SFIT_OK) {
            continue;
        }
        if (rot != NULL) {
            rot[f] = pose.r;
        }
        for (k = 0; k < 3; k++) {
            p[k] = c.v[k];
        }
        if (j->hinge) {
            for (i = 0; i < 3; i++) {
                a.v[i] = pose.r.m[i * 3] * j->axis[0] + pose.r.m[i * 3 + 1] * j->axis[1]
                         + pose.r.m[i * 3 + 2] * j->axis[2];
            }
            for (k = 0; k < 3; k++) {
                p[3 + k] = c.v[k] - d * a.v[k];
                p[6 + k] = c.v[k] + d * a.v[k];
            }
        }
        placed++;
    }
    return placed;
}
