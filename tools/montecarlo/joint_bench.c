/* SPDX-License-Identifier: MIT */
/**
 * @file joint_bench.c
 * @brief Monte Carlo benchmark of joint centres and hinge axes (issue 28,
 * docs/joint_benchmark.md): synthetic functional trials after the protocol
 * of Ehrig et al. (J Biomech 2006, 39:2798; 2007, 40:2150), every method on
 * the same trials:
 *  - mgdk:       today's `sfit joint` default (sfit_joint, mode auto, MGDK,
 *                no noise model); a hinge in planar mode (`--mode planar`);
 *  - mgdk_sig:   the same with the true marker variance
 *                (SFIT_JOINT_NOISE_MARKER, `--noise-var sigma^2`);
 *  - mgdk_est:   the same with sigma^2 estimated from the two clusters'
 *                registration residuals (one candidate default);
 *  - score:      SCoRE (ball) / SARA (hinge) written here in double from
 *                the papers, poses by a double least-squares registration
 *                (Horn's quaternion, tests/ref); sandwich covariance;
 *  - score_eiv:  the same with the errors-in-variables bias of the noisy
 *                rotations removed, sigma^2 from the residuals (the other
 *                candidate default, see eiv_shrink below);
 *  - score_gls:  score_eiv weighted by each frame's residual covariance at
 *                a first estimate (a second pass; what weighting would gain);
 *  - the library's pair module (sfit_pair.h) when it is built in
 *    (SFIT_MC_HAVE_PAIR): pair_default (bias removed and, for a ball, weighted
 *    by the residual covariance at a first estimate in the same solve) and
 *    pair_score (SFIT_PAIR_METHOD_*;
 *    ball cells in mode auto, hinge cells in mode hinge) and pair_auto (the
 *    default in mode auto on the hinge cells).
 *
 * Usage: sfit_mc_joint_bench OUTDIR [full|quick|check] [trials]
 *   full (default): every cell, 200 trials; writes OUTDIR/joint_bench.csv,
 *                   joint_bench_table.md and joint_bench_claims.md.
 *   quick:          every cell, 100 trials (or the given count).
 *   check:          the reduced grid of the ctest (18 cells, 100 trials);
 *                   exit status 1 when a claim fails (must-shows 1 and 2 of
 *                   issue 28, see claims_cell), except the listed known
 *                   exceptions (known_exception), or when the pair module is
 *                   not built.
 * Fixed seeds: identical output from run to run on the same platform.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit_ref_joint.h"
#include "test_util.h"
#include "mc_out.h"

#ifdef SFIT_MC_HAVE_PAIR
#include "sfit/sfit_pair.h"
#endif

#define FMAX 400
#define MAXM 5
#define TMAX 1000
#define CHI2_3_95 7.8147279
#define CHI2_2_95 5.9914645

/* ------------------------------------------------------------ geometry */

/* Segment geometry in an anatomical frame (x anterior, y left, z up, mm)
 * with the origin at the joint centre; the templates are these markers
 * centred on their centroid (the frame of sfit_cluster_from_frames), the
 * true centre in each template frame is minus the centroid. */
static const double k_pelvis[4][3] = {/* RASIS, LASIS, LPSIS, RPSIS about the right hip */
                                      {70.0, 80.0, 95.0},
                                      {70.0, 320.0, 95.0},
                                      {-105.0, 245.0, 125.0},
                                      {-105.0, 120.0, 125.0}};
static const double k_thigh_b[5][3] = {/* THI1-3, lateral and medial epicondyle */
                                       {45.0, -70.0, -150.0},
                                       {60.0, -55.0, -230.0},
                                       {30.0, -80.0, -310.0},
                                       {5.0, -50.0, -420.0},
                                       {5.0, 45.0, -420.0}};
/* Knee: the thigh cluster as parent, a shank cluster as child. */
static const double k_thigh_k[4][3] = {
    {40.0, -70.0, 260.0}, {70.0, -45.0, 180.0}, {20.0, -75.0, 110.0}, {-30.0, -60.0, 200.0}};
static const double k_shank[4][3] = {
    {35.0, -60.0, -110.0}, {60.0, -40.0, -190.0}, {20.0, -65.0, -270.0}, {-25.0, -55.0, -170.0}};
static const double k_knee_axis[3] = {0.04, 1.0, -0.03}; /* normalised at start */

typedef struct seg {
    int m;                 /* markers */
    double tpl[MAXM][3];   /* centred template */
    double c[3];           /* joint centre in the template frame */
    sfit_vec3_t ftpl[MAXM];
    double kmat[9];        /* J^-1 (per unit variance): rotation noise covariance */
} seg_t;

static seg_t g_par_b, g_chi_b, g_par_k, g_chi_k;
static double g_axis0[3];

static void inv3(const double a[9], double o[9])
{
    const double c0 = a[4] * a[8] - a[5] * a[7], c1 = a[5] * a[6] - a[3] * a[8],
                 c2 = a[3] * a[7] - a[4] * a[6];
    const double det = a[0] * c0 + a[1] * c1 + a[2] * c2;
    o[0] = c0 / det;
    o[1] = (a[2] * a[7] - a[1] * a[8]) / det;
    o[2] = (a[1] * a[5] - a[2] * a[4]) / det;
    o[3] = c1 / det;
    o[4] = (a[0] * a[8] - a[2] * a[6]) / det;
    o[5] = (a[2] * a[3] - a[0] * a[5]) / det;
    o[6] = c2 / det;
    o[7] = (a[1] * a[6] - a[0] * a[7]) / det;
    o[8] = (a[0] * a[4] - a[1] * a[3]) / det;
}

static void seg_make(seg_t *s, const double (*x)[3], int m)
{
    double mean[3] = {0.0, 0.0, 0.0}, jm[9];
    int i, k, l;
    s->m = m;
    for (i = 0; i < m; i++) {
        for (k = 0; k < 3; k++) {
            mean[k] += x[i][k] / m;
        }
    }
    memset(jm, 0, sizeof jm);
    for (i = 0; i < m; i++) {
        double n2;
        for (k = 0; k < 3; k++) {
            s->tpl[i][k] = x[i][k] - mean[k];
            s->ftpl[i].v[k] = (float)s->tpl[i][k];
        }
        n2 = tu_dot3(s->tpl[i], s->tpl[i]);
        for (k = 0; k < 3; k++) {
            for (l = 0; l < 3; l++) {
                jm[3 * k + l] += (k == l ? n2 : 0.0) - s->tpl[i][k] * s->tpl[i][l];
            }
        }
    }
    for (k = 0; k < 3; k++) {
        s->c[k] = -mean[k];
    }
    inv3(jm, s->kmat);
}

/* ------------------------------------------------------------ rotations */

static void matmul3(const double a[9], const double b[9], double o[9])
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

/* o = a^T b */
static void matmul3_tn(const double a[9], const double b[9], double o[9])
{
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            o[3 * i + j] = a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j];
        }
    }
}

static void matvec3(const double a[9], const double x[3], double o[3])
{
    double t[3];
    int i;
    for (i = 0; i < 3; i++) {
        t[i] = a[3 * i] * x[0] + a[3 * i + 1] * x[1] + a[3 * i + 2] * x[2];
    }
    memcpy(o, t, sizeof t);
}

static void matvec3_t(const double a[9], const double x[3], double o[3])
{
    double t[3];
    int i;
    for (i = 0; i < 3; i++) {
        t[i] = a[i] * x[0] + a[3 + i] * x[1] + a[6 + i] * x[2];
    }
    memcpy(o, t, sizeof t);
}

static void rot(const double u[3], double ang, double r[9])
{
    if (ang == 0.0) {
        static const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        memcpy(r, id, sizeof id);
        return;
    }
    tu_rot_axis_angle(u, ang, r);
}

static double deg(double d)
{
    return d * TU_PI / 180.0;
}

