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

#include "names.h"
#include "joint_run.h"
#include "swaps.h"
#include "sfit/sfit_cluster.h"

#define CHI2_3_95 7.814727903251178 /* 95 % quantile of chi^2 with 3 degrees of freedom */
#define CHI2_2_95 5.991464547107979 /* ... with 2 (a hinge: normal to the axis) */
#define M_PI_SESSION 3.14159265358979323846

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
static void rotation_range(const frames_data_t *fr, int np, int nc, const joint_run_out_t *jo,
                           const float *axis, double range[3], double *flex)
{
    double flo = 1e9, fhi = -1e9;
    sfit_cluster_t child;
    sfit_vec3_t *blk;
    double rref[3][3], lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
    int have_ref = 0;
    long f;
    size_t used = 0;
    int i, k, m;
    range[0] = range[1] = range[2] = 0.0;
    if (flex != NULL) {
        *flex = 0.0;
    }
    if (nc < 3) {
        return;
    }
    blk = malloc((size_t)fr->nframes * (size_t)nc * sizeof *blk);
    if (blk == NULL) {
        return;
    }
    for (f = 0; f < fr->nframes; f++) {
        for (k = 0; k < nc; k++) {
            blk[(size_t)f * (size_t)nc + (size_t)k] = *frames_at(fr, f, np + k);
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
            || sfit_cluster_register(&jo->j.parent, frames_at(fr, f, 0), (size_t)np, &pp,
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
        if (axis != NULL) { /* the rotation about the hinge axis (parent frame) */
            const double deg = (w[0] * (double)axis[0] + w[1] * (double)axis[1]
                                + w[2] * (double)axis[2]) * 57.29577951308232;
            flo = deg < flo ? deg : flo;
            fhi = deg > fhi ? deg : fhi;
        }
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
        if (axis != NULL && flex != NULL) {
            *flex = fhi - flo;
        }
    }
}

/* The marker noise: the parent registrations' residuals over the frames
 * used, E sum |res|^2 = (3 M - 6) sigma^2 per frame. */
static double marker_var(const frames_data_t *fr, int np, const joint_run_out_t *jo)
{
    double num = 0.0, den = 0.0;
    long f;
    for (f = 0; f < fr->nframes; f++) {
        sfit_pose_t p;
        sfit_cluster_fit_t fit;
        if (jo->ok[f]
            && sfit_cluster_register(&jo->j.parent, frames_at(fr, f, 0), (size_t)np, &p, &fit)
                   == SFIT_OK
            && fit.used > 2u) {
            num += (double)fit.rms * (double)fit.rms * (double)fit.used;
            den += 3.0 * (double)fit.used - 6.0;
        }
    }
    return den > 0.0 ? num / den : 0.0;
}

/* The centre's covariance (library: sfit_joint_center_cov, the frames that gave the fit). */
static int center_cov(const frames_data_t *fr, int np, int nc, const joint_run_out_t *jo,
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
                pb[(size_t)f * (size_t)np + (size_t)k] = *frames_at(fr, f, k);
            }
            for (k = 0; k < nc; k++) {
                cb[(size_t)f * (size_t)nc + (size_t)k] = *frames_at(fr, f, np + k);
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

/* inv = a^-1 (symmetric 3x3); 0, or -1 when singular. */
static int inv3(double a[3][3], double inv[3][3])
{
    const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    const double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    const double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    const double scale = fabs(a[0][0]) + fabs(a[1][1]) + fabs(a[2][2]);
    if (!(fabs(det) > 1e-12 * scale * scale * scale)) {
        return -1;
    }
    inv[0][0] = c00 / det;
    inv[1][0] = c01 / det;
    inv[2][0] = c02 / det;
    inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    return 0;
}

/* The field's convention for a hinge's centre (docs/session.md#joint-centre-conventions):
 * with landmarks (a knee's epicondyles, an ankle's malleoli, markers of the
 * parent segment) the point of the functional axis nearest their midpoint
 * in the parent template; its covariance gains the axis' tilt over the
 * distance moved (s^2 axis_cov). Without, the axis point the data leave.
 * A ball joint keeps its functional centre. Names the rule in
 * j->convention. */
static void place_on_axis(const sm_joint_t *mj, const sm_segment_t *ps,
                          const sfit_pair_result_t *pr, session_joint_t *j)
{
    double mid[3] = {0, 0, 0}, s = 0.0;
    int i, k, q;
    if (!j->hinge) {
        (void)snprintf(j->convention, sizeof j->convention,
                       mj->nlandmarks == 2 ? "functional: the point fixed in both segments "
                                             "(a ball joint: its landmarks are not used)"
                                           : "functional: the point fixed in both segments");
        return;
    }
    if (mj->nlandmarks != 2) {
        (void)snprintf(j->convention, sizeof j->convention,
                       "functional axis: its point nearest the mid-point of the two "
                       "segments' markers (no landmarks in the model)");
        return;
    }
    for (i = 0; i < 2; i++) {
        for (k = 0; k < ps->nmarkers && strcmp(ps->markers[k], mj->landmarks[i]) != 0; k++) {
        }
        for (q = 0; q < 3; q++) {
            mid[q] += 0.5 * (double)j->tpl[k][q]; /* k < nmarkers: the model checked it */
        }
    }
    for (q = 0; q < 3; q++) {
        s += (mid[q] - (double)j->center[q]) * (double)j->axis[q];
    }
    for (q = 0; q < 3; q++) {
        j->center[q] = (float)((double)j->center[q] + s * (double)j->axis[q]);
    }
    if (pr != NULL) {
        for (i = 0; i < 3; i++) {
            for (q = 0; q < 3; q++) {
                j->cov[i][q] += s * s * (double)pr->axis_cov.m[i * 3 + q];
            }
        }
    }
    (void)snprintf(j->convention, sizeof j->convention,
                   "functional axis: its point nearest the mid-point of %s and %s",
                   mj->landmarks[0], mj->landmarks[1]);
}

#define JACK_BLOCKS 10 /* contiguous blocks of the block jackknife */

/* The block jackknife of the pair's centre: the joint solved again
 * without each of JACK_BLOCKS contiguous blocks of the frames used (mode
 * fixed to the result's), cov = (K - 1) / K sum (c_b - cbar)(c_b - cbar)^T;
 * a hinge: the part normal to the axis. Residuals correlated over many
 * frames (soft tissue moving with the joint angle) show in it, where the
 * misfit scaling assumes independent frames. 0, or -1 (fewer than 3
 * frames per block, or a solve failed). */
static int jackknife_cov(const frames_data_t *fr, int np, int nc, const joint_run_out_t *jo,
                         double cov[3][3])
{
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_cluster_t child;
    sfit_pair_t *pr;
    sfit_pair_result_t r;
    sfit_vec3_t *blk;
    double c[JACK_BLOCKS][3], mean[3] = {0, 0, 0}, ax[3];
    size_t used = 0;
    long f, n = 0, i;
    int b, k, q, rc = -1;
    memset(cov, 0, 9 * sizeof cov[0][0]);
    for (f = 0; f < fr->nframes; f++) {
        n += jo->ok[f] != 0u;
    }
    if (!jo->pair_used || n < 3L * JACK_BLOCKS) {
        return -1;
    }
    blk = malloc((size_t)fr->nframes * (size_t)nc * sizeof *blk);
    pr = malloc(sizeof *pr);
    if (blk == NULL || pr == NULL) {
        goto out;
    }
    for (f = 0; f < fr->nframes; f++) {
        for (k = 0; k < nc; k++) {
            blk[(size_t)f * (size_t)nc + (size_t)k] = *frames_at(fr, f, np + k);
        }
    }
    if (sfit_cluster_from_frames(&child, blk, (size_t)fr->nframes, (size_t)nc, &used)
        != SFIT_OK) {
        goto out;
    }
    cfg.mode = jo->pair.mode;
    for (b = 0; b < JACK_BLOCKS; b++) {
        const long lo = n * b / JACK_BLOCKS, hi = n * (b + 1) / JACK_BLOCKS;
        if (sfit_pair_init(pr, &jo->j.parent, &child, &cfg) != SFIT_OK) {
            goto out;
        }
        for (f = 0, i = 0; f < fr->nframes; f++) {
            const sfit_vec3_t *row = frames_at(fr, f, 0);
            if (jo->ok[f] == 0u) {
                continue;
            }
            if (i < lo || i >= hi) {
                (void)sfit_pair_add_markers(pr, &jo->j.parent, row, (size_t)np, &child,
                                            row + np, (size_t)nc);
            }
            i++;
        }
        if (sfit_pair_solve(pr, &r) != SFIT_OK) {
            goto out;
        }
        for (k = 0; k < 3; k++) {
            c[b][k] = (double)r.center_p.v[k];
            mean[k] += c[b][k] / JACK_BLOCKS;
        }
    }
    for (k = 0; k < 3; k++) {
        ax[k] = (double)jo->pair.axis_p.v[k];
    }
    for (b = 0; b < JACK_BLOCKS; b++) {
        double d[3], t;
        for (k = 0; k < 3; k++) {
            d[k] = c[b][k] - mean[k];
        }
        if (jo->pair.mode == SFIT_PAIR_MODE_HINGE) { /* normal to the axis */
            t = d[0] * ax[0] + d[1] * ax[1] + d[2] * ax[2];
            for (k = 0; k < 3; k++) {
                d[k] -= t * ax[k];
            }
        }
        for (k = 0; k < 3; k++) {
            for (q = 0; q < 3; q++) {
                cov[k][q] += (JACK_BLOCKS - 1.0) / JACK_BLOCKS * d[k] * d[q];
            }
        }
    }
    rc = 0;
out:
    free(blk);
    free(pr);
    return rc;
}

/* tr(C^-1 J) / p: the jackknife's spread against the covariance C, per
 * dimension (p = 3; a hinge: 2, in the plane normal to the axis); about 1
 * when C describes the error. -1 when C is singular there. */
static double jack_ratio(double C[3][3], double J[3][3], int hinge, const float *axis)
{
    double u[2][3], c2[2][2], j2[2][2], det, ci[3][3];
    int a, b, k, q;
    if (!hinge) {
        double t = 0.0;
        if (inv3(C, ci) != 0) {
            return -1.0;
        }
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                t += ci[a][b] * J[b][a];
            }
        }
        return t / 3.0;
    }
    { /* a basis u0, u1 of the plane normal to the axis */
        const double n[3] = {(double)axis[0], (double)axis[1], (double)axis[2]};
        const int m = fabs(n[0]) < 0.6 ? 0 : (fabs(n[1]) < 0.6 ? 1 : 2);
        double e[3] = {0, 0, 0}, t, len;
        e[m] = 1.0;
        t = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
        for (k = 0; k < 3; k++) {
            u[0][k] = e[k] - t * n[k];
        }
        len = sqrt(u[0][0] * u[0][0] + u[0][1] * u[0][1] + u[0][2] * u[0][2]);
        for (k = 0; k < 3; k++) {
            u[0][k] /= len;
        }
        u[1][0] = n[1] * u[0][2] - n[2] * u[0][1];
        u[1][1] = n[2] * u[0][0] - n[0] * u[0][2];
        u[1][2] = n[0] * u[0][1] - n[1] * u[0][0];
    }
    for (a = 0; a < 2; a++) {
        for (b = 0; b < 2; b++) {
            c2[a][b] = j2[a][b] = 0.0;
            for (k = 0; k < 3; k++) {
                for (q = 0; q < 3; q++) {
                    c2[a][b] += u[a][k] * C[k][q] * u[b][q];
                    j2[a][b] += u[a][k] * J[k][q] * u[b][q];
                }
            }
        }
    }
    det = c2[0][0] * c2[1][1] - c2[0][1] * c2[1][0];
    if (!(det > 0.0)) {
        return -1.0;
    }
    return (c2[1][1] * j2[0][0] - c2[0][1] * j2[1][0] - c2[1][0] * j2[0][1]
            + c2[0][0] * j2[1][1]) / det / 2.0;
}

/* A verdict in plain words. */
static void verdict(session_joint_t *j, const char *u)
{
    static const char *ax[3] = {"x", "y", "z"};
    const double big = j->semi95[0];
    char advice[300], model[64];
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
        if (j->hinge) {
            (void)snprintf(model, sizeof model, "%.1f x %.1f", j->semi95_model[0],
                           j->semi95_model[1]);
        } else {
            (void)snprintf(model, sizeof model, "%.1f x %.1f x %.1f", j->semi95_model[0],
                           j->semi95_model[1], j->semi95_model[2]);
        }
        (void)snprintf(advice, sizeof advice,
                       "untrusted: soft-tissue motion far above the marker noise (misfit %.1f); "
                       "95 %% with it %s %s",
                       j->misfit, model, u);
    } else if ((j->flags & SFIT_FLAG_UNTRUSTED) && (j->flags & SFIT_PAIR_FLAG_AXIS_FREE)
               && j->hinge && j->cone_model_deg > 0.0) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted: the joint turns out of its axis by %.1f degrees rms; a "
                       "knee's wobble in step with the flexion (2.5 degrees rms, or twice the "
                       "part seen) would tilt the axis unseen: axis uncertain by %.0f degrees "
                       "(95 %%): record more flexion",
                       j->wobble_deg, j->cone_deg);
    } else if ((j->flags & SFIT_FLAG_UNTRUSTED) && (j->flags & SFIT_PAIR_FLAG_AXIS_FREE)) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted: the motion does not fix the hinge axis: record more flexion");
    } else if ((j->flags & SFIT_FLAG_UNTRUSTED) && (j->flags & SFIT_PAIR_FLAG_AMBIGUOUS)) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted: ball or hinge cannot be told apart: give the joint's type");
    } else if (j->flags & SFIT_FLAG_UNTRUSTED) {
        (void)snprintf(advice, sizeof advice,
                       "untrusted fit (too little motion for the noise): record more motion");
    } else if (j->hinge && j->flex_deg < 30.0) {
        (void)snprintf(advice, sizeof advice, "flexion range %.0f degrees: record more flexion",
                       j->flex_deg);
    } else if (!j->hinge && j->range_deg[order[1]] < 20.0) {
        (void)snprintf(advice, sizeof advice,
                       "only %.0f degrees about lab %s: record more motion about that axis",
                       j->range_deg[order[1]], ax[order[1]]);
    } else if (!j->hinge && j->skin_rms > 0.0) {
        (void)snprintf(advice, sizeof advice,
                       "skin motion: the markers move on the skin with the joint angle by about "
                       "%.1f %s at the joint; the centre is uncertain by %.1f %s from it alone "
                       "(95 %%, in the ellipsoid)",
                       j->skin_rms, u, j->semi95_skin[0], u);
    } else if (big > 10.0 && strcmp(u, "mm") == 0) {
        (void)snprintf(advice, sizeof advice, "uncertain by more than 10 mm: record more motion");
    } else {
        (void)snprintf(advice, sizeof advice, "good");
    }
    if (j->hinge) {
        (void)snprintf(j->verdict, sizeof j->verdict,
                       "%s (hinge): 95 %% ellipse normal to the axis %.1f x %.1f %s; axis "
                       "95 %% cone %.1f degrees (%.1f of it from an out-of-axis rotation in step "
                       "with the flexion; %.1f degrees rms seen); flexion range %.0f degrees about the axis (lab x/y/z "
                       "%.0f/%.0f/%.0f): %s",
                       j->name, j->semi95[0], j->semi95[1], u, j->cone_deg, j->cone_model_deg,
                       j->wobble_deg, j->flex_deg, j->range_deg[0], j->range_deg[1], j->range_deg[2], advice);
    } else {
        (void)snprintf(j->verdict, sizeof j->verdict,
                       "%s (ball): 95 %% ellipsoid %.1f x %.1f x %.1f %s; rotation range about "
                       "lab x/y/z %.0f/%.0f/%.0f degrees: %s",
                       j->name, j->semi95[0], j->semi95[1], j->semi95[2], u, j->range_deg[0],
                       j->range_deg[1], j->range_deg[2], advice);
    }
}

