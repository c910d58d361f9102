/* SPDX-License-Identifier: MIT */
/**
 * @file sta_bench.c
 * @brief Monte Carlo benchmark of the pair module under soft-tissue artefact
 * (STA) and wobbling hinges (docs/joint_benchmark.md#soft-tissue): is the
 * reported 95 % region of an unflagged result still a 95 % region when the
 * markers slide on the skin with the joint angle?
 *
 * Ball joint (hip-like): a pelvis cluster of 4 markers travelling 1.2-3.0 m
 * from the lab origin, a thigh cluster of 5 markers, 500 frames: four star
 * arcs (80 frames each, a swing to +RoM/2, through neutral to -RoM/2 and
 * back) and a circumduction (180 frames) on a cone of half-angle RoM/2.
 * Two STA models, both linear in the joint's rotation vector w and sized
 * by the RMS displacement of the child's markers at a 30-degree swing (the
 * parent's a third of it):
 *  - rigid:  each cluster moves rigidly on its bone, a rotation a w and a
 *            translation b w (a, b random 3x3 per trial, half of the
 *            displacement variance each), after the rigid-cluster reading of
 *            the thigh STA (e.g. Camomilla et al. 2009; Barre et al. 2013);
 *  - marker: every marker has its own displacement D_i w (D_i random 3x3
 *            per marker and trial) plus a slow skin drift (one smooth
 *            excursion per trial, 20 % of the amplitude), after the
 *            per-marker linear models of Dumas, Camomilla, Cheze et al.
 *            (2014, 2015): part of it is non-rigid and goes into the
 *            registration residual.
 * Hinge (knee-like, 500 frames, three flexion cycles 0 -> F -> 0, moving
 * thigh): ab/adduction and axial rotation of peak 2-5 degrees each (random
 * per trial), either "free" (smooth, non-commensurate with the flexion) or
 * "step" (at the flexion's frequency with a random phase: in step with it
 * by the cosine of that phase); the nominal flexion axis is the truth.
 * Noise: isotropic Gaussian sigma on every marker coordinate.
 *
 * Usage: sfit_mc_sta_bench OUTDIR [full|check] [trials]
 *   full:  every cell (1000 trials: the 92-98 % band is then 4 binomial
 *          standard errors either side of 95 %, so that a right ellipsoid
 *          keeps every one of the 64 skin-motion cells in it; at 200 an
 *          exact 95 % region would leave about 3 of them out by chance):
 *          OUTDIR/sta_bench.csv, sta_bench_table.md.
 *   check: a reduced grid (fixed seeds, 200 trials per cell); exit status 1
 *          when a claim fails (check_cell).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit/sfit_pair.h"
#include "test_util.h"
#include "mc_out.h"

#define NF 500
#define STA_DRIFT 0.2 /* slow skin drift: its share of the amplitude */
#define MAXM 5
#define TMAX 1000
#define CHI2_3_95 7.8147279
#define CHI2_2_95 5.9914645

static double deg(double d) { return d * TU_PI / 180.0; }

static void rot(const double u[3], double ang, double r[9])
{
    const double n = tu_norm3(u);
    double x = 0, y = 0, z = 0, c = cos(ang), s = sin(ang), t = 1.0 - c;
    if (n > 0.0) {
        x = u[0] / n;
        y = u[1] / n;
        z = u[2] / n;
    }
    r[0] = t * x * x + c;     r[1] = t * x * y - s * z; r[2] = t * x * z + s * y;
    r[3] = t * x * y + s * z; r[4] = t * y * y + c;     r[5] = t * y * z - s * x;
    r[6] = t * x * z - s * y; r[7] = t * y * z + s * x; r[8] = t * z * z + c;
}

static void mul(const double a[9], const double b[9], double o[9])
{
    double t[9];
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            t[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
        }
    }
    memcpy(o, t, sizeof t);
}

static void mv(const double a[9], const double x[3], double o[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        o[i] = a[3 * i] * x[0] + a[3 * i + 1] * x[1] + a[3 * i + 2] * x[2];
    }
}