/* rotation vector (axis * angle) of a rotation matrix, small to moderate angles */
static void rotvec(const double r[9], double w[3])
{
    const double c = fmax(-1.0, fmin(1.0, (r[0] + r[4] + r[8] - 1.0) / 2.0));
    const double a = acos(c), s = sin(a);
    const double f = (s > 1e-12) ? a / (2.0 * s) : 0.5;
    w[0] = f * (r[7] - r[5]);
    w[1] = f * (r[2] - r[6]);
    w[2] = f * (r[3] - r[1]);
}

/* ------------------------------------------------------------ cells */

typedef enum kind { K_BALL = 0, K_HINGE = 1 } kind_t;

typedef struct cell {
    kind_t kind;
    int still;      /* nearly still parent */
    int sta;        /* soft-tissue artefact */
    int wobble;     /* hinge: 2-5 deg out-of-axis motion */
    double rom;     /* ball: range of motion (deg); hinge: flexion range (deg) */
    double sigma;   /* marker noise (mm) */
} cell_t;

/* ------------------------------------------------------------ methods */

enum {
    E_MGDK = 0,
    E_MGDK_SIG,
    E_MGDK_EST,
    E_SCORE,
    E_SCORE_EIV,
    E_SCORE_GLS,
#ifdef SFIT_MC_HAVE_PAIR
    E_PAIR_DEF,
    E_PAIR_SCORE,
    E_PAIR_AUTO,
#endif
    E_COUNT
};
static const char *const k_ename[E_COUNT] = {
    "mgdk", "mgdk_sig", "mgdk_est", "score", "score_eiv", "score_gls",
#ifdef SFIT_MC_HAVE_PAIR
    "pair_default", "pair_score", "pair_auto",
#endif
};

typedef struct res {
    int ok;         /* 1: a result */
    int flagged;    /* SFIT_FLAG_UNTRUSTED (library) */
    int cov;        /* -1 no covariance, 0 outside, 1 inside the 95 % ellipsoid */
    int planar;     /* ball trials: the result is a hinge (mode auto) */
    double err;     /* centre error (mm) or axis error (deg) */
    double e[3];    /* ball: the centre's error vector (parent frame, mm) */
    int reason;     /* pair module: sfit_pair_reason_t of a flagged result */
    double tr;      /* trace of the reported covariance (0: none) */
} res_t;

static res_t g_res[E_COUNT][TMAX];

/* ------------------------------------------------------------ one trial */

static double g_pm[FMAX][MAXM][3], g_cm[FMAX][MAXM][3]; /* float-rounded markers */
static sfit_vec3_t g_pf[FMAX][MAXM], g_cf[FMAX][MAXM];
static double g_rp[FMAX][9], g_tp[FMAX][3], g_rc[FMAX][9], g_tc[FMAX][3];
static int g_nf;
static double g_sig2_hat; /* marker variance from the registration residuals */
static sfit_joint_t g_j;
static sfit_vec3_t g_pflat[FMAX * MAXM], g_cflat[FMAX * MAXM]; /* frame-major, no padding */

/* Relative rotation of frame f (child in parent, about the joint centre). */
static void rel_rot(const cell_t *c, int f, int nf, double phi0, const double wob[6],
                    double r[9])
{
    const double s = (double)f / (double)nf;
    if (c->kind == K_BALL) {
        const double a = deg(c->rom) / 2.0;
        const int star = 4 * 60;
        double u[3];
        if (f < star) {
            const int arc = f / 60;
            const double sa = (double)(f % 60) / 60.0, ph = phi0 + deg(45.0) * arc;
            u[0] = cos(ph);
            u[1] = sin(ph);
            u[2] = 0.0;
            rot(u, a * sin(2.0 * TU_PI * sa), r);
        } else {
            const double ps = 2.0 * TU_PI * (double)(f - star) / (double)(nf - star) + phi0;
            u[0] = cos(ps);
            u[1] = sin(ps);
            u[2] = 0.0;
            rot(u, a, r);
        }
    } else {
        const double th = deg(c->rom) * (1.0 - cos(2.0 * TU_PI * 3.0 * s)) / 2.0;
        rot(g_axis0, -th, r);
        if (c->wobble) {
            static const double ex[3] = {1.0, 0.0, 0.0}, ez[3] = {0.0, 0.0, 1.0};
            double q[9];
            /* ab/adduction and internal rotation: smooth, not coupled to the
             * flexion (non-commensurate frequencies), peak wob[0], wob[1] */
            rot(ex, wob[0] * (0.6 * sin(2.0 * TU_PI * 2.3 * s + wob[2])
                              + 0.4 * sin(2.0 * TU_PI * 4.7 * s + wob[3])), q);
            matmul3(r, q, r);
            rot(ez, wob[1] * (0.6 * sin(2.0 * TU_PI * 1.7 * s + wob[4])
                              + 0.4 * sin(2.0 * TU_PI * 5.3 * s + wob[5])), q);
            matmul3(r, q, r);
        }
    }
}

/* Parent pose of frame f. */
static void parent_pose(const cell_t *c, int f, int nf, double head, double r[9], double t[3])
{
    static const double ex[3] = {1.0, 0.0, 0.0}, ey[3] = {0.0, 1.0, 0.0},
                        ez[3] = {0.0, 0.0, 1.0};
    const double s = (double)f / (double)nf, w = 2.0 * TU_PI * s;
    double q[9];
    if (c->still) {
        rot(ez, head + deg(0.2) * sin(2.0 * w), r);
        rot(ex, deg(0.1) * sin(3.0 * w + 1.0), q);
        matmul3(r, q, r);
        t[0] = 1500.0 + 0.5 * sin(w);
        t[1] = 400.0 + 0.5 * sin(2.0 * w);
        t[2] = 900.0;
    } else {
        rot(ez, head + deg(10.0) * sin(2.0 * w), r);
        rot(ex, deg(5.0) * sin(3.0 * w + 1.0), q);
        matmul3(r, q, r);
        rot(ey, deg(5.0) * sin(w), q);
        matmul3(r, q, r);
        t[0] = 700.0 + 2200.0 * s; /* 1.2 m to 3.0 m from the lab origin */
        t[1] = 400.0 + 30.0 * sin(3.0 * w);
        t[2] = 900.0 + 20.0 * sin(5.0 * w);
    }
}

/* A rigid displacement of a cluster on its segment, linear in the joint's
 * rotation vector w: rotation by a w, translation b w (3x3 each, random per
 * trial, RMS gains ga rad/rad and gb mm/rad). */
typedef struct sta {
    double a[9], b[9];
} sta_t;

static void sta_draw(tu_rng_t *g, double ga, double gb, sta_t *s)
{
    int k;
    for (k = 0; k < 9; k++) {
        s->a[k] = ga * tu_rng_gauss(g) / sqrt(3.0);
        s->b[k] = gb * tu_rng_gauss(g) / sqrt(3.0);
    }
}

static void sta_apply(const sta_t *s, const double w[3], const double x[3], double o[3])
{
    double aw[3], bw[3], r[9], n;
    matvec3(s->a, w, aw);
    matvec3(s->b, w, bw);
    n = tu_norm3(aw);
    rot(aw, n, r);
    matvec3(r, x, o);
    o[0] += bw[0];
    o[1] += bw[1];
    o[2] += bw[2];
}