int session_calibrate_frames(frames_data_t *fr, const session_model_t *m, int k,
                             const char *trial, session_joint_t *j, char *err)
{
    const sm_joint_t *mj = &m->joint[k];
    const sm_segment_t *ps = &m->seg[mj->parent], *cs = &m->seg[mj->child];
    const int np = ps->nmarkers, nc = cs->nmarkers;
    const char *path = trial;
    joint_run_opts_t o;
    joint_run_out_t jo;
    swaps_joint_t sw;
    double ev[3], var;
    int i;

    memset(j, 0, sizeof *j);
    err[0] = '\0';
    if (fr->nmarkers != np + nc || fr->nframes < 1) {
        (void)snprintf(err, SM_ERR_MAX, "%d markers expected (parent and child), %d given",
                       np + nc, fr->nmarkers);
        return -1;
    }
    if (swaps_joint_run(fr, np, nc, 0, -1, 1, &sw) != 0) {
        (void)snprintf(err, SM_ERR_MAX, "label swap check: out of memory");
        return -1;
    }
    joint_run_opts_default(&o);
    o.mode = mj->type == SM_BALL ? SFIT_MODE_SPHERE
                                 : (mj->type == SM_HINGE ? SFIT_MODE_PLANAR : SFIT_MODE_AUTO);
    if (joint_run(fr, np, nc, &o, &jo) != SFIT_OK) {
        (void)snprintf(err, SM_ERR_MAX, "the joint failed at the %s stage (%s): %s", jo.stage,
                       sfit_status_str(jo.st), names_status_message(jo.st, NAMES_CLI));
        joint_run_free(&jo);
        swaps_joint_free(&sw);
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
    j->ref_frame = jo.ref_frame;
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
        /* the model part: skin motion with the joint angle (ball), an
         * out-of-axis rotation in step with the flexion (hinge) */
        j->skin_rms = (double)jo.pair.sta_rms;
        {
            double cm[3][3];
            for (i = 0; i < 9; i++) {
                cm[i / 3][i % 3] = (double)jo.pair.center_cov_model.m[i];
            }
            session_semi_axes(cm, CHI2_3_95, j->semi95_skin);
        }
        if (jo.pair.mode == SFIT_PAIR_MODE_HINGE) {
            const double t = (double)(jo.pair.axis_cov.m[0] + jo.pair.axis_cov.m[4]
                                      + jo.pair.axis_cov.m[8]);
            const double tm = (double)(jo.pair.axis_cov_model.m[0] + jo.pair.axis_cov_model.m[4]
                                       + jo.pair.axis_cov_model.m[8]);
            j->cone_deg = sqrt(CHI2_2_95 * (t > 0.0 ? t : 0.0)) * 180.0 / M_PI_SESSION;
            j->cone_model_deg = sqrt(CHI2_2_95 * (tm > 0.0 ? tm : 0.0)) * 180.0 / M_PI_SESSION;
            j->wobble_deg = (double)jo.pair.wobble_rms * 180.0 / M_PI_SESSION;
        }
        for (i = 0; i < 3; i++) {
            for (q = 0; q < 3; q++) {
                j->cov[i][q] = (double)jo.pair.center_cov.m[i * 3 + q];
            }
        }
    } else if (center_cov(fr, np, nc, &jo, var, j->cov) != 0) {
        j->flags |= SFIT_FLAG_UNTRUSTED;
    }
    place_on_axis(mj, ps, jo.pair_used ? &jo.pair : NULL, j);
    sym3_eig(j->cov, ev);
    for (i = 0; i < 3; i++) {
        const double q = j->hinge ? CHI2_2_95 : CHI2_3_95;
        j->semi95[i] = ev[i] > 0.0 ? sqrt(q * ev[i]) : 0.0;
    }
    /* the model error: when the misfit test says the joint model does not
     * hold, the covariance scaled so that it covers the block jackknife's
     * spread (docs/session.md) */
    j->model_scale = 1.0;
    if (jo.pair_used) {
        j->misfit = (double)jo.pair.misfit;
        j->model_rms = (double)jo.pair.rms;
        if (jackknife_cov(fr, np, nc, &jo, j->cov_jack) == 0) {
            const double r = jack_ratio(j->cov, j->cov_jack, j->hinge, j->axis);
            j->jack_ratio = r > 0.0 ? r : 0.0;
            if ((j->flags & SFIT_PAIR_FLAG_MISFIT) && r > 1.0) {
                j->model_scale = r;
            }
        }
    }
    memcpy(j->cov_model, j->cov, sizeof j->cov_model);
    for (i = 0; i < 9; i++) {
        j->cov_model[i / 3][i % 3] *= j->model_scale;
    }
    session_semi_axes(j->cov_model, j->hinge ? CHI2_2_95 : CHI2_3_95, j->semi95_model);
    rotation_range(fr, np, nc, &jo, j->hinge ? j->axis : NULL, j->range_deg, &j->flex_deg);
    verdict(j, fr->units[0] != '\0' ? fr->units : "units");
    joint_run_free(&jo);
    swaps_joint_free(&sw);
    return 0;
}