/* Rotation vector of a rotation matrix (angles below 180 degrees). */
static void rotvec(const double r[9], double w[3])
{
    const double c = (r[0] + r[4] + r[8] - 1.0) / 2.0;
    const double a = acos(c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c));
    const double k = (a < 1e-9) ? 0.5 : a / (2.0 * sin(a));
    w[0] = k * (r[7] - r[5]);
    w[1] = k * (r[2] - r[6]);
    w[2] = k * (r[3] - r[1]);
}

/* Segments (x anterior, y left, z up, mm; origin at the joint). */
static const double k_pelvis[4][3] = {
    {70, 80, 95}, {70, 320, 95}, {-105, 245, 125}, {-105, 120, 125}};
static const double k_thigh[5][3] = {
    {45, -70, -150}, {60, -55, -230}, {30, -80, -310}, {5, -50, -420}, {5, 45, -420}};
static const double k_thigh_k[4][3] = {{40, -70, 260}, {70, -45, 180}, {20, -75, 110}, {-30, -60, 200}};
static const double k_shank[4][3] = {{35, -60, -110}, {60, -40, -190}, {20, -65, -270}, {-25, -55, -170}};

typedef struct seg {
    int m;
    double x[MAXM][3]; /* markers about the joint */
    double cen[3];     /* their centroid */
    sfit_cluster_t cl; /* template: markers about the centroid */
} seg_t;

static void seg_make(seg_t *s, const double (*x)[3], int m)
{
    int i, k;
    s->m = m;
    memset(s->cen, 0, sizeof s->cen);
    for (i = 0; i < m; i++) {
        for (k = 0; k < 3; k++) {
            s->x[i][k] = x[i][k];
            s->cen[k] += x[i][k] / m;
        }
    }
    memset(&s->cl, 0, sizeof s->cl);
    s->cl.count = (uint32_t)m;
    for (i = 0; i < m; i++) {
        for (k = 0; k < 3; k++) {
            s->cl.pos[i].v[k] = (float)(x[i][k] - s->cen[k]);
        }
    }
}

typedef enum { K_BALL, K_HINGE } kind_t;
typedef enum { STA_NONE, STA_RIGID, STA_MARKER } sta_kind_t;
static const char *k_sta_name[3] = {"none", "rigid", "marker"};

typedef struct cell {
    kind_t kind;
    sta_kind_t sta;
    double rom, sigma, amp; /* RoM / flexion (deg), sigma (mm), STA (mm at 30 deg) */
    int step;               /* hinge: wobble at the flexion's frequency */
    int autom;              /* hinge: mode auto instead of hinge */
    int clean;              /* hinge: no wobble (noise only) */
} cell_t;

/* STA of one cluster: per-marker D_i (3x3, mm/rad), rigid a (rad/rad), b,
 * drift direction per marker. */
typedef struct sta {
    double d[MAXM][9], a[9], b[9], drift[MAXM][3];
} sta_t;

static void sta_draw(tu_rng_t *g, sta_kind_t kind, const seg_t *s, double amp, sta_t *o)
{
    const double w30 = deg(30.0);
    double ms = 0.0, scale;
    int i, k;
    memset(o, 0, sizeof *o);
    if (kind == STA_NONE || amp <= 0.0) {
        return;
    }
    if (kind == STA_RIGID) {
        double rr = 0.0, sa, sb;
        for (k = 0; k < 9; k++) {
            o->a[k] = tu_rng_gauss(g);
            o->b[k] = tu_rng_gauss(g);
        }
        for (i = 0; i < s->m; i++) {
            for (k = 0; k < 3; k++) {
                const double p = s->x[i][k] - s->cen[k];
                rr += p * p / s->m;
            }
        }
        /* E|b u|^2 = |b|_F^2 / 3 for a random unit u; E|a u x p|^2 ~ 2/3 rr |a|_F^2 / 3 */
        sb = 0.0;
        sa = 0.0;
        for (k = 0; k < 9; k++) {
            sb += o->b[k] * o->b[k] / 3.0;
            sa += o->a[k] * o->a[k] / 3.0 * (2.0 / 3.0) * rr;
        }
        for (k = 0; k < 9; k++) {
            o->b[k] *= sqrt(0.5 * amp * amp / sb) / w30;
            o->a[k] *= sqrt(0.5 * amp * amp / sa) / w30;
        }
        return;
    }
    for (i = 0; i < s->m; i++) {
        for (k = 0; k < 9; k++) {
            o->d[i][k] = tu_rng_gauss(g);
            ms += o->d[i][k] * o->d[i][k] / 3.0 / s->m;
        }
        for (k = 0; k < 3; k++) {
            o->drift[i][k] = STA_DRIFT * amp * tu_rng_gauss(g) / sqrt(3.0);
        }
    }
    scale = amp / sqrt(ms) / w30;
    for (i = 0; i < s->m; i++) {
        for (k = 0; k < 9; k++) {
            o->d[i][k] *= scale;
        }
    }
}