static void make_trial(const cell_t *c, tu_rng_t *g, const seg_t *ps, const seg_t *cs)
{
    const int nf = (c->kind == K_BALL) ? 4 * 60 + 120 : 240;
    const double phi0 = deg(45.0) * tu_rng_uniform(g), head = 2.0 * TU_PI * tu_rng_uniform(g);
    double wob[6];
    sta_t sp, sc;
    int f, i, k;
    wob[0] = deg(2.0 + 3.0 * tu_rng_uniform(g));
    wob[1] = deg(2.0 + 3.0 * tu_rng_uniform(g));
    for (k = 2; k < 6; k++) {
        wob[k] = 2.0 * TU_PI * tu_rng_uniform(g);
    }
    sta_draw(g, 0.04, 8.0, &sp);  /* pelvis / thigh-on-knee cluster */
    sta_draw(g, 0.10, 20.0, &sc); /* thigh / shank cluster */
    g_nf = nf;
    for (f = 0; f < nf; f++) {
        double rp[9], tp[3], rr[9], rc[9], tc[3], w[3], a[3];
        parent_pose(c, f, nf, head, rp, tp);
        rel_rot(c, f, nf, phi0, wob, rr);
        matmul3(rp, rr, rc);
        /* t_c = R_p c_p + t_p - R_c c_c: the centre is common */
        matvec3(rp, ps->c, tc);
        matvec3(rc, cs->c, a);
        for (k = 0; k < 3; k++) {
            tc[k] += tp[k] - a[k];
        }
        rotvec(rr, w);
        for (i = 0; i < ps->m; i++) {
            double x[3], y[3];
            if (c->sta) {
                sta_apply(&sp, w, ps->tpl[i], x);
            } else {
                memcpy(x, ps->tpl[i], sizeof x);
            }
            ref_pose_to_global(rp, tp, x, y);
            for (k = 0; k < 3; k++) {
                volatile float v = (float)(y[k] + c->sigma * tu_rng_gauss(g));
                g_pf[f][i].v[k] = v;
                g_pm[f][i][k] = (double)v;
            }
        }
        for (i = 0; i < cs->m; i++) {
            double x[3], y[3];
            if (c->sta) {
                sta_apply(&sc, w, cs->tpl[i], x);
            } else {
                memcpy(x, cs->tpl[i], sizeof x);
            }
            ref_pose_to_global(rc, tc, x, y);
            for (k = 0; k < 3; k++) {
                volatile float v = (float)(y[k] + c->sigma * tu_rng_gauss(g));
                g_cf[f][i].v[k] = v;
                g_cm[f][i][k] = (double)v;
            }
        }
    }
}

/* Double registration of both clusters (Horn); the marker variance from the
 * residuals: E sum |res|^2 = (3 M - 6) sigma^2 per cluster and frame. */
static void register_double(const seg_t *ps, const seg_t *cs)
{
    double ss = 0.0, dof = 0.0;
    int f;
    for (f = 0; f < g_nf; f++) {
        double rms;
        (void)ref_horn_pose((const double(*)[3])ps->tpl, (const double(*)[3])g_pm[f], NULL,
                            (size_t)ps->m, g_rp[f], g_tp[f], &rms);
        ss += rms * rms * ps->m;
        (void)ref_horn_pose((const double(*)[3])cs->tpl, (const double(*)[3])g_cm[f], NULL,
                            (size_t)cs->m, g_rc[f], g_tc[f], &rms);
        ss += rms * rms * cs->m;
        dof += 3.0 * ps->m - 6.0 + 3.0 * cs->m - 6.0;
    }
    g_sig2_hat = ss / dof;
}

/* ------------------------------------------------------------ SCoRE / SARA */

/* Solve a x = b (n x n, partial pivoting); returns 0 or -1 (singular). */
static int solve_n(const double *a_in, const double *b_in, int n, double *x)
{
    double a[36], b[6];
    int i, j, k;
    memcpy(a, a_in, sizeof(double) * (size_t)(n * n));
    memcpy(b, b_in, sizeof(double) * (size_t)n);
    for (k = 0; k < n; k++) {
        int p = k;
        for (i = k + 1; i < n; i++) {
            if (fabs(a[i * n + k]) > fabs(a[p * n + k])) {
                p = i;
            }
        }
        if (a[p * n + k] == 0.0) {
            return -1;
        }
        if (p != k) {
            double t;
            for (j = 0; j < n; j++) {
                t = a[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = t;
            }
            t = b[k];
            b[k] = b[p];
            b[p] = t;
        }
        for (i = k + 1; i < n; i++) {
            const double m = a[i * n + k] / a[k * n + k];
            for (j = k; j < n; j++) {
                a[i * n + j] -= m * a[k * n + j];
            }
            b[i] -= m * b[k];
        }
    }
    for (k = n - 1; k >= 0; k--) {
        double s = b[k];
        for (j = k + 1; j < n; j++) {
            s -= a[k * n + j] * x[j];
        }
        x[k] = s / a[k * n + k];
    }
    return 0;
}

/* (I - K)^-1 for the errors-in-variables shrinkage of a noisy rotation:
 * R = R0 exp([d]x), d ~ (0, s2 J^-1) in the segment frame, so
 * E[R] = R0 (I - K) with K = s2 (tr(J^-1) I - J^-1) / 2 to second order. */
static void eiv_shrink(const seg_t *s, double s2, double o[9])
{
    double k[9];
    const double tr = s->kmat[0] + s->kmat[4] + s->kmat[8];
    int i;
    for (i = 0; i < 9; i++) {
        k[i] = -s2 * s->kmat[i] / 2.0;
    }
    for (i = 0; i < 3; i++) {
        k[4 * i] += s2 * tr / 2.0;
    }
    for (i = 0; i < 9; i++) {
        k[i] = (i % 4 == 0 ? 1.0 : 0.0) - k[i];
    }
    inv3(k, o);
}

/* The SCoRE normal equations with optional de-shrinking matrices dp, dc
 * ((I - K)^-1 of each segment, NULL = none): per frame
 *   psi_f(x) = [c_p - Mt_f c_c - bp_f ; c_c - Mt_f^T c_p - bc_f],
 *   Mt_f = Dp R_p^T R_c Dc, bp_f = Dp R_p^T (t_c - t_p), bc_f = -Dc R_c^T (t_c - t_p).
 * Returns the 6x6 matrix h (row-major) and the right-hand side g. */
static void score_system(const double *dp, const double *dc, double h[36], double g[6])
{
    double m[9] = {0}, bp[3] = {0}, bc[3] = {0};
    int f, i, j;
    for (f = 0; f < g_nf; f++) {
        double pc[9], d[3], u[3], v[3];
        matmul3_tn(g_rp[f], g_rc[f], pc);
        for (i = 0; i < 3; i++) {
            d[i] = g_tc[f][i] - g_tp[f][i];
        }
        matvec3_t(g_rp[f], d, u);
        matvec3_t(g_rc[f], d, v);
        for (i = 0; i < 9; i++) {
            m[i] += pc[i];
        }
        for (i = 0; i < 3; i++) {
            bp[i] += u[i];
            bc[i] -= v[i];
        }
    }
    if (dp != NULL) {
        matmul3(dp, m, m);
        matmul3(m, dc, m);
        matvec3(dp, bp, bp);
        matvec3(dc, bc, bc);
    }
    memset(h, 0, 36 * sizeof *h);
    for (i = 0; i < 3; i++) {
        h[6 * i + i] = (double)g_nf;
        h[6 * (i + 3) + i + 3] = (double)g_nf;
        for (j = 0; j < 3; j++) {
            h[6 * i + j + 3] = -m[3 * i + j];
            h[6 * (j + 3) + i] = -m[3 * i + j];
        }
        g[i] = bp[i];
        g[i + 3] = bc[i];
    }
}

/* Sandwich covariance of c_p: H^-1 (sum psi_f psi_f^T) H^-T at x. */
static int score_cov(const double *dp, const double *dc, const double h[36], const double x[6],
                     double cov[9])
{
    double meat[36] = {0}, hinv[36], e[6];
    int f, i, j, k;
    for (f = 0; f < g_nf; f++) {
        double pc[9], d[3], u[3], v[3], psi[6], a[3], b[3];
        matmul3_tn(g_rp[f], g_rc[f], pc);
        if (dp != NULL) {
            matmul3(dp, pc, pc);
            matmul3(pc, dc, pc);
        }
        for (i = 0; i < 3; i++) {
            d[i] = g_tc[f][i] - g_tp[f][i];
        }
        matvec3_t(g_rp[f], d, u);
        matvec3_t(g_rc[f], d, v);
        if (dp != NULL) {
            matvec3(dp, u, u);
            matvec3(dc, v, v);
        }
        matvec3(pc, x + 3, a);
        matvec3_t(pc, x, b);
        for (i = 0; i < 3; i++) {
            psi[i] = x[i] - a[i] - u[i];
            psi[i + 3] = x[i + 3] - b[i] + v[i];
        }
        for (i = 0; i < 6; i++) {
            for (j = 0; j < 6; j++) {
                meat[6 * i + j] += psi[i] * psi[j];
            }
        }
    }
    for (k = 0; k < 6; k++) { /* columns of H^-1 */
        double col[6];
        for (i = 0; i < 6; i++) {
            e[i] = (i == k) ? 1.0 : 0.0;
        }
        if (solve_n(h, e, 6, col) != 0) {
            return -1;
        }
        for (i = 0; i < 6; i++) {
            hinv[6 * i + k] = col[i];
        }
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            int a, b;
            for (a = 0; a < 6; a++) {
                for (b = 0; b < 6; b++) {
                    s += hinv[6 * i + a] * meat[6 * a + b] * hinv[6 * j + b];
                }
            }
            cov[3 * i + j] = s;
        }
    }
    return 0;
}