void session_semi_axes(double cov[3][3], double q, double semi[3])
{
    double ev[3];
    int i;
    sym3_eig(cov, ev);
    for (i = 0; i < 3; i++) {
        semi[i] = ev[i] > 0.0 ? sqrt(q * ev[i]) : 0.0;
    }
}

/* The registration's error at point c (template frame) per unit marker
 * variance, from the markers seen (seen[i]): I / M + [x]x J^-1 [x]x^T with
 * x = c - centroid and J = sum (|y|^2 I - y y^T), y = tpl - centroid (the
 * centroid's translation noise and the rotation noise times the lever
 * arm). Added to g; 0, or -1 (fewer than 3 markers, or collinear). */
static int place_gain(const session_joint_t *j, const int *seen, double g[3][3])
{
    double cen[3] = {0, 0, 0}, J[3][3] = {{0}}, Ji[3][3], x[3], X[3][3], T[3][3];
    int i, a, b, m = 0;
    for (i = 0; i < j->nmarkers; i++) {
        if (seen[i]) {
            for (a = 0; a < 3; a++) {
                cen[a] += (double)j->tpl[i][a];
            }
            m++;
        }
    }
    if (m < 3) {
        return -1;
    }
    for (a = 0; a < 3; a++) {
        cen[a] /= m;
    }
    for (i = 0; i < j->nmarkers; i++) {
        double y[3], yy;
        if (!seen[i]) {
            continue;
        }
        for (a = 0; a < 3; a++) {
            y[a] = (double)j->tpl[i][a] - cen[a];
        }
        yy = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                J[a][b] += (a == b ? yy : 0.0) - y[a] * y[b];
            }
        }
    }
    if (inv3(J, Ji) != 0) {
        return -1;
    }
    for (a = 0; a < 3; a++) {
        x[a] = (double)j->center[a] - cen[a];
    }
    X[0][0] = X[1][1] = X[2][2] = 0.0; /* [x]x */
    X[0][1] = -x[2];
    X[0][2] = x[1];
    X[1][0] = x[2];
    X[1][2] = -x[0];
    X[2][0] = -x[1];
    X[2][1] = x[0];
    for (a = 0; a < 3; a++) { /* T = X Ji */
        for (b = 0; b < 3; b++) {
            T[a][b] = X[a][0] * Ji[0][b] + X[a][1] * Ji[1][b] + X[a][2] * Ji[2][b];
        }
    }
    for (a = 0; a < 3; a++) { /* g += I / m + T X^T */
        for (b = 0; b < 3; b++) {
            g[a][b] += (a == b ? 1.0 / m : 0.0) + T[a][0] * X[b][0] + T[a][1] * X[b][1]
                       + T[a][2] * X[b][2];
        }
    }
    return 0;
}