/* Marker i of a segment in its bone frame at joint rotation vector w, time s. */
static void sta_apply(const sta_t *o, sta_kind_t kind, const seg_t *sg, int i, const double w[3],
                      double s, double out[3])
{
    double p[3], t[3];
    int k;
    for (k = 0; k < 3; k++) {
        p[k] = sg->x[i][k];
        out[k] = p[k];
    }
    if (kind == STA_RIGID) {
        double aw[3], r[9], q[3];
        mv(o->a, w, aw);
        rot(aw, tu_norm3(aw), r);
        for (k = 0; k < 3; k++) {
            q[k] = p[k] - sg->cen[k];
        }
        mv(r, q, t);
        mv(o->b, w, aw);
        for (k = 0; k < 3; k++) {
            out[k] = sg->cen[k] + t[k] + aw[k];
        }
    } else if (kind == STA_MARKER) {
        const double dr = sin(TU_PI * s); /* one slow excursion */
        mv(o->d[i], w, t);
        for (k = 0; k < 3; k++) {
            out[k] += t[k] + dr * o->drift[i][k];
        }
    }
}

static seg_t g_pel, g_thi, g_thk, g_sha;
static double g_axis[3];

typedef struct res {
    int ok, flagged;
    double err, d2; /* error (mm or deg), d' C^-1 d */
    int covered;
    double sd;      /* sqrt of the reported covariance's largest eigenvalue (mm / deg) */
    double sta_rms, model_frac;
    int reason; /* sfit_pair_reason_t of a flagged result (ball reported for a hinge: 7) */
} res_t;

/* Ball cells of the full grid run NBLK blocks of the trial count, each from
 * its own seed: 8000 trials put the binomial standard error of a 92-95 %
 * coverage at 0.3 %, where 1000 leave it at 0.85 % (an exact 92 % cell
 * would then read below 92 % half the time). */
#define NBLK 8
static res_t g_r[NBLK * TMAX];

static int inv3(const double a[9], double o[9])
{
    const double d = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6])
                     + a[2] * (a[3] * a[7] - a[4] * a[6]);
    if (!(fabs(d) > 0.0)) {
        return -1;
    }
    o[0] = (a[4] * a[8] - a[5] * a[7]) / d;
    o[1] = (a[2] * a[7] - a[1] * a[8]) / d;
    o[2] = (a[1] * a[5] - a[2] * a[4]) / d;
    o[3] = (a[5] * a[6] - a[3] * a[8]) / d;
    o[4] = (a[0] * a[8] - a[2] * a[6]) / d;
    o[5] = (a[2] * a[3] - a[0] * a[5]) / d;
    o[6] = (a[3] * a[7] - a[4] * a[6]) / d;
    o[7] = (a[1] * a[6] - a[0] * a[7]) / d;
    o[8] = (a[0] * a[4] - a[1] * a[3]) / d;
    return 0;
}

static double maxeig(const sfit_mat3_t *m)
{
    sfit_vec3_t w;
    if (sfit_mat3_eig_sym(m, &w, NULL) != SFIT_OK) {
        return 0.0;
    }
    return w.v[2] > 0.0f ? (double)w.v[2] : 0.0;
}