static double g_last_tr; /* trace of the last covariance given to covered3 */

static int covered3(const double cov[9], const double e[3])
{
    double x[3];
    g_last_tr = cov[0] + cov[4] + cov[8];
    if (solve_n(cov, e, 3, x) != 0) {
        return 0;
    }
    return tu_dot3(e, x) <= CHI2_3_95;
}

/* SCoRE centre (ball) in the parent frame, or SARA axis (hinge): the axis is
 * the eigenvector of the smallest eigenvalue of the Schur complement
 * N I - M M^T / N (M the possibly de-shrunk sum of R_p^T R_c). */
static void run_score(const cell_t *c, const seg_t *ps, const seg_t *cs, int eiv, res_t *out)
{
    double dp[9], dc[9], h[36], g[6], x[6];
    memset(out, 0, sizeof *out);
    out->cov = -1;
    if (eiv) {
        eiv_shrink(ps, g_sig2_hat, dp);
        eiv_shrink(cs, g_sig2_hat, dc);
    }
    score_system(eiv ? dp : NULL, eiv ? dc : NULL, h, g);
    if (c->kind == K_BALL) {
        double e[3], cov[9];
        int k;
        if (solve_n(h, g, 6, x) != 0) {
            return;
        }
        out->ok = 1;
        for (k = 0; k < 3; k++) {
            e[k] = x[k] - ps->c[k];
            out->e[k] = e[k];
        }
        out->err = tu_norm3(e);
        if (score_cov(eiv ? dp : NULL, eiv ? dc : NULL, h, x, cov) == 0) {
            out->cov = covered3(cov, e);
            out->tr = g_last_tr;
        }
    } else {
        double s[9], w[3], v[9], a[3];
        int i, j, lo = 0;
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                double mm = 0.0;
                int k;
                for (k = 0; k < 3; k++) {
                    mm += h[6 * i + 3 + k] * h[6 * j + 3 + k];
                }
                s[3 * i + j] = (i == j ? (double)g_nf : 0.0) - mm / (double)g_nf;
            }
        }
        ref_jacobi_n(s, 3, w, v);
        for (i = 1; i < 3; i++) {
            if (w[i] < w[lo]) {
                lo = i;
            }
        }
        for (i = 0; i < 3; i++) {
            a[i] = v[3 * i + lo];
        }
        out->ok = 1;
        out->err = acos(fmin(1.0, fabs(tu_dot3(a, g_axis0)) / tu_norm3(a))) * 180.0 / TU_PI;
    }
}

/* [a]x b for the unit vector e_a: the cross-product matrix of e_a */
static void skew_unit(int a, double o[9])
{
    memset(o, 0, 9 * sizeof *o);
    switch (a) {
    case 0:
        o[5] = -1.0;
        o[7] = 1.0;
        break;
    case 1:
        o[2] = 1.0;
        o[6] = -1.0;
        break;
    default:
        o[1] = -1.0;
        o[3] = 1.0;
        break;
    }
}

/* Noise covariance (per unit marker variance) of a segment point x seen
 * through the segment's pose, in the segment frame: I/M + [x]x J^-1 [x]x^T. */
static void point_cov(const seg_t *s, const double x[3], double o[9])
{
    double sx[9], t[9];
    int i;
    sx[0] = 0.0;
    sx[1] = -x[2];
    sx[2] = x[1];
    sx[3] = x[2];
    sx[4] = 0.0;
    sx[5] = -x[0];
    sx[6] = -x[1];
    sx[7] = x[0];
    sx[8] = 0.0;
    matmul3(sx, s->kmat, t);
    for (i = 0; i < 3; i++) {
        int j;
        for (j = 0; j < 3; j++) {
            o[3 * i + j] = t[3 * i] * sx[3 * j] + t[3 * i + 1] * sx[3 * j + 1]
                           + t[3 * i + 2] * sx[3 * j + 2] + (i == j ? 1.0 / s->m : 0.0);
        }
    }
}

/* A sum of R^T W R (segment frame) corrected for the rotation noise
 * d ~ (0, s2 J^-1): E[Rn^T W Rn] = A - K A - A K - E[[d]x A [d]x]. */
static void diag_correct(const seg_t *s, double s2, const double a_in[9], double o[9])
{
    double k[9], t[9], a[9];
    const double tr = s->kmat[0] + s->kmat[4] + s->kmat[8];
    int i, p, q;
    memcpy(a, a_in, sizeof a);
    for (i = 0; i < 9; i++) {
        k[i] = -s2 * s->kmat[i] / 2.0 + (i % 4 == 0 ? s2 * tr / 2.0 : 0.0);
    }
    matmul3(k, a, o);
    matmul3(a, k, t);
    for (i = 0; i < 9; i++) {
        o[i] = a[i] + o[i] + t[i];
    }
    for (p = 0; p < 3; p++) {
        for (q = 0; q < 3; q++) {
            double ep[9], eq[9];
            const double c = s2 * s->kmat[3 * p + q];
            skew_unit(p, ep);
            skew_unit(q, eq);
            matmul3(ep, a, t);
            matmul3(t, eq, t);
            for (i = 0; i < 9; i++) {
                o[i] += c * t[i];
            }
        }
    }
}

/* Feasible weighted SCoRE with the errors-in-variables correction: weights
 * W_f = (R_p S_p R_p^T + R_c S_c R_c^T)^-1 at a first estimate x0 (S the
 * point covariances of the centre in each segment), then the weighted
 * normal equations with the off-diagonal blocks and the right-hand side
 * de-shrunk and the diagonal blocks corrected (diag_correct). */
static void run_score_gls(const cell_t *c, const seg_t *ps, const seg_t *cs, res_t *out)
{
    double dp[9], dc[9], h[36], g[6], x[6], sp[9], sc[9];
    double app[9] = {0}, acc[9] = {0}, apc[9] = {0}, bp[3] = {0}, bc[3] = {0};
    int f, i, j, k;
    run_score(c, ps, cs, 1, out);
    if (!out->ok || c->kind != K_BALL) {
        return;
    }
    for (k = 0; k < 3; k++) {
        x[k] = ps->c[k] + out->e[k];
    }
    /* c_c from the first estimate's second row */
    eiv_shrink(ps, g_sig2_hat, dp);
    eiv_shrink(cs, g_sig2_hat, dc);
    score_system(dp, dc, h, g);
    if (solve_n(h, g, 6, x) != 0) {
        return;
    }
    point_cov(ps, x, sp);
    point_cov(cs, x + 3, sc);
    for (f = 0; f < g_nf; f++) {
        double a1[9], a2[9], w[9], t[9], d[3], u[3];
        matmul3(g_rp[f], sp, t);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                a1[3 * i + j] = t[3 * i] * g_rp[f][3 * j] + t[3 * i + 1] * g_rp[f][3 * j + 1]
                                + t[3 * i + 2] * g_rp[f][3 * j + 2];
            }
        }
        matmul3(g_rc[f], sc, t);
        for (i = 0; i < 3; i++) {
            for (j = 0; j < 3; j++) {
                a2[3 * i + j] = t[3 * i] * g_rc[f][3 * j] + t[3 * i + 1] * g_rc[f][3 * j + 1]
                                + t[3 * i + 2] * g_rc[f][3 * j + 2];
            }
        }
        for (i = 0; i < 9; i++) {
            a1[i] += a2[i];
        }
        inv3(a1, w);
        /* R_p^T W R_p, R_c^T W R_c, R_p^T W R_c, R_p^T W d, R_c^T W d */
        matmul3_tn(g_rp[f], w, t);
        matmul3(t, g_rp[f], a1);
        matmul3(t, g_rc[f], a2);
        for (i = 0; i < 9; i++) {
            app[i] += a1[i];
            apc[i] += a2[i];
        }
        for (i = 0; i < 3; i++) {
            d[i] = g_tc[f][i] - g_tp[f][i];
        }
        matvec3(t, d, u);
        for (i = 0; i < 3; i++) {
            bp[i] += u[i];
        }
        matmul3_tn(g_rc[f], w, t);
        matmul3(t, g_rc[f], a1);
        for (i = 0; i < 9; i++) {
            acc[i] += a1[i];
        }
        matvec3(t, d, u);
        for (i = 0; i < 3; i++) {
            bc[i] -= u[i];
        }
    }
    diag_correct(ps, g_sig2_hat, app, app);
    diag_correct(cs, g_sig2_hat, acc, acc);
    matmul3(dp, apc, apc);
    matmul3(apc, dc, apc);
    matvec3(dp, bp, bp);
    matvec3(dc, bc, bc);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            h[6 * i + j] = app[3 * i + j];
            h[6 * (i + 3) + j + 3] = acc[3 * i + j];
            h[6 * i + j + 3] = -apc[3 * i + j];
            h[6 * (j + 3) + i] = -apc[3 * i + j];
        }
        g[i] = bp[i];
        g[i + 3] = bc[i];
    }
    if (solve_n(h, g, 6, x) != 0) {
        out->ok = 0;
        return;
    }
    for (k = 0; k < 3; k++) {
        out->e[k] = x[k] - ps->c[k];
    }
    out->err = tu_norm3(out->e);
    out->cov = -1;
}