long session_place_frames(const session_joint_t *j, frames_data_t *fr, float d, float *pts,
                          int stride, sfit_mat3_t *rot, session_place_cov_t *pc)
{
    sfit_cluster_t cl;
    sfit_vec3_t tpl[SM_MARKERS_MAX];
    swaps_t sw;
    long f, placed = 0, ngain = 0;
    int i, k;
    double rsum[SM_MARKERS_MAX][3], num = 0.0, den = 0.0, gsum[3][3] = {{0}};
    long rn[SM_MARKERS_MAX];
    if (pc != NULL) {
        memset(pc, 0, sizeof *pc);
    }
    if (fr->nmarkers != j->nmarkers || j->nmarkers < 3 || j->nmarkers > SM_MARKERS_MAX) {
        return -1;
    }
    memset(rsum, 0, sizeof rsum);
    memset(rn, 0, sizeof rn);
    for (i = 0; i < j->nmarkers; i++) {
        for (k = 0; k < 3; k++) {
            tpl[i].v[k] = j->tpl[i][k];
        }
    }
    if (sfit_cluster_init(&cl, tpl, (size_t)j->nmarkers) != SFIT_OK) {
        return -1;
    }
    /* the parent's label swaps, repaired as `sfit joint` does */
    if (fr->nframes > 0 && swaps_run(fr->xyz, fr->nframes, fr->nmarkers, 0, fr->nmarkers, 0,
                                         fr->nframes - 1, 1, &sw) == 0) {
        swaps_free(&sw);
    }
    for (f = 0; f < fr->nframes; f++) {
        sfit_pose_t pose;
        sfit_vec3_t c, a;
        const sfit_vec3_t *row = frames_at(fr, f, 0);
        float *p = pts + (size_t)f * (size_t)stride * 3u;
        int seen[SM_MARKERS_MAX], m = 0;
        if (sfit_cluster_register(&cl, row, (size_t)j->nmarkers, &pose, NULL) != SFIT_OK
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
        /* the residuals in the template frame, R^T (x - t) - tpl */
        for (i = 0; i < j->nmarkers; i++) {
            double r[3];
            int q;
            seen[i] = isfinite(row[i].v[0]) && isfinite(row[i].v[1]) && isfinite(row[i].v[2]);
            if (!seen[i]) {
                continue;
            }
            m++;
            for (k = 0; k < 3; k++) {
                r[k] = -(double)j->tpl[i][k];
                for (q = 0; q < 3; q++) {
                    r[k] += (double)pose.r.m[q * 3 + k]
                            * ((double)row[i].v[q] - (double)pose.t.v[q]);
                }
                rsum[i][k] += r[k];
                num += r[k] * r[k];
            }
            rn[i]++;
        }
        den += 3.0 * m - 6.0;
        ngain += place_gain(j, seen, gsum) == 0;
    }
    if (pc != NULL && placed > 0) {
        double sys = 0.0;
        pc->frames = placed;
        pc->var = den > 0.0 ? num / den : 0.0;
        for (i = 0; i < j->nmarkers; i++) {
            if (rn[i] > 0) {
                sys += (rsum[i][0] * rsum[i][0] + rsum[i][1] * rsum[i][1]
                        + rsum[i][2] * rsum[i][2]) / (double)rn[i];
            }
        }
        /* sum |mean r|^2 / dof estimates var_sys + var_rand / frames, the
         * rest of the residual var_rand (1 - 1 / frames) */
        sys = den > 0.0 ? sys / den : 0.0;
        if (sys > pc->var) {
            sys = pc->var;
        }
        pc->var_rand = placed > 1 ? (pc->var - sys) * (double)placed / (double)(placed - 1) : 0.0;
        pc->var_sys = sys - pc->var_rand / (double)placed;
        if (pc->var_sys < 0.0) {
            pc->var_sys = 0.0;
        }
        pc->var_rand = pc->var - pc->var_sys;
        pc->var_mean = pc->var_sys + pc->var_rand / (double)placed;
        for (i = 0; i < j->nmarkers; i++) {
            for (k = 0; k < 3 && rn[i] > 0; k++) {
                pc->mean_res[i][k] = rsum[i][k] / (double)rn[i];
            }
        }
        for (i = 0; i < 3 && ngain > 0; i++) {
            for (k = 0; k < 3; k++) {
                const double g = gsum[i][k] / (double)ngain;
                pc->gain[i][k] = g;
                pc->cov_frame[i][k] = pc->var * g;
                pc->cov_mean[i][k] = pc->var_mean * g;
            }
        }
        for (i = 0; i < 9; i++) {
            pc->total[i / 3][i % 3] = j->cov_model[i / 3][i % 3] + pc->cov_frame[i / 3][i % 3];
        }
        session_semi_axes(pc->cov_frame, CHI2_3_95, pc->semi_frame);
        session_semi_axes(pc->cov_mean, CHI2_3_95, pc->semi_mean);
        session_semi_axes(pc->total, CHI2_3_95, pc->semi_total);
    }
    return placed;
}

static void json_vec(FILE *f, const double v[3])
{
    fprintf(f, "[%.9g,%.9g,%.9g]", v[0], v[1], v[2]);
}

static void json_mat(FILE *f, const char *key, double m[3][3])
{
    fprintf(f, ",\"%s\":[", key);
    json_vec(f, m[0]);
    fputc(',', f);
    json_vec(f, m[1]);
    fputc(',', f);
    json_vec(f, m[2]);
    fputc(']', f);
}

void session_place_json(FILE *f, const session_place_cov_t *pc, int nmarkers)
{
    session_place_cov_t c = *pc;
    int q;
    fprintf(f, "{\"frames\":%ld,\"marker_sigma\":%.9g,\"var_systematic\":%.9g,"
               "\"var_frame_to_frame\":%.9g,\"var_mean\":%.9g,\"systematic_fraction\":%.9g",
            c.frames, sqrt(c.var), c.var_sys, c.var_rand, c.var_mean,
            c.var > 0.0 ? c.var_sys / c.var : 0.0);
    json_mat(f, "gain", c.gain);
    json_mat(f, "cov_frame", c.cov_frame);
    json_mat(f, "cov_mean", c.cov_mean);
    json_mat(f, "total_cov_frame", c.total);
    fprintf(f, ",\"semi_axes_95_frame\":");
    json_vec(f, c.semi_frame);
    fprintf(f, ",\"semi_axes_95_mean\":");
    json_vec(f, c.semi_mean);
    fprintf(f, ",\"semi_axes_95_total\":");
    json_vec(f, c.semi_total);
    fprintf(f, ",\"mean_residual\":[");
    for (q = 0; q < nmarkers && q < SM_MARKERS_MAX; q++) {
        if (q > 0) {
            fputc(',', f);
        }
        json_vec(f, c.mean_res[q]);
    }
    fprintf(f, "]}");
}