static void trial(const cell_t *c, tu_rng_t *g, res_t *out)
{
    const int ball = c->kind == K_BALL;
    const seg_t *ps = ball ? &g_pel : &g_thk, *cs = ball ? &g_thi : &g_sha;
    const double phi0 = deg(45.0) * tu_rng_uniform(g), head = 2.0 * TU_PI * tu_rng_uniform(g);
    double wob[6];
    sta_t sp, sc;
    sfit_pair_t pr;
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_pair_result_t r;
    int f, i, k;
    memset(out, 0, sizeof *out);
    wob[0] = deg(2.0 + 3.0 * tu_rng_uniform(g));
    wob[1] = deg(2.0 + 3.0 * tu_rng_uniform(g));
    if (c->clean) {
        wob[0] = 0.0;
        wob[1] = 0.0;
    }
    for (k = 2; k < 6; k++) {
        wob[k] = 2.0 * TU_PI * tu_rng_uniform(g);
    }
    sta_draw(g, c->sta, ps, c->amp / 3.0, &sp);
    sta_draw(g, c->sta, cs, c->amp, &sc);
    cfg.mode = ball ? SFIT_PAIR_MODE_AUTO : (c->autom ? SFIT_PAIR_MODE_AUTO : SFIT_PAIR_MODE_HINGE);
    if (sfit_pair_init(&pr, &ps->cl, &cs->cl, &cfg) != SFIT_OK) {
        return;
    }
    for (f = 0; f < NF; f++) {
        static const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, ez[3] = {0, 0, 1};
        const double s = (double)f / NF, w2 = 2.0 * TU_PI * s;
        double rp[9], tp[3], rr[9], rc[9], q[9], w[3];
        sfit_vec3_t pm[MAXM], cm[MAXM];
        /* parent: 1.2 to 3.0 m from the origin, sway and rotations */
        rot(ez, head + deg(10.0) * sin(2.0 * w2), rp);
        rot(ex, deg(5.0) * sin(3.0 * w2 + 1.0), q);
        mul(rp, q, rp);
        rot(ey, deg(5.0) * sin(w2), q);
        mul(rp, q, rp);
        tp[0] = 700.0 + 2200.0 * s;
        tp[1] = 400.0 + 30.0 * sin(3.0 * w2);
        tp[2] = 900.0 + 20.0 * sin(5.0 * w2);
        if (ball) {
            const double a = deg(c->rom) / 2.0;
            double u[3] = {0, 0, 0};
            if (f < 320) {
                const double ph = phi0 + deg(45.0) * (f / 80), sa = (double)(f % 80) / 80.0;
                u[0] = cos(ph);
                u[1] = sin(ph);
                rot(u, a * sin(2.0 * TU_PI * sa), rr);
            } else {
                const double ps2 = 2.0 * TU_PI * (double)(f - 320) / (NF - 320) + phi0;
                u[0] = cos(ps2);
                u[1] = sin(ps2);
                rot(u, a, rr);
            }
        } else {
            const double fl = deg(c->rom) * (1.0 - cos(2.0 * TU_PI * 3.0 * s)) / 2.0;
            double aa, ar;
            if (c->step) {
                aa = wob[0] * sin(2.0 * TU_PI * 3.0 * s + wob[2]);
                ar = wob[1] * sin(2.0 * TU_PI * 3.0 * s + wob[3]);
            } else {
                aa = wob[0] * (0.6 * sin(2.0 * TU_PI * 2.3 * s + wob[2])
                               + 0.4 * sin(2.0 * TU_PI * 4.7 * s + wob[3]));
                ar = wob[1] * (0.6 * sin(2.0 * TU_PI * 1.7 * s + wob[4])
                               + 0.4 * sin(2.0 * TU_PI * 5.3 * s + wob[5]));
            }
            rot(g_axis, -fl, rr);
            rot(ex, aa, q);
            mul(rr, q, rr);
            rot(ez, ar, q);
            mul(rr, q, rr);
        }
        mul(rp, rr, rc);
        rotvec(rr, w);
        /* the joint (origin of both segments' frames) is at t_p */
        for (i = 0; i < ps->m; i++) {
            double x[3], y[3];
            sta_apply(&sp, c->sta, ps, i, w, s, x);
            mv(rp, x, y);
            for (k = 0; k < 3; k++) {
                pm[i].v[k] = (float)(y[k] + tp[k] + c->sigma * tu_rng_gauss(g));
            }
        }
        for (i = 0; i < cs->m; i++) {
            double x[3], y[3];
            sta_apply(&sc, c->sta, cs, i, w, s, x);
            mv(rc, x, y);
            for (k = 0; k < 3; k++) {
                cm[i].v[k] = (float)(y[k] + tp[k] + c->sigma * tu_rng_gauss(g));
            }
        }
        if (sfit_pair_add_markers(&pr, &ps->cl, pm, (size_t)ps->m, &cs->cl, cm, (size_t)cs->m)
            != SFIT_OK) {
            return;
        }
    }
    if (sfit_pair_solve(&pr, &r) != SFIT_OK) {
        return;
    }
    out->ok = 1;
    out->flagged = (r.flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u;
    out->reason = (int)r.reason;
    out->sta_rms = (double)r.sta_rms;
    if (ball || r.mode == SFIT_PAIR_MODE_BALL) {
        double e[3], cv[9], ci[9], t[3];
        for (k = 0; k < 3; k++) {
            e[k] = (double)r.center_p.v[k] + ps->cen[k]; /* truth: -centroid */
        }
        for (k = 0; k < 9; k++) {
            cv[k] = (double)r.center_cov.m[k];
        }
        out->err = tu_norm3(e);
        if (inv3(cv, ci) == 0) {
            mv(ci, e, t);
            out->d2 = e[0] * t[0] + e[1] * t[1] + e[2] * t[2];
        } else {
            out->d2 = 1e30;
        }
        out->covered = out->d2 < CHI2_3_95;
        out->sd = sqrt(maxeig(&r.center_cov));
        {
            const double tm = (double)(r.center_cov_model.m[0] + r.center_cov_model.m[4]
                                       + r.center_cov_model.m[8]);
            const double tt = cv[0] + cv[4] + cv[8];
            out->model_frac = tt > 0.0 ? tm / tt : 0.0;
        }
        if (!ball) {
            out->flagged = 1; /* a hinge called a ball: no axis */
            out->reason = 7;
        }
    } else {
        /* axis: angle to the true axis; d' C^+ d in the plane normal to it */
        double a[3], e[3], dt, cv[9];
        sfit_mat3_t m;
        sfit_vec3_t wv;
        int j;
        for (k = 0; k < 3; k++) {
            a[k] = (double)r.axis_p.v[k];
        }
        {
            double tr[3];
            /* the true axis in the parent template frame: the same frame here */
            memcpy(tr, g_axis, sizeof tr);
            dt = a[0] * tr[0] + a[1] * tr[1] + a[2] * tr[2];
            if (dt < 0.0) {
                for (k = 0; k < 3; k++) {
                    tr[k] = -tr[k];
                }
                dt = -dt;
            }
            for (k = 0; k < 3; k++) {
                e[k] = tr[k] - a[k];
            }
        }
        out->err = acos(dt > 1.0 ? 1.0 : dt) * 180.0 / TU_PI;
        for (k = 0; k < 9; k++) {
            cv[k] = (double)r.axis_cov.m[k];
            m.m[k] = r.axis_cov.m[k];
        }
        out->d2 = 0.0;
        {
            sfit_mat3_t v;
            if (sfit_mat3_eig_sym(&m, &wv, &v) != SFIT_OK) {
                out->d2 = 1e30;
            } else {
                for (j = 1; j < 3; j++) {
                    const double p = e[0] * (double)v.m[j] + e[1] * (double)v.m[3 + j]
                                     + e[2] * (double)v.m[6 + j];
                    out->d2 += (wv.v[j] > 0.0f) ? p * p / (double)wv.v[j] : 1e30;
                }
            }
        }
        (void)cv;
        out->covered = out->d2 < CHI2_2_95;
        out->sd = sqrt(maxeig(&r.axis_cov)) * 180.0 / TU_PI;
        {
            const double tm = (double)(r.axis_cov_model.m[0] + r.axis_cov_model.m[4]
                                       + r.axis_cov_model.m[8]);
            const double tt = cv[0] + cv[4] + cv[8];
            out->model_frac = tt > 0.0 ? tm / tt : 0.0;
        }
    }
}

typedef struct stat {
    int n, unflagged, covered, below, why[8]; /* below: unflagged with d' C^-1 d < 0.8 */
    double mean_err, p95_err, med_d2, med_sd, mean_sta, med_frac;
} stat_t;

static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double g_tmp[NBLK * TMAX];

static void stats(int n, stat_t *s)
{
    int i, m = 0;
    memset(s, 0, sizeof *s);
    for (i = 0; i < n; i++) {
        if (!g_r[i].ok) {
            continue;
        }
        s->n++;
        if (g_r[i].flagged) {
            s->why[g_r[i].reason & 7]++;
        }
        s->mean_err += g_r[i].err;
        s->mean_sta += g_r[i].sta_rms;
        g_tmp[m++] = g_r[i].err;
    }
    if (m > 0) {
        s->mean_err /= m;
        s->mean_sta /= m;
        qsort(g_tmp, (size_t)m, sizeof g_tmp[0], cmp_d);
        s->p95_err = g_tmp[(int)(0.95 * (m - 1))];
    }
    m = 0;
    for (i = 0; i < n; i++) {
        if (g_r[i].ok && !g_r[i].flagged) {
            s->unflagged++;
            s->covered += g_r[i].covered;
            s->below += g_r[i].d2 < 0.8;
            g_tmp[m++] = g_r[i].d2;
        }
    }
    if (m > 0) {
        qsort(g_tmp, (size_t)m, sizeof g_tmp[0], cmp_d);
        s->med_d2 = g_tmp[m / 2];
        m = 0;
        for (i = 0; i < n; i++) {
            if (g_r[i].ok && !g_r[i].flagged) {
                g_tmp[m++] = g_r[i].sd;
            }
        }
        qsort(g_tmp, (size_t)m, sizeof g_tmp[0], cmp_d);
        s->med_sd = g_tmp[m / 2];
        m = 0;
        for (i = 0; i < n; i++) {
            if (g_r[i].ok && !g_r[i].flagged) {
                g_tmp[m++] = g_r[i].model_frac;
            }
        }
        qsort(g_tmp, (size_t)m, sizeof g_tmp[0], cmp_d);
        s->med_frac = g_tmp[m / 2];
    }
}

#define NCELL_MAX 200
static cell_t g_cells[NCELL_MAX];
static int g_nc;

static void add(kind_t k, sta_kind_t st, double rom, double sig, double amp, int step, int autom)
{
    cell_t *c = &g_cells[g_nc++];
    c->clean = 0;
    c->kind = k;
    c->sta = st;
    c->rom = rom;
    c->sigma = sig;
    c->amp = amp;
    c->step = step;
    c->autom = autom;
}

static void grid(int check)
{
    static const double roms[] = {20, 30, 45, 60}, sigs[] = {0.5, 1.0}, amps[] = {2, 4, 6, 10};
    static const double flex[] = {45, 60, 90};
    int a, b, d, m;
    g_nc = 0;
    if (check) {
        add(K_BALL, STA_RIGID, 30, 0.5, 2, 0, 0);
        add(K_BALL, STA_MARKER, 30, 0.5, 2, 0, 0);
        add(K_BALL, STA_RIGID, 45, 1.0, 6, 0, 0);
        add(K_BALL, STA_MARKER, 20, 1.0, 4, 0, 0);
        add(K_BALL, STA_RIGID, 60, 1.0, 10, 0, 0);
        add(K_BALL, STA_MARKER, 60, 0.5, 10, 0, 0);
        add(K_BALL, STA_NONE, 30, 0.5, 0, 0, 0);
        add(K_BALL, STA_NONE, 60, 1.0, 0, 0, 0);
        add(K_HINGE, STA_NONE, 90, 1.0, 0, 1, 0);
        add(K_HINGE, STA_NONE, 90, 1.0, 0, 0, 1);
        add(K_HINGE, STA_NONE, 45, 1.0, 0, 0, 0);
        g_cells[g_nc - 1].clean = 1;
        add(K_HINGE, STA_NONE, 60, 0.5, 0, 0, 1);
        g_cells[g_nc - 1].clean = 1;
        add(K_HINGE, STA_NONE, 60, 1.0, 0, 1, 0);
        add(K_HINGE, STA_NONE, 60, 1.0, 0, 1, 1);
        return;
    }
    for (m = STA_RIGID; m <= STA_MARKER; m++) {
        for (a = 0; a < 4; a++) {
            for (b = 0; b < 2; b++) {
                for (d = 0; d < 4; d++) {
                    add(K_BALL, (sta_kind_t)m, roms[a], sigs[b], amps[d], 0, 0);
                }
            }
        }
    }
    for (a = 0; a < 4; a++) {
        for (b = 0; b < 2; b++) {
            add(K_BALL, STA_NONE, roms[a], sigs[b], 0, 0, 0);
        }
    }
    for (m = 0; m < 2; m++) {
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 2; b++) {
                for (d = 0; d < 2; d++) {
                    add(K_HINGE, STA_NONE, flex[a], sigs[b], 0, d, m);
                }
                add(K_HINGE, STA_NONE, flex[a], sigs[b], 0, 0, m);
                g_cells[g_nc - 1].clean = 1;
            }
        }
    }
}