/* ------------------------------------------------------------ MGDK */

static void run_mgdk(const cell_t *c, const sfit_cluster_t *cl, const seg_t *ps, const seg_t *cs,
                     int noise, double var, res_t *out)
{
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t r;
    sfit_status_t st;
    int f;
    memset(out, 0, sizeof *out);
    out->cov = -1;
    cfg.n_child = (uint32_t)cs->m;
    cfg.solve.fit.mode = (c->kind == K_BALL) ? SFIT_MODE_AUTO : SFIT_MODE_PLANAR;
    if (noise) {
        cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
        cfg.solve.fit.noise = SFIT_NOISE_ISO;
        cfg.solve.fit.noise_var = (float)var;
    }
    st = sfit_joint_init(&g_j, cl, &cfg);
    for (f = 0; f < g_nf && st == SFIT_OK; f++) {
        st = sfit_joint_add(&g_j, g_pf[f], (size_t)ps->m, g_cf[f], (size_t)cs->m, NULL);
    }
    if (st == SFIT_OK) {
        st = sfit_joint_fit(&g_j, &r, NULL);
    }
    if (st != SFIT_OK) {
        return;
    }
    out->ok = 1;
    out->flagged = (r.fit.flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u;
    out->planar = r.fit.mode == SFIT_MODE_PLANAR;
    if (c->kind == K_BALL) {
        double e[3];
        sfit_mat3_t cv;
        int k;
        for (k = 0; k < 3; k++) {
            e[k] = (double)r.fit.center.v[k] - ps->c[k];
            out->e[k] = e[k];
        }
        out->err = tu_norm3(e);
        /* the covariance this fit would report with the true (mgdk) or the
         * used (mgdk_sig, mgdk_est) marker variance */
        for (f = 0; f < g_nf; f++) {
            for (k = 0; k < ps->m; k++) {
                g_pflat[f * ps->m + k] = g_pf[f][k];
            }
            for (k = 0; k < cs->m; k++) {
                g_cflat[f * cs->m + k] = g_cf[f][k];
            }
        }
        if (r.fit.mode == SFIT_MODE_SPHERE
            && sfit_joint_center_cov(&g_j, &r, g_pflat, g_cflat, (size_t)g_nf,
                                     (float)(noise ? var : c->sigma * c->sigma),
                                     &cv) == SFIT_OK) {
            double cd[9];
            for (k = 0; k < 9; k++) {
                cd[k] = (double)cv.m[k];
            }
            out->cov = covered3(cd, e);
            out->tr = g_last_tr;
        }
    } else {
        double a[3];
        int k;
        for (k = 0; k < 3; k++) {
            a[k] = (double)r.fit.axis.v[k];
        }
        out->err = acos(fmin(1.0, fabs(tu_dot3(a, g_axis0)) / tu_norm3(a))) * 180.0 / TU_PI;
    }
}

/* ------------------------------------------------------------ pair module */

#ifdef SFIT_MC_HAVE_PAIR
static int g_pair_ok = 1; /* 0 once sfit_pair_init says the module is not built */

/* d^2 of the unit-axis error e in the rank-2 covariance c (pseudo-inverse
 * over its two largest eigenvalues); covered when <= chi^2_2(0.95). */
static int covered_axis(const double c[9], const double e[3])
{
    double w[3], v[9], d2 = 0.0;
    int i, lo = 0;
    ref_jacobi_n(c, 3, w, v);
    for (i = 1; i < 3; i++) {
        if (w[i] < w[lo]) {
            lo = i;
        }
    }
    for (i = 0; i < 3; i++) {
        double p;
        if (i == lo) {
            continue;
        }
        if (!(w[i] > 0.0)) {
            return 0;
        }
        p = v[i] * e[0] + v[3 + i] * e[1] + v[6 + i] * e[2];
        d2 += p * p / w[i];
    }
    return d2 <= CHI2_2_95;
}

static void run_pair(const cell_t *c, const sfit_cluster_t *clp, const sfit_cluster_t *clc,
                     const seg_t *ps, const seg_t *cs, sfit_pair_method_t method,
                     sfit_pair_mode_t mode, res_t *out)
{
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_pair_t st;
    sfit_pair_result_t r;
    sfit_status_t rc;
    int f, k;
    memset(out, 0, sizeof *out);
    out->cov = -1;
    cfg.method = method;
    cfg.mode = mode;
    rc = sfit_pair_init(&st, clp, clc, &cfg);
    if (rc == SFIT_E_UNSUPPORTED) {
        g_pair_ok = 0;
    }
    for (f = 0; f < g_nf && rc == SFIT_OK; f++) {
        rc = sfit_pair_add_markers(&st, clp, g_pf[f], (size_t)ps->m, clc, g_cf[f],
                                   (size_t)cs->m);
    }
    if (rc == SFIT_OK) {
        rc = sfit_pair_solve(&st, &r);
    }
    if (rc != SFIT_OK) {
        return;
    }
    out->ok = 1;
    out->flagged = (r.flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u;
    out->reason = (int)r.reason;
    out->planar = r.mode == SFIT_PAIR_MODE_HINGE;
    if (c->kind == K_BALL) {
        double cd[9];
        for (k = 0; k < 3; k++) {
            out->e[k] = (double)r.center_p.v[k] - ps->c[k];
        }
        out->err = tu_norm3(out->e);
        for (k = 0; k < 9; k++) {
            cd[k] = (double)r.center_cov.m[k];
        }
        out->cov = covered3(cd, out->e);
        out->tr = g_last_tr;
    } else {
        double a[3], e[3], cd[9], sg;
        for (k = 0; k < 3; k++) {
            a[k] = (double)r.axis_p.v[k];
        }
        sg = (tu_dot3(a, g_axis0) < 0.0) ? -1.0 : 1.0;
        for (k = 0; k < 3; k++) {
            e[k] = a[k] - sg * g_axis0[k];
        }
        out->err = acos(fmin(1.0, fabs(tu_dot3(a, g_axis0)) / tu_norm3(a))) * 180.0 / TU_PI;
        for (k = 0; k < 9; k++) {
            cd[k] = (double)r.axis_cov.m[k];
        }
        out->cov = covered_axis(cd, e);
    }
}
#endif

/* ------------------------------------------------------------ statistics */

typedef struct stat {
    long n, ok, flagged, unfl, cov_n, cov_in, planar;
    double mean, sd, p95, mean_unfl, bias;
    double trratio; /* unflagged with a covariance: mean reported trace / MC trace */
} stat_t;

static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void stats(const res_t *r, int n, stat_t *s)
{
    static double v[TMAX];
    double sum = 0.0, ss = 0.0, su = 0.0, be[3] = {0.0, 0.0, 0.0};
    double cs[3] = {0.0, 0.0, 0.0}, css = 0.0, ctr = 0.0;
    int i, m = 0;
    memset(s, 0, sizeof *s);
    s->n = n;
    for (i = 0; i < n; i++) {
        if (!r[i].ok) {
            continue;
        }
        s->ok++;
        v[m++] = r[i].err;
        sum += r[i].err;
        ss += r[i].err * r[i].err;
        s->planar += r[i].planar;
        be[0] += r[i].e[0];
        be[1] += r[i].e[1];
        be[2] += r[i].e[2];
        if (r[i].flagged) {
            s->flagged++;
            continue;
        }
        s->unfl++;
        su += r[i].err;
        if (r[i].cov >= 0) {
            int k;
            s->cov_n++;
            s->cov_in += r[i].cov;
            ctr += r[i].tr;
            for (k = 0; k < 3; k++) {
                cs[k] += r[i].e[k];
                css += r[i].e[k] * r[i].e[k];
            }
        }
    }
    if (m > 0) {
        qsort(v, (size_t)m, sizeof v[0], cmp_d);
        s->mean = sum / m;
        s->sd = (m > 1) ? sqrt(fmax(0.0, (ss - sum * sum / m) / (m - 1))) : 0.0;
        s->p95 = v[(int)ceil(0.95 * m) - 1];
        s->bias = tu_norm3(be) / m;
    }
    s->mean_unfl = (s->unfl > 0) ? su / (double)s->unfl : 0.0;
    if (s->cov_n > 1) {
        const double nn = (double)s->cov_n;
        const double mc = (css - tu_dot3(cs, cs) / nn) / (nn - 1.0);
        s->trratio = (mc > 0.0) ? (ctr / nn) / mc : 0.0;
    }
}

/* Paired test of mean(err_a) <= k mean(err_b) over the trials where both
 * gave a result and a is not flagged (a flagged result of a passes: it
 * says it is not to be trusted): the mean of d = err_a - k err_b and its
 * standard error. Returns the number of pairs. */
static long paired(const res_t *a, const res_t *b, int n, double k, int all, double *md,
                   double *se)
{
    double s = 0.0, ss = 0.0;
    long m = 0;
    int i;
    for (i = 0; i < n; i++) {
        double d;
        if (!a[i].ok || !b[i].ok || (a[i].flagged && !all)) {
            continue;
        }
        d = a[i].err - k * b[i].err;
        s += d;
        ss += d * d;
        m++;
    }
    *md = (m > 0) ? s / (double)m : 0.0;
    *se = (m > 1) ? sqrt(fmax(0.0, (ss - s * s / (double)m) / (double)(m - 1)) / (double)m) : 0.0;
    return m;
}

/* ------------------------------------------------------------ the grid */

static const double k_rom[] = {5, 10, 20, 30, 45, 60, 90};
static const double k_sig[] = {0.1, 0.5, 1.0, 2.0};
static const double k_flex[] = {10, 20, 30, 45, 60, 90};
static const double k_hsig[] = {0.5, 1.0, 2.0};

#define NCELL_MAX 256
static cell_t g_cells[NCELL_MAX];
static int g_ncell;

static void add_cell(kind_t kind, int still, int sta, int wobble, double rom, double sigma)
{
    cell_t *c = &g_cells[g_ncell++];
    c->kind = kind;
    c->still = still;
    c->sta = sta;
    c->wobble = wobble;
    c->rom = rom;
    c->sigma = sigma;
}

static void build_grid(int check)
{
    size_t a, b;
    int still;
    g_ncell = 0;
    for (still = 0; still < 2; still++) {
        for (a = 0; a < sizeof k_rom / sizeof k_rom[0]; a++) {
            for (b = 0; b < sizeof k_sig / sizeof k_sig[0]; b++) {
                if (check && ((k_rom[a] != 5 && k_rom[a] != 10 && k_rom[a] != 45)
                              || (k_sig[b] != 0.5 && k_sig[b] != 2.0))) {
                    continue;
                }
                add_cell(K_BALL, still, 0, 0, k_rom[a], k_sig[b]);
            }
        }
    }
    for (a = 0; a < sizeof k_rom / sizeof k_rom[0] && !check; a++) {
        add_cell(K_BALL, 0, 1, 0, k_rom[a], 0.5);
    }
    for (still = 0; still < 2; still++) { /* still = 0: pure hinge; 1: wobble */
        for (a = 0; a < sizeof k_flex / sizeof k_flex[0]; a++) {
            for (b = 0; b < sizeof k_hsig / sizeof k_hsig[0]; b++) {
                if (check && (k_hsig[b] != 1.0
                              || (k_flex[a] != 10 && k_flex[a] != 30 && k_flex[a] != 90))) {
                    continue;
                }
                add_cell(K_HINGE, 0, 0, still, k_flex[a], k_hsig[b]);
            }
        }
    }
}

static const char *cell_name(const cell_t *c, char *buf, size_t n)
{
    if (c->kind == K_BALL) {
        snprintf(buf, n, "ball %s%s", c->still ? "still" : "moving", c->sta ? " STA" : "");
    } else {
        snprintf(buf, n, "hinge %s", c->wobble ? "wobble 2-5" : "pure");
    }
    return buf;
}

static stat_t g_st[NCELL_MAX][E_COUNT];
static long g_big_unfl[NCELL_MAX]; /* hinge: default results > 10 deg off, not flagged */
static long g_reasons[NCELL_MAX][8]; /* default's flagged results by reason */

/* ------------------------------------------------------------ claims */

typedef struct claims {
    FILE *f;
    int def;    /* the method checked as "the default" */
    int n, fail, known;
} claims_t;

/* Claims measured not to hold (docs/joint_benchmark.md, "What does not
 * hold"): reported as "NO (known)" and not counted as failures, so that
 * the check guards every other claim. Remove an entry when it holds. */
static int known_exception(const cell_t *c, double lim, int all)
{
    /* None. (Until the weighted default, ball, moving parent, RoM 10,
     * sigma 0.5 was listed here: 0.64 x SCoRE.) */
    (void)c;
    (void)lim;
    (void)all;
    return 0;
}

/* mean(err_default - lim err_reference) <= 2 SE over the paired trials: all
 * results (all != 0), or those the default does not flag. */
static void claim_ratio(claims_t *k, const cell_t *c, int trials, double lim, int all)
{
    double md, se;
    char nm[64];
    const long m = paired(g_res[k->def], g_res[E_SCORE], trials, lim, all, &md, &se);
    const int ok = md <= 2.0 * se, known = !ok && known_exception(c, lim, all);
    k->n++;
    k->fail += !ok && !known;
    k->known += known;
    fprintf(k->f, "| %s | %g | %g | %s <= %.1f x %s (%s) | %ld | %+.3f +- %.3f | %s |\n",
            cell_name(c, nm, sizeof nm), c->rom, c->sigma, k_ename[k->def], lim,
            c->kind == K_BALL ? "SCoRE" : "SARA", all ? "all results" : "unflagged", m, md, se,
            ok ? "yes" : known ? "**NO** (known)" : "**NO**");
}

/* The claims above pass for flagged results; so that they cannot pass by
 * flagging everything, the default must leave a well-determined joint
 * unflagged: at most 5 % flagged (+ 2 binomial SE) in noise-only ball cells
 * with RoM >= 20 and pure-hinge cells with flexion >= 60. */
static void claim_not_overflagged(claims_t *k, const cell_t *c, const stat_t *d)
{
    const double fr = (double)d->flagged / (double)d->n;
    const double se = sqrt(0.05 * 0.95 / (double)d->n);
    const int ok = fr <= 0.05 + 2.0 * se;
    char nm[64];
    k->n++;
    k->fail += !ok;
    fprintf(k->f, "| %s | %g | %g | %s flags <= 5 %% (+ 2 SE) of a well-determined joint | "
                  "%ld | %.3f +- %.3f | %s |\n",
            cell_name(c, nm, sizeof nm), c->rom, c->sigma, k_ename[k->def], d->n, fr, se,
            ok ? "yes" : "**NO**");
}

static void claims_cell(claims_t *k, const cell_t *c, int ci, int trials)
{
    const stat_t *d = &g_st[ci][k->def];
    char nm[64];
    if (c->sta) {
        return;
    }
    if ((c->kind == K_BALL && c->rom >= 20.0) || (c->kind == K_HINGE && !c->wobble
                                                  && c->rom >= 60.0)) {
        claim_not_overflagged(k, c, d);
    }
    if (c->kind == K_BALL) {
        claim_ratio(k, c, trials, 1.1, 1);
        if (c->rom <= 10.0 && c->sigma >= 0.5) {
            claim_ratio(k, c, trials, 0.6, 0);
        }
        if (d->cov_n >= 50) {
            const double cv = (double)d->cov_in / (double)d->cov_n;
            const double se = sqrt(0.95 * 0.05 / (double)d->cov_n);
            const int ok = cv >= 0.92 - 2.0 * se && cv <= 0.98 + 2.0 * se;
            k->n++;
            k->fail += !ok;
            fprintf(k->f, "| %s | %g | %g | coverage of %s in 92-98 %% (+- 2 SE) | %ld | "
                          "%.3f +- %.3f | %s |\n",
                    cell_name(c, nm, sizeof nm), c->rom, c->sigma, k_ename[k->def], d->cov_n,
                    cv, se, ok ? "yes" : "**NO**");
        }
    } else {
        claim_ratio(k, c, trials, 1.1, 1);
        if (d->cov_n >= 50 && !c->wobble) { /* wobble is not noise: reported, not claimed */
            const double cv = (double)d->cov_in / (double)d->cov_n;
            const double se = sqrt(0.95 * 0.05 / (double)d->cov_n);
            const int ok = cv >= 0.92 - 2.0 * se && cv <= 0.98 + 2.0 * se;
            k->n++;
            k->fail += !ok;
            fprintf(k->f, "| %s | %g | %g | axis coverage of %s in 92-98 %% (+- 2 SE) | %ld | "
                          "%.3f +- %.3f | %s |\n",
                    cell_name(c, nm, sizeof nm), c->rom, c->sigma, k_ename[k->def], d->cov_n,
                    cv, se, ok ? "yes" : "**NO**");
        }
        k->n++;
        k->fail += g_big_unfl[ci] > 0;
        fprintf(k->f, "| %s | %g | %g | every %s result > 10 deg off flagged | %ld | %ld "
                      "unflagged > 10 deg | %s |\n",
                cell_name(c, nm, sizeof nm), c->rom, c->sigma, k_ename[k->def], d->ok,
                g_big_unfl[ci], g_big_unfl[ci] == 0 ? "yes" : "**NO**");
    }
}

/* ------------------------------------------------------------ tables */

/* One table cell: mean / p95, coverage among unflagged, flagged fraction. */
static void stat_cell(FILE *f, const stat_t *s)
{
    if (s->ok == 0) {
        fprintf(f, " - |");
        return;
    }
    fprintf(f, " %.3g / %.3g", s->mean, s->p95);
    if (s->cov_n > 0) {
        fprintf(f, " / %.0f %%", 100.0 * (double)s->cov_in / (double)s->cov_n);
    } else {
        fprintf(f, " / -");
    }
    fprintf(f, " / %.0f %% |", 100.0 * (double)s->flagged / (double)s->n);
}

static void table_ball(FILE *f, int sta)
{
    int ci, e;
    fprintf(f, "| parent | RoM (deg) | sigma (mm) |");
    for (e = 0; e < E_COUNT; e++) {
        fprintf(f, " %s |", k_ename[e]);
    }
    fprintf(f, "\n|---|---|---|");
    for (e = 0; e < E_COUNT; e++) {
        fprintf(f, "---|");
    }
    fprintf(f, "\n");
    for (ci = 0; ci < g_ncell; ci++) {
        const cell_t *c = &g_cells[ci];
        if (c->kind != K_BALL || c->sta != sta) {
            continue;
        }
        fprintf(f, "| %s | %g | %g |", c->still ? "still" : "moving", c->rom, c->sigma);
        for (e = 0; e < E_COUNT; e++) {
            const stat_t *s = &g_st[ci][e];
            stat_cell(f, s);
        }
        fprintf(f, "\n");
    }
}

static void table_hinge(FILE *f)
{
    int ci, e;
    fprintf(f, "| motion | flexion (deg) | sigma (mm) |");
    for (e = 0; e < E_COUNT; e++) {
        if (e != E_MGDK_SIG && e != E_SCORE_GLS) {
            fprintf(f, " %s |", e == E_SCORE ? "sara" : e == E_SCORE_EIV ? "sara_eiv"
                                                                          : k_ename[e]);
        }
    }
    fprintf(f, "\n|---|---|---|");
    for (e = 0; e < E_COUNT; e++) {
        if (e != E_MGDK_SIG && e != E_SCORE_GLS) {
            fprintf(f, "---|");
        }
    }
    fprintf(f, "\n");
    for (ci = 0; ci < g_ncell; ci++) {
        const cell_t *c = &g_cells[ci];
        if (c->kind != K_HINGE) {
            continue;
        }
        fprintf(f, "| %s | %g | %g |", c->wobble ? "wobble 2-5" : "pure", c->rom, c->sigma);
        for (e = 0; e < E_COUNT; e++) {
            const stat_t *s = &g_st[ci][e];
            if (e == E_MGDK_SIG || e == E_SCORE_GLS) {
                continue;
            }
            stat_cell(f, s);
        }
        fprintf(f, "\n");
    }
}

static void reasons_line(FILE *f, int ci)
{
    static const char *const nm[8] = {"none", "few frames", "small motion", "axis free",
                                      "ambiguous", "misfit", "no noise", "other"};
    int r, any = 0;
    for (r = 0; r < 8; r++) {
        if (g_reasons[ci][r] > 0) {
            fprintf(f, "%s%s %ld", any ? ", " : "", nm[r], g_reasons[ci][r]);
            any = 1;
        }
    }
    if (!any) {
        fprintf(f, "-");
    }
}

int main(int argc, char **argv)
{
    int check = 0, quick = 0, trials = 200, ci, e;
    FILE *fc, *ft, *fk;
    sfit_cluster_t cl_b, cl_k, clc_b, clc_k;
    claims_t k;
    if (argc < 2) {
        fprintf(stderr, "usage: sfit_mc_joint_bench OUTDIR [quick|check] [trials]\n");
        return 2;
    }
    if (argc > 2) {
        check = strcmp(argv[2], "check") == 0;
        quick = strcmp(argv[2], "quick") == 0;
        if (!check && !quick && strcmp(argv[2], "full") != 0) {
            fprintf(stderr, "sfit_mc_joint_bench: unknown argument %s\n", argv[2]);
            return 2;
        }
        if (check || quick) {
            trials = 100;
        }
    }
    if (argc > 3) {
        trials = atoi(argv[3]);
    }
    if (trials < 10 || trials > TMAX) {
        fprintf(stderr, "sfit_mc_joint_bench: trials must be 10..%d\n", TMAX);
        return 2;
    }
    seg_make(&g_par_b, k_pelvis, 4);
    seg_make(&g_chi_b, k_thigh_b, 5);
    seg_make(&g_par_k, k_thigh_k, 4);
    seg_make(&g_chi_k, k_shank, 4);
    {
        const double n = tu_norm3(k_knee_axis);
        int j;
        for (j = 0; j < 3; j++) {
            g_axis0[j] = k_knee_axis[j] / n;
        }
    }
    if (sfit_cluster_init(&cl_b, g_par_b.ftpl, 4) != SFIT_OK
        || sfit_cluster_init(&cl_k, g_par_k.ftpl, 4) != SFIT_OK
        || sfit_cluster_init(&clc_b, g_chi_b.ftpl, 5) != SFIT_OK
        || sfit_cluster_init(&clc_k, g_chi_k.ftpl, 4) != SFIT_OK) {
        return 1;
    }
    build_grid(check);
    fc = mc_out_open(argv[1], "joint_bench.csv");
    ft = mc_out_open(argv[1], "joint_bench_table.md");
    fk = mc_out_open(argv[1], "joint_bench_claims.md");
    if (fc == NULL || ft == NULL || fk == NULL) {
        return 1;
    }
    fprintf(fc, "kind,parent,sta,wobble,rom,sigma,method,trials,ok,flagged,mean,sd,p95,"
                "mean_unflagged,cov_n,coverage,planar,sigma_hat,bias,rep_mc_trace\n");
    memset(&k, 0, sizeof k);
    k.f = fk;
    k.def = E_SCORE_EIV;
    fprintf(fk, "| cell | RoM / flexion | sigma | claim | pairs / trials | measured | holds |\n"
                "|---|---|---|---|---|---|---|\n");
    for (ci = 0; ci < g_ncell; ci++) {
        const cell_t *c = &g_cells[ci];
        const seg_t *ps = (c->kind == K_BALL) ? &g_par_b : &g_par_k;
        const seg_t *cs = (c->kind == K_BALL) ? &g_chi_b : &g_chi_k;
        const sfit_cluster_t *cl = (c->kind == K_BALL) ? &cl_b : &cl_k;
        const sfit_cluster_t *clc = (c->kind == K_BALL) ? &clc_b : &clc_k;
        double shat = 0.0;
        tu_rng_t g;
        char nm[64];
        int t;
        tu_rng_seed(&g, UINT64_C(0x28BE4C0000000000) ^ ((uint64_t)c->kind << 40)
                            ^ ((uint64_t)c->still << 36) ^ ((uint64_t)c->sta << 35)
                            ^ ((uint64_t)c->wobble << 34) ^ ((uint64_t)(c->rom * 10.0) << 16)
                            ^ (uint64_t)(c->sigma * 100.0));
        for (t = 0; t < trials; t++) {
            make_trial(c, &g, ps, cs);
            register_double(ps, cs);
            shat += sqrt(g_sig2_hat) / trials;
            run_mgdk(c, cl, ps, cs, 0, 0.0, &g_res[E_MGDK][t]);
            run_mgdk(c, cl, ps, cs, 1, c->sigma * c->sigma, &g_res[E_MGDK_SIG][t]);
            run_mgdk(c, cl, ps, cs, 1, g_sig2_hat, &g_res[E_MGDK_EST][t]);
            run_score(c, ps, cs, 0, &g_res[E_SCORE][t]);
            run_score(c, ps, cs, 1, &g_res[E_SCORE_EIV][t]);
            run_score_gls(c, ps, cs, &g_res[E_SCORE_GLS][t]);
#ifdef SFIT_MC_HAVE_PAIR
            {
                /* a knee is fitted as a hinge (`--mode hinge`, as MGDK is run planar);
                 * pair_auto: the default with the mode decided from the data */
                const sfit_pair_mode_t md =
                    (c->kind == K_BALL) ? SFIT_PAIR_MODE_AUTO : SFIT_PAIR_MODE_HINGE;
                run_pair(c, cl, clc, ps, cs, SFIT_PAIR_METHOD_DEFAULT, md, &g_res[E_PAIR_DEF][t]);
                run_pair(c, cl, clc, ps, cs, SFIT_PAIR_METHOD_SCORE, md, &g_res[E_PAIR_SCORE][t]);
                if (c->kind == K_HINGE) {
                    run_pair(c, cl, clc, ps, cs, SFIT_PAIR_METHOD_DEFAULT, SFIT_PAIR_MODE_AUTO,
                             &g_res[E_PAIR_AUTO][t]);
                } else {
                    g_res[E_PAIR_AUTO][t] = g_res[E_PAIR_DEF][t];
                }
            }
#else
            (void)clc;
#endif
        }
#ifdef SFIT_MC_HAVE_PAIR
        if (g_pair_ok) {
            k.def = E_PAIR_DEF;
        }
#endif
        cell_name(c, nm, sizeof nm);
        for (e = 0; e < E_COUNT; e++) {
            stat_t *s = &g_st[ci][e];
            stats(g_res[e], trials, s);
            fprintf(fc, "%s,%s,%d,%d,%g,%g,%s,%ld,%ld,%ld,%.5g,%.5g,%.5g,%.5g,%ld,%.4f,%ld,%.4g,%.4g,"
                        "%.4g\n",
                    c->kind == K_BALL ? "ball" : "hinge", c->still ? "still" : "moving", c->sta,
                    c->wobble, c->rom, c->sigma, k_ename[e], s->n, s->ok, s->flagged, s->mean,
                    s->sd, s->p95, s->mean_unfl, s->cov_n,
                    s->cov_n > 0 ? (double)s->cov_in / (double)s->cov_n : -1.0, s->planar, shat,
                    s->bias, s->trratio);
        }
        for (t = 0; t < trials; t++) {
            const res_t *r = &g_res[k.def][t];
            if (r->ok && !r->flagged && c->kind == K_HINGE && r->err > 10.0) {
                g_big_unfl[ci]++;
            }
            if (r->ok && r->flagged) {
                g_reasons[ci][(r->reason >= 0 && r->reason < 7) ? r->reason : 7]++;
            }
        }
        claims_cell(&k, c, ci, trials);
        fflush(fc);
        fflush(fk);
        fprintf(stderr, "%s rom %g sigma %g done\n", nm, c->rom, c->sigma);
    }
    fprintf(fk, "\nThe default checked: %s. %d of %d claims hold (%d known not to).\n",
            k_ename[k.def], k.n - k.fail - k.known, k.n, k.known);
    fprintf(ft, "Each entry: mean / 95th percentile of the error (centre: mm; axis: degrees) / "
                "coverage of the reported 95 %% region among unflagged results / flagged "
                "fraction. %d trials per cell.\n\n### Ball joint, marker noise only\n\n",
            trials);
    table_ball(ft, 0);
    fprintf(ft, "\n### Ball joint with the soft-tissue artefact (sigma 0.5 mm)\n\n");
    table_ball(ft, 1);
    fprintf(ft, "\nFlag reasons of %s (soft-tissue cells):\n\n", k_ename[k.def]);
    for (ci = 0; ci < g_ncell; ci++) {
        if (g_cells[ci].sta) {
            fprintf(ft, "- RoM %g: ", g_cells[ci].rom);
            reasons_line(ft, ci);
            fprintf(ft, "\n");
        }
    }
    fprintf(ft, "\nFlag reasons of %s in every cell (flagged results by main reason):\n\n",
            k_ename[k.def]);
    for (ci = 0; ci < g_ncell; ci++) {
        char nm[64];
        fprintf(ft, "- %s, %g deg, sigma %g: ", cell_name(&g_cells[ci], nm, sizeof nm),
                g_cells[ci].rom, g_cells[ci].sigma);
        reasons_line(ft, ci);
        fprintf(ft, "\n");
    }
    fprintf(ft, "\n### Hinge (axis error, degrees)\n\n");
    table_hinge(ft);
    fprintf(ft, "\nResults of %s more than 10 degrees off and not flagged:", k_ename[k.def]);
    for (ci = 0; ci < g_ncell; ci++) {
        if (g_cells[ci].kind == K_HINGE) {
            fprintf(ft, " %ld", g_big_unfl[ci]);
        }
    }
    fprintf(ft, " (hinge cells in table order).\n");
    fclose(fc);
    fclose(ft);
    fclose(fk);
    fprintf(stderr, "joint_bench: default %s, %d of %d claims hold, %d known not to, %d fail\n",
            k_ename[k.def], k.n - k.fail - k.known, k.n, k.known, k.fail);
#ifdef SFIT_MC_HAVE_PAIR
    if (check && !g_pair_ok) {
        fprintf(stderr, "joint_bench: the pair module is not built (SFIT_E_UNSUPPORTED)\n");
        return 1;
    }
#endif
    return (check && k.fail > 0) ? 1 : 0;
}