static const char *cname(const cell_t *c, char *buf, size_t n)
{
    if (c->kind == K_BALL) {
        snprintf(buf, n, "ball %s", k_sta_name[c->sta]);
    } else {
        snprintf(buf, n, "hinge %s %s", c->clean ? "clean" : (c->step ? "step" : "free"),
                 c->autom ? "auto" : "hinge");
    }
    return buf;
}

/* The claims of the check grid (3 binomial standard errors around the
 * band, at least 30 unflagged results for a coverage):
 *  - ball: coverage of the 95 % ellipsoid among unflagged results in
 *    92-98 % and median d' C^-1 d >= 0.8 (not inflated; a sign test on the
 *    count below 0.8), with and without
 *    skin motion; without it at least 90 % unflagged; the mild cell (2 mm,
 *    RoM 30, sigma 0.5) at least 30 % unflagged;
 *  - hinge: the axis cone covers at least 92 % of the unflagged results
 *    (or fewer than 30 are unflagged); a clean hinge (no wobble) at least
 *    90 % unflagged; a wobbling hinge is flagged or covered: at most 1 %
 *    of its trials unflagged and outside the cone (a wobble in step with
 *    the flexion over 60 degrees: a tilted axis the data cannot tell). Its cone is not held to 98 %: it carries the default
 *    floor of 0.5 degrees rms of unseen in-step wobble (a real knee's, see
 *    docs/pair.md#model-error), far above a synthetic clean hinge's noise. */
static int check_cell(const cell_t *c, const stat_t *s, double cov)
{
    const int u = s->unflagged;
    int fail = 0;
    if (u >= 30) {
        const double lo = 0.92 - 3.0 * sqrt(0.92 * 0.08 / u), hi = 0.98 + 3.0 * sqrt(0.98 * 0.02 / u);
        if (cov < lo) {
            printf("  FAIL: coverage %.3f below %.3f\n", cov, lo);
            fail = 1;
        }
        if (c->kind == K_BALL && cov > hi) {
            printf("  FAIL: coverage %.3f above %.3f\n", cov, hi);
            fail = 1;
        }
        /* the median at least 0.8: a sign test, 3 standard errors as for
         * the coverage (the median of 200 trials moves by about 0.1) */
        if (c->kind == K_BALL && (double)s->below > 0.5 * u + 1.5 * sqrt((double)u)) {
            printf("  FAIL: median d'C^-1 d %.3f, %d of %d below 0.8 (inflated)\n", s->med_d2,
                   s->below, u);
            fail = 1;
        }
    }
    if (c->kind == K_HINGE && !c->clean && (double)(u - s->covered) > 0.01 * s->n) {
        printf("  FAIL: wobbling hinge, %d of %d unflagged outside the cone\n", u - s->covered,
               s->n);
        fail = 1;
    }
    if ((c->kind == K_BALL && c->sta == STA_NONE) || c->clean) {
        if (u < (int)(0.9 * s->n)) {
            printf("  FAIL: noise only, %d of %d unflagged\n", u, s->n);
            fail = 1;
        }
    }
    if (c->kind == K_BALL && c->amp == 2.0 && c->rom == 30.0 && c->sigma == 0.5
        && u < (int)(0.3 * s->n)) {
        printf("  FAIL: mild skin motion flagged in %d of %d\n", s->n - u, s->n);
        fail = 1;
    }
    return fail;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : ".";
    const int check = argc > 2 && strcmp(argv[2], "check") == 0;
    int trials = check ? 200 : 1000, ci, fail = 0;
    FILE *csv, *md;
    if (argc > 3) {
        trials = atoi(argv[3]);
        if (trials < 1 || trials > TMAX) {
            fprintf(stderr, "trials must be 1..%d\n", TMAX);
            return 2;
        }
    }
    seg_make(&g_pel, k_pelvis, 4);
    seg_make(&g_thi, k_thigh, 5);
    seg_make(&g_thk, k_thigh_k, 4);
    seg_make(&g_sha, k_shank, 4);
    {
        const double ax[3] = {0.04, 1.0, -0.03};
        const double n = tu_norm3(ax);
        int k;
        for (k = 0; k < 3; k++) {
            g_axis[k] = ax[k] / n;
        }
    }
    grid(check);
    csv = mc_out_open(dir, check ? "sta_bench_check.csv" : "sta_bench.csv");
    md = mc_out_open(dir, check ? "sta_bench_check.md" : "sta_bench_table.md");
    if (csv == NULL || md == NULL) {
        return 2;
    }
    fprintf(csv, "cell,sta,rom,sigma,amp,trials,ok,unflagged,covered,coverage,mean_err,p95_err,"
                 "med_d2,med_sd,mean_sta_rms,med_model_frac\n");
    fprintf(md, "| cell | RoM / flexion | sigma | STA (mm at 30 deg) | mean / 95th pct error | "
                "unflagged | coverage (unflagged) | median d'C^-1 d | median SD | model share |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n");
    for (ci = 0; ci < g_nc; ci++) {
        const cell_t *c = &g_cells[ci];
        tu_rng_t g;
        stat_t s;
        char nm[64];
        int t;
        double cov;
        const int nblk = (!check && c->kind == K_BALL) ? NBLK : 1;
        int b;
        for (b = 0; b < nblk; b++) {
            tu_rng_seed(&g, 0x57A0000ull + (uint64_t)ci * 7919u + (uint64_t)1000003u * (uint64_t)b);
            for (t = 0; t < trials; t++) {
                trial(c, &g, &g_r[b * trials + t]);
            }
        }
        stats(nblk * trials, &s);
        cov = s.unflagged > 0 ? (double)s.covered / s.unflagged : 0.0;
        cname(c, nm, sizeof nm);
        fprintf(csv, "%s,%s,%g,%g,%g,%d,%d,%d,%d,%.4f,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g\n", nm,
                k_sta_name[c->sta], c->rom, c->sigma, c->amp, nblk * trials, s.n, s.unflagged,
                s.covered, cov, s.mean_err, s.p95_err, s.med_d2, s.med_sd, s.mean_sta,
                s.med_frac);
        fprintf(md, "| %s | %g | %g | %g | %.3g / %.3g %s | %d of %d | %s%.0f %% | %.3g | %.3g | %.2f |\n",
                nm, c->rom, c->sigma, c->amp, s.mean_err, s.p95_err,
                c->kind == K_BALL ? "mm" : "deg", s.unflagged, s.n, s.unflagged ? "" : "- ",
                100.0 * cov, s.med_d2, s.med_sd, s.med_frac);
        printf("%-22s rom %4g sig %3g amp %4g: err %6.3g unfl %3d/%3d cov %5.1f%% medd2 %6.3g sd %6.3g frac %.2f why %d %d %d %d %d %d %d\n",
               nm, c->rom, c->sigma, c->amp, s.mean_err, s.unflagged, s.n, 100.0 * cov, s.med_d2,
               s.med_sd, s.med_frac, s.why[1], s.why[2], s.why[3], s.why[4], s.why[5], s.why[6], s.why[7]);
        if (check) {
            fail |= check_cell(c, &s, cov);
        }
    }
    fclose(csv);
    fclose(md);
    return fail;
}
