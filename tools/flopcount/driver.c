/* SPDX-License-Identifier: MIT */
/**
 * @file driver.c
 * @brief FLOP-count driver: runs every public operation of sfit once, on
 * fixed deterministic data, between two marker calls, on the emulated
 * Cortex-M4F. tools/flopcount/count.sh logs every executed instruction
 * (QEMU, one instruction per translation block) and counts, between
 * fc_begin() and fc_end(), the instructions that are NOT in this file
 * (every function here is named fc_* or is main), i.e. the library's own
 * code and the C-library routines it calls (memset, ...).
 *
 * Built with -std=c99: no a*b+c contraction, so every float operation of
 * the C source is one VFP instruction (vadd/vsub/vmul/vdiv/vsqrt.f32).
 *
 * Output (semihosting stdout), read by count.sh:
 *   fcop NAME DIV NMEAS FN  before the NMEAS (1 or 2) measured intervals of
 *                           operation NAME (public function FN); its
 *                           figure is (interval1 - interval2) / DIV
 *   fcinfo KEY VALUE        facts about the build (block size, ...)
 *   fcfail NAME STATUS      an operation did not return SFIT_OK
 *   fcdone FAILS
 * Exit status: number of failed operations.
 *
 * Adding an operation = one row of fc_ops[] (name, set-up, measured
 * function, optional baseline, divisor) plus the small fc_* functions it
 * names. Data: samples on a 45-degree cap / 90-degree arc of radius
 * 100 mm around a centre 2.7 m from the origin (the motion-capture case,
 * DESIGN.md section 2), Gaussian-like noise sigma = 0.5 mm, from a fixed
 * LCG: identical on every run.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit/sfit_fit.h"
#include "sfit/sfit_mat3.h"
#include "sfit/sfit_moments.h"

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_incr.h"
#include "sfit/sfit_joint.h"
#include "sfit/sfit_pair.h"
#include "sfit/sfit_imu.h"
#include "sfit/sfit_multi.h"
#include "sfit/sfit_noise.h"

#define FC_NPTS 512u               /* samples of the main data set */
#define FC_NHALF (FC_NPTS / 2u)    /* the smaller batch */
#define FC_NMARK 8u                /* markers of the multi-marker probe */
#define FC_NPERMARK 64u            /* samples per marker */
#if SFIT_SUM_BLOCK > FC_NHALF
#error "flopcount: SFIT_SUM_BLOCK larger than the probe size; raise FC_NPTS"
#endif
/* Amortised moments add: a whole number of blocks. */
#define FC_NAMORT ((FC_NPTS / SFIT_SUM_BLOCK) * SFIT_SUM_BLOCK)

typedef void (*fc_fn_t)(void);

/** One operation: figure = (F(run) - F(base)) / div, F = counts inside
 *  the library during the call. prep runs (unmeasured) before run, and
 *  prep_base before base. */
typedef struct fc_op {
    const char *name;
    const char *fn; /* public function whose stack the report shows */
    fc_fn_t prep;
    fc_fn_t run;
    fc_fn_t prep_base;
    fc_fn_t base;
    unsigned div;
} fc_op_t;

int main(void);
void fc_begin(void);
void fc_end(void);

static const float fc_centre[3] = {1500.0f, -2000.0f, 1000.0f}; /* |c| = 2693 mm */
static const float fc_radius = 100.0f;
static const float fc_sigma = 0.5f;

static uint32_t fc_rng = 12345u;
static sfit_vec3_t fc_pts[FC_NPTS];      /* 45-degree cap */
static sfit_vec3_t fc_arc[FC_NHALF];     /* 90-degree arc (hinge) */
static sfit_moments_t fc_acc;            /* scratch accumulator */
static sfit_moments_t fc_mom_cap;        /* moments of fc_pts */
static sfit_moments_t fc_mom_arc;        /* moments of fc_arc */
static sfit_mat3_t fc_c;                 /* covariance of the cap */
static sfit_vec3_t fc_b;                 /* S/2 of the cap */
static sfit_mat3_t fc_rot;               /* one-rotation matrix */
static sfit_mat3_t fc_l;
static sfit_mat3_t fc_v;
static sfit_vec3_t fc_x;
static sfit_vec3_t fc_w;
static sfit_result_t fc_res;
static sfit_fit_cfg_t fc_cfg_ugdk;
static sfit_fit_cfg_t fc_cfg_planar;
static sfit_fit_cfg_t fc_cfg_gdke_eig; /* cfg.eigen true: the full solver */
static sfit_fit_cfg_t fc_cfg_ugdk_eig;
static sfit_status_t fc_st;
static sfit_selfcal_result_t fc_sc;      /* self-calibrated fit of fc_pts */
static sfit_uncert_t fc_unc;
static sfit_moments_t fc_mk[FC_NMARK];
static sfit_multi_result_t fc_mres;
static float fc_radii[FC_NMARK];
static sfit_noise_est_t fc_nest;
/* Joint probe: a 4-marker parent cluster (pelvis-like, +-75 mm) and 5
 * child markers turning about a centre, 2.7 m from the origin; FC_NJF
 * frames (a whole number of moments blocks, so the amortised figure
 * includes the block merges). */
#define FC_NJP 4u
#define FC_NJC 5u
#define FC_NJF SFIT_SUM_BLOCK
static sfit_cluster_t fc_cl;
static sfit_joint_t fc_jnt;
static sfit_joint_result_t fc_jres;
static sfit_pose_t fc_pose;
static sfit_cluster_fit_t fc_cfit;
static sfit_vec3_t fc_jpar[FC_NJF][FC_NJP];
static sfit_vec3_t fc_jchi[FC_NJF][FC_NJC];
/* Tracking probe: the parent cluster on two consecutive frames at 200 Hz,
 * turning at 200 degrees/s (1 degree between the frames). */
static sfit_vec3_t fc_jtrk[2][FC_NJP];
static sfit_cluster_track_t fc_trk;
static sfit_joint_cfg_t fc_jcfg5;
static sfit_joint_cfg_t fc_jcfg1;
static sfit_joint_cfg_t fc_jcfgm;
static sfit_incr_t fc_inc;
static sfit_sphere_t fc_iest;

/* ---- markers: the counting window is between these two calls ---------- */
__attribute__((noinline)) void fc_begin(void)
{
    __asm__ volatile("" ::: "memory");
}

__attribute__((noinline)) void fc_end(void)
{
    __asm__ volatile("" ::: "memory");
}

/* ---- deterministic data --------------------------------------------------- */
static float fc_unif(void) /* [0, 1) */
{
    fc_rng = fc_rng * 1664525u + 1013904223u;
    return (float)(fc_rng >> 8) * (1.0f / 16777216.0f);
}

static float fc_noise(void) /* Irwin-Hall(12) - 6: mean 0, variance 1 */
{
    float s = 0.0f;
    int i;
    for (i = 0; i < 12; i++) {
        s += fc_unif();
    }
    return s - 6.0f;
}

/* Uniform direction within `cosmax` of +z (cap) or, planar != 0, within
 * `cosmax` of +x in the z = 0 plane (arc); rejection sampling. */
static void fc_dir(float d[3], float cosmax, int planar)
{
    int tries;
    for (tries = 0; tries < 10000; tries++) {
        float u = 2.0f * fc_unif() - 1.0f;
        float v = 2.0f * fc_unif() - 1.0f;
        float w = planar ? 0.0f : 2.0f * fc_unif() - 1.0f;
        float q = u * u + v * v + w * w;
        float k;
        if (q > 1.0f || q < 1e-4f) {
            continue;
        }
        k = 1.0f / __builtin_sqrtf(q);
        d[0] = u * k;
        d[1] = v * k;
        d[2] = w * k;
        if ((planar ? d[0] : d[2]) >= cosmax) {
            return;
        }
    }
    d[0] = planar ? 1.0f : 0.0f;
    d[1] = 0.0f;
    d[2] = planar ? 0.0f : 1.0f;
}

static void fc_sample(sfit_vec3_t *p, unsigned n, float cosmax, int planar, const float c[3],
                      float r)
{
    unsigned i;
    int k;
    for (i = 0; i < n; i++) {
        float d[3];
        fc_dir(d, cosmax, planar);
        for (k = 0; k < 3; k++) {
            p[i].v[k] = c[k] + r * d[k] + fc_sigma * fc_noise();
        }
    }
}

static void fc_moments_of(sfit_moments_t *m, const sfit_vec3_t *p, unsigned n)
{
    (void)sfit_moments_init(m);
    (void)sfit_moments_add_block(m, p, n, NULL);
}

static void fc_setup(void)
{
    sfit_vec3_t s;
    static const float cos45 = 0.70710678f;
    fc_sample(fc_pts, FC_NPTS, cos45, 0, fc_centre, fc_radius);
    fc_sample(fc_arc, FC_NHALF, cos45, 1, fc_centre, fc_radius);
    fc_moments_of(&fc_mom_cap, fc_pts, FC_NPTS);
    fc_moments_of(&fc_mom_arc, fc_arc, FC_NHALF);
    (void)sfit_moments_stats(&fc_mom_cap, NULL, &fc_c, &s);
    fc_b.v[0] = 0.5f * s.v[0];
    fc_b.v[1] = 0.5f * s.v[1];
    fc_b.v[2] = 0.5f * s.v[2];
    memset(&fc_rot, 0, sizeof fc_rot);
    fc_rot.m[0] = 2.0f;
    fc_rot.m[1] = 1.0f;
    fc_rot.m[3] = 1.0f;
    fc_rot.m[4] = 3.0f;
    fc_rot.m[8] = 5.0f;
    fc_cfg_ugdk = sfit_fit_cfg_default;
    fc_cfg_ugdk.noise = SFIT_NOISE_ISO;
    fc_cfg_ugdk.noise_var = fc_sigma * fc_sigma;
    fc_cfg_planar = sfit_fit_cfg_default;
    fc_cfg_planar.mode = SFIT_MODE_PLANAR;
    fc_cfg_gdke_eig = sfit_fit_cfg_default;
    fc_cfg_gdke_eig.eigen = true;
    fc_cfg_ugdk_eig = fc_cfg_ugdk;
    fc_cfg_ugdk_eig.eigen = true;
    {
        unsigned p;
        for (p = 0; p < FC_NMARK; p++) {
            sfit_vec3_t tmp[FC_NPERMARK];
            fc_sample(tmp, FC_NPERMARK, cos45, 0, fc_centre, 80.0f + 10.0f * (float)p);
            fc_moments_of(&fc_mk[p], tmp, FC_NPERMARK);
        }
    }
}

/* Rotation about a unit axis u by an angle with cosine c and sine s. */
static void fc_rot_axis(const float u[3], float c, float s, float r[9])
{
    const float t = 1.0f - c;
    r[0] = c + u[0] * u[0] * t;
    r[1] = u[0] * u[1] * t - u[2] * s;
    r[2] = u[0] * u[2] * t + u[1] * s;
    r[3] = u[1] * u[0] * t + u[2] * s;
    r[4] = c + u[1] * u[1] * t;
    r[5] = u[1] * u[2] * t - u[0] * s;
    r[6] = u[2] * u[0] * t - u[1] * s;
    r[7] = u[2] * u[1] * t + u[0] * s;
    r[8] = c + u[2] * u[2] * t;
}

static void fc_apply(const float r[9], const float x[3], const float t[3], float y[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        y[k] = r[3 * k] * x[0] + r[3 * k + 1] * x[1] + r[3 * k + 2] * x[2] + t[k];
    }
}

static void fc_setup_joint(void)
{
    static const float tpl[FC_NJP][3] = {
        {70.0f, 40.0f, 10.0f}, {-75.0f, 35.0f, 5.0f}, {-60.0f, -50.0f, 30.0f}, {65.0f, -25.0f, -45.0f}};
    static const float dk[FC_NJC][3] = {{30.0f, -20.0f, -150.0f}, {-35.0f, 25.0f, -220.0f},
                                        {40.0f, 30.0f, -300.0f}, {-20.0f, -45.0f, -380.0f},
                                        {45.0f, -10.0f, -420.0f}};
    static const float jc[3] = {-80.0f, 90.0f, -70.0f};
    sfit_vec3_t tv[FC_NJP];
    float rq[9];
    unsigned f, i;
    int k;
    for (i = 0; i < FC_NJP; i++) {
        for (k = 0; k < 3; k++) {
            tv[i].v[k] = tpl[i][k];
        }
    }
    if (sfit_cluster_init(&fc_cl, tv, FC_NJP) != SFIT_OK) {
        fc_st = SFIT_E_ARG;
    }
    for (f = 0; f < FC_NJF; f++) {
        float u[3], rp[9], c, s, y[3];
        fc_dir(u, -1.0f, 0);
        c = 2.0f * fc_unif() - 1.0f;
        s = __builtin_sqrtf(1.0f - c * c);
        fc_rot_axis(u, c, s, rp);
        fc_dir(u, -1.0f, 0);
        c = 0.5f + 0.5f * fc_unif(); /* up to 60 degrees */
        s = __builtin_sqrtf(1.0f - c * c);
        fc_rot_axis(u, c, s, rq);
        for (i = 0; i < FC_NJP; i++) {
            fc_apply(rp, tpl[i], fc_centre, fc_jpar[f][i].v);
            for (k = 0; k < 3; k++) {
                fc_jpar[f][i].v[k] += fc_sigma * fc_noise();
            }
        }
        for (i = 0; i < FC_NJC; i++) {
            fc_apply(rq, dk[i], jc, y);
            fc_apply(rp, y, fc_centre, fc_jchi[f][i].v);
            for (k = 0; k < 3; k++) {
                fc_jchi[f][i].v[k] += fc_sigma * fc_noise();
            }
        }
    }
    {
        float u[3], r0[9], r1[9], c, s;
        static const float deg1c = 0.99984770f, deg1s = 0.017452406f;
        unsigned a, b;
        fc_dir(u, -1.0f, 0);
        c = 2.0f * fc_unif() - 1.0f;
        s = __builtin_sqrtf(1.0f - c * c);
        fc_rot_axis(u, c, s, r0);
        fc_dir(u, -1.0f, 0);
        fc_rot_axis(u, deg1c, deg1s, rq);
        for (a = 0; a < 3u; a++) {
            for (b = 0; b < 3u; b++) {
                r1[3u * a + b] = rq[3u * a] * r0[b] + rq[3u * a + 1u] * r0[3u + b] + rq[3u * a + 2u] * r0[6u + b];
            }
        }
        for (i = 0; i < FC_NJP; i++) {
            fc_apply(r0, tpl[i], fc_centre, fc_jtrk[0][i].v);
            fc_apply(r1, tpl[i], fc_centre, fc_jtrk[1][i].v);
            for (k = 0; k < 3; k++) {
                fc_jtrk[0][i].v[k] += fc_sigma * fc_noise();
                fc_jtrk[1][i].v[k] += fc_sigma * fc_noise();
            }
        }
    }
    fc_jcfg5 = sfit_joint_cfg_default;
    fc_jcfg5.n_child = FC_NJC;
    fc_jcfg1 = sfit_joint_cfg_default;
    fc_jcfg1.n_child = 1u;
    fc_jcfgm = fc_jcfg5;
    fc_jcfgm.noise_model = SFIT_JOINT_NOISE_MARKER;
    fc_jcfgm.solve.fit.noise = SFIT_NOISE_ISO;
    fc_jcfgm.solve.fit.noise_var = fc_sigma * fc_sigma;
}

/* ---- operations ----------------------------------------------------------- */
static void fc_keep(sfit_status_t st)
{
    if (st != SFIT_OK) {
        fc_st = st;
    }
}

static void fc_prep_empty(void)
{
    (void)sfit_moments_init(&fc_acc);
}

static void fc_add_amortised(void)
{
    unsigned i;
    for (i = 0; i < FC_NAMORT; i++) {
        fc_keep(sfit_moments_add(&fc_acc, &fc_pts[i]));
    }
}

static void fc_prep_mid_block(void) /* one full block merged, 3 samples open */
{
    fc_moments_of(&fc_acc, fc_pts, SFIT_SUM_BLOCK + 3u);
}

static void fc_prep_block_end(void) /* the next add closes the second block */
{
    fc_moments_of(&fc_acc, fc_pts, 2u * SFIT_SUM_BLOCK - 1u);
}

static void fc_add_one(void)
{
    fc_keep(sfit_moments_add(&fc_acc, &fc_pts[FC_NPTS - 1u]));
}

/* The batch entry: the same FC_NAMORT samples in one call. */
static void fc_add_batch(void)
{
    fc_keep(sfit_moments_add_block(&fc_acc, fc_pts, FC_NAMORT, NULL));
}

/* N = 500 samples: not a whole number of blocks (the open block holds
 * 500 mod SFIT_SUM_BLOCK samples at the solve). */
#define FC_N500 500u
static void fc_prep_500(void)
{
    fc_moments_of(&fc_acc, fc_pts, FC_N500);
}

static void fc_solve_gdke_500(void)
{
    fc_keep(sfit_fit_moments(&fc_acc, NULL, &fc_res));
    fc_keep((!fc_res.exact) ? SFIT_OK : SFIT_E_RANGE);
}

static void fc_batch_n(void)
{
    fc_keep(sfit_fit_points(fc_pts, FC_NPTS, NULL, &fc_res));
}

static void fc_batch_half(void)
{
    fc_keep(sfit_fit_points(fc_pts, FC_NHALF, NULL, &fc_res));
}

static void fc_prep_selfcal(void)
{
    fc_keep(sfit_selfcal_points(fc_pts, FC_NPTS, NULL, &fc_sc));
}

static void fc_uncert_selfcal_n(void)
{
    fc_keep(sfit_uncert_selfcal(fc_pts, FC_NPTS, &fc_sc.fit.center, fc_sc.fit.radius,
                                fc_sc.noise_var, &fc_unc));
}

static void fc_uncert_selfcal_half(void)
{
    fc_keep(sfit_uncert_selfcal(fc_pts, FC_NHALF, &fc_sc.fit.center, fc_sc.fit.radius,
                                fc_sc.noise_var, &fc_unc));
}

/* The default solve must take the screened path on the cap. */
static void fc_solve_gdke(void)
{
    fc_keep(sfit_fit_moments(&fc_mom_cap, NULL, &fc_res));
    fc_keep((!fc_res.exact) ? SFIT_OK : SFIT_E_RANGE);
}

static void fc_solve_ugdk(void)
{
    fc_keep(sfit_fit_moments(&fc_mom_cap, &fc_cfg_ugdk, &fc_res));
    fc_keep((!fc_res.exact) ? SFIT_OK : SFIT_E_RANGE);
}

static void fc_solve_gdke_eigen(void)
{
    fc_keep(sfit_fit_moments(&fc_mom_cap, &fc_cfg_gdke_eig, &fc_res));
}

/* The default fit by the plain solver alone (the minimal application's). */
static void fc_solve_default(void)
{
    fc_keep(sfit_fit_moments_default(&fc_mom_cap, &fc_res));
    fc_keep(fc_res.exact ? SFIT_OK : SFIT_E_RANGE);
}

static void fc_solve_ugdk_eigen(void)
{
    fc_keep(sfit_fit_moments(&fc_mom_cap, &fc_cfg_ugdk_eig, &fc_res));
}

static void fc_solve_planar(void)
{
    fc_keep(sfit_fit_moments(&fc_mom_arc, &fc_cfg_planar, &fc_res));
}

static void fc_chol(void)
{
    fc_keep(sfit_mat3_chol(&fc_c, &fc_l));
}

static void fc_subst(void)
{
    fc_keep(sfit_mat3_chol_solve(&fc_l, &fc_b, &fc_x));
}

static void fc_chol_and_subst(void)
{
    fc_chol();
    fc_subst();
}

static void fc_eig(void)
{
    fc_keep(sfit_mat3_eig_sym(&fc_c, &fc_w, &fc_v));
}

static void fc_eig_rot(void)
{
    fc_keep(sfit_mat3_eig_sym(&fc_rot, &fc_w, &fc_v));
}

static void fc_stats(void)
{
    fc_keep(sfit_moments_stats(&fc_mom_cap, &fc_x, &fc_l, &fc_w));
}

static void fc_multi_all(void)
{
    fc_keep(sfit_multi_fit(fc_mk, FC_NMARK, NULL, &fc_mres, fc_radii));
}

static void fc_multi_noise(void)
{
    static sfit_multi_noise_t nz[FC_NMARK];
    unsigned p;
    for (p = 0; p < FC_NMARK; p++) {
        nz[p].cov.m[0] = nz[p].cov.m[4] = nz[p].cov.m[8] = 0.25f;
        nz[p].skew.v[2] = 1.0f;
    }
    fc_keep(sfit_multi_fit_noise(fc_mk, FC_NMARK, NULL, nz, &fc_mres, fc_radii));
}

static void fc_multi_cov(void)
{
    sfit_mat3_t cov;
    fc_keep(sfit_multi_center_cov(fc_mk, FC_NMARK, NULL, &fc_mres, fc_sigma * fc_sigma, &cov));
}

static void fc_multi_half(void)
{
    fc_keep(sfit_multi_fit(fc_mk, FC_NMARK / 2u, NULL, &fc_mres, fc_radii));
}

static void fc_noise_calib(void)
{
    sfit_vec3_t c0;
    c0.v[0] = fc_centre[0];
    c0.v[1] = fc_centre[1];
    c0.v[2] = fc_centre[2];
    fc_keep(sfit_noise_calibrate(&fc_mom_cap, &c0, fc_radius, &fc_nest));
}

/* State after a batch start on FC_NHALF samples: the next call is an
 * ordinary one (no fold; folds come at n = 1, 2, 4, ... and then every
 * SFIT_INCR_BLOCK samples: moments_add-like amortisation, see docs/cost.md). */
static void fc_prep_incr(const sfit_fit_cfg_t *cfg)
{
    sfit_incr_cfg_t ic = sfit_incr_cfg_default;
    if (cfg != NULL) {
        ic.noise = cfg->noise;
        ic.noise_var = cfg->noise_var;
        ic.noise_cov = cfg->noise_cov;
    }
    (void)sfit_incr_init(&fc_inc, &ic);
    fc_keep(sfit_incr_start(&fc_inc, fc_pts, FC_NHALF, NULL));
}

static void fc_prep_incr_gdke(void)
{
    fc_prep_incr(NULL);
}

static void fc_prep_incr_ugdk(void)
{
    fc_prep_incr(&fc_cfg_ugdk);
}

static void fc_incr_update(void)
{
    fc_keep(sfit_incr_update(&fc_inc, &fc_pts[FC_NPTS - 1u], &fc_iest));
}

static void fc_incr_add(void)
{
    fc_keep(sfit_incr_add(&fc_inc, &fc_pts[FC_NPTS - 1u]));
}

static void fc_incr_solve(void)
{
    fc_keep(sfit_incr_fit(&fc_inc, &fc_iest));
}

static void fc_incr_updates(void) /* FC_NHALF more samples, an estimate after each */
{
    unsigned i;
    for (i = FC_NHALF; i < FC_NPTS; i++) {
        fc_keep(sfit_incr_update(&fc_inc, &fc_pts[i], &fc_iest));
    }
}

static void fc_register(void)
{
    fc_keep(sfit_cluster_register(&fc_cl, fc_jpar[0], FC_NJP, &fc_pose, &fc_cfit));
}

static void fc_prep_track(void) /* the first frame: the full solve */
{
    fc_keep(sfit_cluster_track_reset(&fc_trk));
    fc_keep(sfit_cluster_track(&fc_cl, &fc_trk, fc_jtrk[0], FC_NJP, &fc_pose, &fc_cfit));
}

static void fc_track(void) /* the next frame, from the previous rotation */
{
    fc_keep(sfit_cluster_track(&fc_cl, &fc_trk, fc_jtrk[1], FC_NJP, &fc_pose, &fc_cfit));
    fc_keep((fc_trk.steps > 0u) ? SFIT_OK : SFIT_E_NO_CONVERGENCE);
}

static void fc_track_pose(void) /* the same, pose only (no residual) */
{
    fc_keep(sfit_cluster_track(&fc_cl, &fc_trk, fc_jtrk[1], FC_NJP, &fc_pose, NULL));
}

static void fc_track_first(void)
{
    fc_keep(sfit_cluster_track_reset(&fc_trk));
    fc_keep(sfit_cluster_track(&fc_cl, &fc_trk, fc_jtrk[0], FC_NJP, &fc_pose, &fc_cfit));
}

static void fc_to_segment(void)
{
    fc_keep(sfit_cluster_to_segment(&fc_pose, &fc_jchi[0][0], &fc_x));
}

static void fc_prep_joint5(void)
{
    fc_keep(sfit_joint_init(&fc_jnt, &fc_cl, &fc_jcfg5));
}

static void fc_prep_joint1(void)
{
    fc_keep(sfit_joint_init(&fc_jnt, &fc_cl, &fc_jcfg1));
}

static void fc_joint_frames(void) /* FC_NJF frames */
{
    unsigned f;
    for (f = 0; f < FC_NJF; f++) {
        fc_keep(sfit_joint_add(&fc_jnt, fc_jpar[f], FC_NJP, fc_jchi[f], fc_jnt.cfg.n_child, NULL));
    }
}

static void fc_prep_joint5_full(void)
{
    fc_prep_joint5();
    fc_joint_frames();
}

static void fc_joint_solve(void)
{
    fc_keep(sfit_joint_fit(&fc_jnt, &fc_jres, NULL));
}

static void fc_joint_center_at(void)
{
    sfit_vec3_t c;
    fc_keep(sfit_joint_center_at(&fc_jnt, &fc_jres, fc_jpar[1], FC_NJP, &c, NULL));
}

static void fc_prep_joint5_marker(void) /* SFIT_JOINT_NOISE_MARKER, FC_NJF frames */
{
    fc_keep(sfit_joint_init(&fc_jnt, &fc_cl, &fc_jcfgm));
    fc_joint_frames();
}

static void fc_joint_center_cov(void) /* FC_NJF frames */
{
    sfit_mat3_t cov;
    fc_keep(sfit_joint_center_cov(&fc_jnt, &fc_jres, &fc_jpar[0][0], &fc_jchi[0][0], FC_NJF,
                                  fc_sigma * fc_sigma, &cov));
}

static void fc_prep_joint_marker_solved(void)
{
    fc_prep_joint5_marker();
    fc_joint_solve();
}

static void fc_prep_joint_solved(void)
{
    fc_prep_joint5_full();
    fc_joint_solve();
}

/* ---- pair of segments (sfit_pair.h): the joint's frames, the 5 child
 * markers as a rigid child cluster; poses registered in the set-up. ---- */
static sfit_cluster_t fc_ccl;
static sfit_pose_t fc_ppose[FC_NJF], fc_cpose[FC_NJF];
static sfit_cluster_fit_t fc_pfit[FC_NJF], fc_qfit[FC_NJF];
static sfit_pair_t fc_pair;
static sfit_pair_result_t fc_pres;

static void fc_setup_pair(void)
{
    static const float dk[FC_NJC][3] = {{30.0f, -20.0f, -150.0f}, {-35.0f, 25.0f, -220.0f},
                                        {40.0f, 30.0f, -300.0f}, {-20.0f, -45.0f, -380.0f},
                                        {45.0f, -10.0f, -420.0f}};
    sfit_vec3_t tv[FC_NJC];
    unsigned f, i;
    int k;
    for (i = 0; i < FC_NJC; i++) {
        for (k = 0; k < 3; k++) {
            tv[i].v[k] = dk[i][k];
        }
    }
    fc_keep(sfit_cluster_init(&fc_ccl, tv, FC_NJC));
    for (f = 0; f < FC_NJF; f++) {
        fc_keep(sfit_cluster_register(&fc_cl, fc_jpar[f], FC_NJP, &fc_ppose[f], &fc_pfit[f]));
        fc_keep(sfit_cluster_register(&fc_ccl, fc_jchi[f], FC_NJC, &fc_cpose[f], &fc_qfit[f]));
    }
}

static void fc_prep_pair(void)
{
    fc_keep(sfit_pair_init(&fc_pair, &fc_cl, &fc_ccl, NULL));
}

static void fc_prep_pair_score(void)
{
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    cfg.method = SFIT_PAIR_METHOD_SCORE;
    fc_keep(sfit_pair_init(&fc_pair, &fc_cl, &fc_ccl, &cfg));
}

static void fc_pair_frames(void) /* FC_NJF frames */
{
    unsigned f;
    for (f = 0; f < FC_NJF; f++) {
        fc_keep(sfit_pair_add(&fc_pair, &fc_ppose[f], &fc_pfit[f], &fc_cpose[f], &fc_qfit[f]));
    }
}

static void fc_pair_frames_markers(void) /* FC_NJF frames */
{
    unsigned f;
    for (f = 0; f < FC_NJF; f++) {
        fc_keep(sfit_pair_add_markers(&fc_pair, &fc_cl, fc_jpar[f], FC_NJP, &fc_ccl, fc_jchi[f],
                                      FC_NJC));
    }
}

static void fc_prep_pair_full(void)
{
    fc_prep_pair();
    fc_pair_frames();
}

static void fc_prep_pair_full_score(void)
{
    fc_prep_pair_score();
    fc_pair_frames();
}

static void fc_pair_solve(void)
{
    fc_keep(sfit_pair_solve(&fc_pair, &fc_pres));
}

/* ---- the joint between two IMUs (sfit_imu.h): exact signals of a ball
 * joint, 200 Hz, generated in the driver (outside the counts). The parent
 * yaws, pitches and rolls, R1 = Rz Ry Rx; the child swings about two axes
 * on it, R2 = R1 Ry Rx; every angle a harmonic of one table period, so
 * the table holds one period of every signal and repeats seamlessly. The
 * motion determines both joint positions and the relative rotation: the
 * solve returns an unflagged ball with r1, r2 as generated and runs every
 * pass (the fixed axis's three included). imu_add: per sample in the
 * steady state (amortised over FC_NIMU samples, compactions included);
 * imu_add_compact: the sample whose window fills the buffer; imu_solve: the
 * solve of a full buffer (SFIT_IMU_KEEP kept samples). ---- */
#define FC_NIMU 256u
#define FC_IMU_TAB 512u /* one period of every signal: 2.56 s */
static sfit_imu_sample_t fc_itab[FC_IMU_TAB];
static sfit_imu_t fc_imu;
static sfit_imu_result_t fc_ires;
static unsigned fc_ik;

static void fc_cross(const float a[3], const float b[3], float c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* G r = w x (w x r) + w' x r */
static void fc_g(const float w[3], const float d[3], const float r[3], float o[3])
{
    float x[3], y[3], z[3];
    int k;
    fc_cross(w, r, x);
    fc_cross(w, x, y);
    fc_cross(d, r, z);
    for (k = 0; k < 3; k++) {
        o[k] = y[k] + z[k];
    }
}

/* One more turn of a frame about its own axis ax (0, 1, 2 = x, y, z) by
 * the angle amp sin(m w0 t + ph), w0 = 2 pi / 2.56 s (one table period):
 * the new frame F' = F R(th). Its rate and angular acceleration, each in
 * its own frame: w' = R^T w + th' e, w'' = R^T w' + (R^T w) x th' e + th'' e
 * (e the axis, R's derivative R [th' e]x); f, a vector of the old frame,
 * into the new one. */
static void fc_turn(int ax, float amp, float m, float ph, float t, float w[3], float d[3],
                    float f[3])
{
    const float om = m * 2.4543693f, x = om * t + ph, th = amp * sinf(x);
    const float th1 = amp * om * cosf(x), th2 = -om * om * th, c = cosf(th), s = sinf(th);
    const int i = (ax + 1) % 3, j = (ax + 2) % 3;
    float *v[3];
    float e[3] = {0.0f, 0.0f, 0.0f}, u[3];
    int k;
    v[0] = w;
    v[1] = d;
    v[2] = f;
    for (k = 0; k < 3; k++) {
        /* R^T about ax: (i, j) -> (c vi + s vj, -s vi + c vj) */
        const float vi = v[k][i], vj = v[k][j];
        v[k][i] = c * vi + s * vj;
        v[k][j] = -s * vi + c * vj;
    }
    e[ax] = th1;
    fc_cross(w, e, u);
    for (k = 0; k < 3; k++) {
        d[k] += u[k];
    }
    w[ax] += th1;
    d[ax] += th2;
}

/* the joint in each sensor's frame (m) */
static const float fc_ir1[3] = {0.12f, -0.2f, 0.05f}, fc_ir2[3] = {-0.03f, 0.08f, 0.27f};

static void fc_imu_sample(unsigned k, sfit_imu_sample_t *x)
{
    const float t = (float)k * 0.005f, om = 4.9087385f; /* 2 periods */
    float w1[3] = {0.0f, 0.0f, 0.0f}, d1[3] = {0.0f, 0.0f, 0.0f}, w2[3], d2[3], g1[3], g2[3];
    /* the joint's acceleration minus gravity, world: a sway and a bounce */
    float f1[3] = {-1.5f * sinf(om * t), -1.0f * cosf(0.5f * om * t),
                   9.81f - 1.0f * sinf(2.0f * om * t)};
    float f2[3];
    int i;
    /* the parent: R1 = Rz(yaw) Ry(pitch) Rx(roll) */
    fc_turn(2, 0.3f, 2.0f, 0.0f, t, w1, d1, f1);
    fc_turn(1, 0.15f, 1.0f, 1.3f, t, w1, d1, f1);
    fc_turn(0, 0.2f, 3.0f, 0.4f, t, w1, d1, f1);
    /* the child on it (a ball joint): R2 = R1 Ry(flexion) Rx(abduction) */
    memcpy(w2, w1, sizeof w2);
    memcpy(d2, d1, sizeof d2);
    memcpy(f2, f1, sizeof f2);
    fc_turn(1, 0.5f, 3.0f, 1.0f, t, w2, d2, f2);
    fc_turn(0, 0.35f, 2.0f, 2.0f, t, w2, d2, f2);
    fc_g(w1, d1, fc_ir1, g1);
    fc_g(w2, d2, fc_ir2, g2);
    for (i = 0; i < 3; i++) {
        x->acc1.v[i] = f1[i] - g1[i];
        x->acc2.v[i] = f2[i] - g2[i];
        x->gyr1.v[i] = w1[i];
        x->gyr2.v[i] = w2[i];
    }
}

static void fc_setup_imu(void)
{
    unsigned k;
    for (k = 0; k < FC_IMU_TAB; k++) {
        fc_imu_sample(k, &fc_itab[k]);
    }
}

static void fc_imu_feed(unsigned n)
{
    unsigned i;
    for (i = 0; i < n; i++) {
        fc_keep(sfit_imu_add(&fc_imu, &fc_itab[fc_ik % FC_IMU_TAB]));
        fc_ik++;
    }
}

static void fc_prep_imu(void)
{
    fc_ik = 0u;
    fc_keep(sfit_imu_init(&fc_imu, 200.0f, NULL));
    fc_imu_feed(300u);
}

static void fc_imu_adds(void)
{
    const uint32_t stride = fc_imu.stride;
    fc_imu_feed(FC_NIMU);
    if (fc_imu.stride != 2u * stride) { /* the steady state: one compaction amortised */
        fc_st = SFIT_E_ARG;
    }
}

static void fc_prep_imu_compact(void)
{
    fc_prep_imu();
    while (!(fc_imu.nfull == (uint32_t)SFIT_IMU_KEEP - 1u && fc_imu.wpos == fc_imu.stride - 1u)) {
        fc_imu_feed(1u);
    }
}

static void fc_imu_add1(void)
{
    fc_imu_feed(1u);
    if (fc_imu.nfull != (uint32_t)SFIT_IMU_KEEP / 2u) { /* it compacted */
        fc_st = SFIT_E_ARG;
    }
}

/* a full buffer: SFIT_IMU_KEEP - 1 closed windows and an open one */
static void fc_prep_imu_full(void)
{
    fc_prep_imu();
    while (!(fc_imu.nfull == (uint32_t)SFIT_IMU_KEEP - 1u && fc_imu.wpos > 0u)) {
        fc_imu_feed(1u);
    }
}

/* The case the row stands for, checked (driver code, not counted): a full
 * buffer, an unflagged ball, the relative rotation's path to its end
 * (wobble_deg is 0 when it stops early), r1 and r2 as generated to 2 mm. */
static void fc_imu_solve(void)
{
    int k;
    fc_keep(sfit_imu_solve(&fc_imu, &fc_ires));
    if (fc_ires.used != (uint32_t)SFIT_IMU_KEEP || fc_ires.flags != 0u || fc_ires.hinge ||
        !(fc_ires.wobble_deg > 0.0f)) {
        fc_st = SFIT_E_ARG;
    }
    for (k = 0; k < 3; k++) {
        const float e1 = fc_ires.r1.v[k] - fc_ir1[k], e2 = fc_ires.r2.v[k] - fc_ir2[k];
        if (!(e1 < 0.002f && e1 > -0.002f && e2 < 0.002f && e2 > -0.002f)) {
            fc_st = SFIT_E_ARG;
        }
    }
}

/* ---- issue 30: the whole lower limb per frame -------------------------------
 * 7 segments (pelvis; right and left thigh, shank, foot: the left side the
 * right one mirrored, x -> -x) with 4 / 5 / 5 / 4 markers, 6 joints (hips,
 * knees, ankles), 200 Hz frames 2.5 m from the origin, noise 0.5 mm. Each
 * segment turns about its own axis at a speed typical of gait (pelvis 40,
 * thigh 250, shank 400, foot 400 degrees/s: 0.2 - 2 degrees per frame).
 * Tracking: one pose per segment per frame (sfit_cluster_track, pose
 * only), shared by the joints that use it, and every joint centre mapped
 * to the global frame from its parent's pose. Calibrating: the poses with
 * their residuals and one sfit_pair_add per joint. */
#define FC_LL_NS 7u
#define FC_LL_NJ 6u
#define FC_LL_NF 33u /* frame 0 starts the tracks; 32 measured */
#define FC_LL_MAXM 5u
static const unsigned fc_ll_nm[FC_LL_NS] = {4u, 5u, 5u, 4u, 5u, 5u, 4u};
static const float fc_ll_tpl[4][FC_LL_MAXM][3] = {
    /* pelvis: ASIS, ASIS, PSIS, PSIS */
    {{120.0f, 60.0f, 0.0f}, {-120.0f, 60.0f, 0.0f}, {50.0f, -110.0f, 30.0f}, {-50.0f, -110.0f, 30.0f}},
    /* right thigh (segment frame at the hip) */
    {{70.0f, 20.0f, -200.0f}, {60.0f, -40.0f, -180.0f}, {75.0f, 10.0f, -300.0f}, {55.0f, 0.0f, -420.0f}, {-50.0f, 0.0f, -420.0f}},
    /* right shank (at the knee) */
    {{60.0f, 30.0f, -150.0f}, {20.0f, 45.0f, -200.0f}, {55.0f, 20.0f, -260.0f}, {45.0f, 0.0f, -400.0f}, {-40.0f, 0.0f, -400.0f}},
    /* right foot (at the ankle) */
    {{0.0f, -60.0f, -40.0f}, {30.0f, 160.0f, -50.0f}, {-20.0f, 60.0f, -10.0f}, {55.0f, 130.0f, -45.0f}}};
static const unsigned fc_ll_kind[FC_LL_NS] = {0u, 1u, 2u, 3u, 1u, 2u, 3u};
static const float fc_ll_speed[4] = {40.0f, 250.0f, 400.0f, 400.0f}; /* degrees/s */
static const unsigned fc_ll_par[FC_LL_NJ] = {0u, 1u, 2u, 0u, 4u, 5u};
static const unsigned fc_ll_chi[FC_LL_NJ] = {1u, 2u, 3u, 4u, 5u, 6u};
static sfit_cluster_t fc_ll_cl[FC_LL_NS];
static sfit_cluster_track_t fc_ll_trk[FC_LL_NS];
static sfit_pose_t fc_ll_pose[FC_LL_NS];
static sfit_cluster_fit_t fc_ll_fit[FC_LL_NS];
static sfit_pair_t fc_ll_pair[FC_LL_NJ];
static sfit_vec3_t fc_ll_cen[FC_LL_NJ]; /* calibrated centres, parent frame */
static sfit_vec3_t fc_ll_out[FC_LL_NJ];
static sfit_vec3_t fc_ll_m[FC_LL_NF][FC_LL_NS][FC_LL_MAXM];

static void fc_setup_lower_limb(void)
{
    static const float base[3] = {1500.0f, -1800.0f, 900.0f};
    unsigned sg, f, i;
    int k;
    for (sg = 0; sg < FC_LL_NS; sg++) {
        const unsigned kd = fc_ll_kind[sg];
        const float mir = (sg >= 4u) ? -1.0f : 1.0f;
        sfit_vec3_t tv[FC_LL_MAXM];
        float u[3], r0[9], rs[9], r[9], c, ang;
        for (i = 0; i < fc_ll_nm[sg]; i++) {
            tv[i].v[0] = mir * fc_ll_tpl[kd][i][0];
            tv[i].v[1] = fc_ll_tpl[kd][i][1];
            tv[i].v[2] = fc_ll_tpl[kd][i][2];
        }
        if (sfit_cluster_init(&fc_ll_cl[sg], tv, fc_ll_nm[sg]) != SFIT_OK) {
            fc_st = SFIT_E_ARG;
        }
        fc_dir(u, -1.0f, 0);
        c = 2.0f * fc_unif() - 1.0f;
        fc_rot_axis(u, c, __builtin_sqrtf(1.0f - c * c), r0);
        fc_dir(u, -1.0f, 0);
        ang = fc_ll_speed[kd] * (3.14159265f / 180.0f) / 200.0f;
        fc_rot_axis(u, __builtin_cosf(ang), __builtin_sinf(ang), rs);
        memcpy(r, r0, sizeof r);
        for (f = 0; f < FC_LL_NF; f++) {
            float t[3], nr[9];
            unsigned a, b;
            for (k = 0; k < 3; k++) {
                t[k] = base[k] + 6.0f * (float)f + 100.0f * (float)sg;
            }
            for (i = 0; i < fc_ll_nm[sg]; i++) {
                fc_apply(r, tv[i].v, t, fc_ll_m[f][sg][i].v);
                for (k = 0; k < 3; k++) {
                    fc_ll_m[f][sg][i].v[k] += fc_sigma * fc_noise();
                }
            }
            for (a = 0; a < 3u; a++) {
                for (b = 0; b < 3u; b++) {
                    nr[3u * a + b] = rs[3u * a] * r[b] + rs[3u * a + 1u] * r[3u + b] + rs[3u * a + 2u] * r[6u + b];
                }
            }
            memcpy(r, nr, sizeof r);
        }
    }
    for (i = 0; i < FC_LL_NJ; i++) {
        fc_ll_cen[i].v[0] = 10.0f;
        fc_ll_cen[i].v[1] = -20.0f;
        fc_ll_cen[i].v[2] = -80.0f;
    }
}

/* Frame 0: the full solves that start the tracks and the pair states. */
static void fc_prep_ll(void)
{
    unsigned sg, j;
    for (sg = 0; sg < FC_LL_NS; sg++) {
        fc_keep(sfit_cluster_track_reset(&fc_ll_trk[sg]));
        fc_keep(sfit_cluster_track(&fc_ll_cl[sg], &fc_ll_trk[sg], fc_ll_m[0][sg], fc_ll_nm[sg],
                                   &fc_ll_pose[sg], &fc_ll_fit[sg]));
    }
    for (j = 0; j < FC_LL_NJ; j++) {
        fc_keep(sfit_pair_init(&fc_ll_pair[j], &fc_ll_cl[fc_ll_par[j]], &fc_ll_cl[fc_ll_chi[j]], NULL));
    }
}

static void fc_ll_track_frames(void) /* FC_LL_NF - 1 frames */
{
    unsigned f, sg, j;
    for (f = 1u; f < FC_LL_NF; f++) {
        for (sg = 0; sg < FC_LL_NS; sg++) {
            fc_keep(sfit_cluster_track(&fc_ll_cl[sg], &fc_ll_trk[sg], fc_ll_m[f][sg], fc_ll_nm[sg],
                                       &fc_ll_pose[sg], NULL));
        }
        for (j = 0; j < FC_LL_NJ; j++) {
            fc_keep(sfit_cluster_to_global(&fc_ll_pose[fc_ll_par[j]], &fc_ll_cen[j], &fc_ll_out[j]));
        }
    }
}

static void fc_ll_calib_frames(void) /* FC_LL_NF - 1 frames */
{
    unsigned f, sg, j;
    for (f = 1u; f < FC_LL_NF; f++) {
        for (sg = 0; sg < FC_LL_NS; sg++) {
            fc_keep(sfit_cluster_track(&fc_ll_cl[sg], &fc_ll_trk[sg], fc_ll_m[f][sg], fc_ll_nm[sg],
                                       &fc_ll_pose[sg], &fc_ll_fit[sg]));
        }
        for (j = 0; j < FC_LL_NJ; j++) {
            const unsigned a = fc_ll_par[j], b = fc_ll_chi[j];
            fc_keep(sfit_pair_add(&fc_ll_pair[j], &fc_ll_pose[a], &fc_ll_fit[a], &fc_ll_pose[b],
                                  &fc_ll_fit[b]));
        }
    }
}

/* The same frames registered from nothing (sfit_cluster_register): the
 * lower limb before issue 30. */
static void fc_ll_register_frames(void)
{
    unsigned f, sg, j;
    for (f = 1u; f < FC_LL_NF; f++) {
        for (sg = 0; sg < FC_LL_NS; sg++) {
            fc_keep(sfit_cluster_register(&fc_ll_cl[sg], fc_ll_m[f][sg], fc_ll_nm[sg], &fc_ll_pose[sg],
                                          NULL));
        }
        for (j = 0; j < FC_LL_NJ; j++) {
            fc_keep(sfit_cluster_to_global(&fc_ll_pose[fc_ll_par[j]], &fc_ll_cen[j], &fc_ll_out[j]));
        }
    }
}


/* ---- the table ------------------------------------------------------------ */
static const fc_op_t fc_ops[] = {
    /* name, public function, prep, run, prep_base, base, div */
    {"moments_add", "sfit_moments_add", fc_prep_empty, fc_add_amortised, NULL, NULL, FC_NAMORT},
    {"moments_add_call", "sfit_moments_add", fc_prep_mid_block, fc_add_one, NULL, NULL, 1u},
    {"moments_add_flush", "sfit_moments_add", fc_prep_block_end, fc_add_one, NULL, NULL, 1u},
    {"moments_add_batch", "sfit_moments_add_block", fc_prep_empty, fc_add_batch, NULL, NULL, FC_NAMORT},
    {"moments_stats", "sfit_moments_stats", NULL, fc_stats, NULL, NULL, 1u},
    {"batch_per_point", "sfit_fit_points", NULL, fc_batch_n, NULL, fc_batch_half, FC_NPTS - FC_NHALF},
    {"batch_total", "sfit_fit_points", NULL, fc_batch_n, NULL, NULL, 1u},
    {"solve_gdke", "sfit_fit_moments", NULL, fc_solve_gdke, NULL, NULL, 1u},
    {"solve_gdke_500", "sfit_fit_moments", fc_prep_500, fc_solve_gdke_500, NULL, NULL, 1u},
    {"solve_ugdk", "sfit_fit_moments", NULL, fc_solve_ugdk, NULL, NULL, 1u},
    {"solve_gdke_eigen", "sfit_fit_moments", NULL, fc_solve_gdke_eigen, NULL, NULL, 1u},
    {"solve_ugdk_eigen", "sfit_fit_moments", NULL, fc_solve_ugdk_eigen, NULL, NULL, 1u},
    {"solve_default", "sfit_fit_moments_default", NULL, fc_solve_default, NULL, NULL, 1u},
    {"chol_factor", "sfit_mat3_chol", NULL, fc_chol, NULL, NULL, 1u},
    {"chol_solve", "sfit_mat3_chol", NULL, fc_chol_and_subst, NULL, NULL, 1u},
    {"jacobi_eig", "sfit_mat3_eig_sym", NULL, fc_eig, NULL, NULL, 1u},
    {"jacobi_rotation", "sfit_mat3_eig_sym", NULL, fc_eig_rot, NULL, NULL, 1u},
    {"planar_solve", "sfit_fit_moments", NULL, fc_solve_planar, NULL, NULL, 1u},
    {"uncert_selfcal_per_point", "sfit_uncert_selfcal", fc_prep_selfcal, fc_uncert_selfcal_n,
     fc_prep_selfcal, fc_uncert_selfcal_half, FC_NPTS - FC_NHALF},
    {"uncert_selfcal", "sfit_uncert_selfcal", fc_prep_selfcal, fc_uncert_selfcal_n, NULL, NULL, 1u},
    {"multi_solve_per_marker", "sfit_multi_fit", NULL, fc_multi_all, NULL, fc_multi_half, FC_NMARK / 2u},
    {"multi_solve_total", "sfit_multi_fit", NULL, fc_multi_all, NULL, NULL, 1u},
    {"multi_solve_noise_total", "sfit_multi_fit_noise", NULL, fc_multi_noise, NULL, NULL, 1u},
    {"multi_center_cov", "sfit_multi_center_cov", fc_multi_all, fc_multi_cov, NULL, NULL, 1u},
    {"noise_calibration", "sfit_noise_calibrate", NULL, fc_noise_calib, NULL, NULL, 1u},
    {"cluster_register", "sfit_cluster_register", NULL, fc_register, NULL, NULL, 1u},
    {"cluster_track", "sfit_cluster_track", fc_prep_track, fc_track, NULL, NULL, 1u},
    {"cluster_track_pose", "sfit_cluster_track", fc_prep_track, fc_track_pose, NULL, NULL, 1u},
    {"cluster_track_first", "sfit_cluster_track", NULL, fc_track_first, NULL, NULL, 1u},
    {"pose_to_segment", "sfit_cluster_to_segment", fc_register, fc_to_segment, NULL, NULL, 1u},
    {"joint_frame", "sfit_joint_add", fc_prep_joint5, fc_joint_frames, NULL, NULL, FC_NJF},
    {"joint_per_child", "sfit_joint_add", fc_prep_joint5, fc_joint_frames, fc_prep_joint1, fc_joint_frames, FC_NJF * (FC_NJC - 1u)},
    {"joint_fit", "sfit_joint_fit", fc_prep_joint5_full, fc_joint_solve, NULL, NULL, 1u},
    {"joint_center_at", "sfit_joint_center_at", fc_prep_joint_solved, fc_joint_center_at, NULL, NULL, 1u},
    {"joint_fit_marker", "sfit_joint_fit", fc_prep_joint5_marker, fc_joint_solve, NULL, NULL, 1u},
    {"joint_center_cov_frame", "sfit_joint_center_cov", fc_prep_joint_marker_solved, fc_joint_center_cov, NULL, NULL, FC_NJF},
    {"pair_add", "sfit_pair_add", fc_prep_pair, fc_pair_frames, NULL, NULL, FC_NJF},
    {"pair_add_markers", "sfit_pair_add_markers", fc_prep_pair, fc_pair_frames_markers, NULL, NULL, FC_NJF},
    {"pair_solve", "sfit_pair_solve", fc_prep_pair_full, fc_pair_solve, NULL, NULL, 1u},
    {"pair_solve_score", "sfit_pair_solve", fc_prep_pair_full_score, fc_pair_solve, NULL, NULL, 1u},
    {"imu_add", "sfit_imu_add", fc_prep_imu, fc_imu_adds, NULL, NULL, FC_NIMU},
    {"imu_add_compact", "sfit_imu_add", fc_prep_imu_compact, fc_imu_add1, NULL, NULL, 1u},
    {"imu_solve", "sfit_imu_solve", fc_prep_imu_full, fc_imu_solve, NULL, NULL, 1u},
    {"lower_limb_track_frame", "sfit_cluster_track", fc_prep_ll, fc_ll_track_frames, NULL, NULL, FC_LL_NF - 1u},
    {"lower_limb_calib_frame", "sfit_pair_add", fc_prep_ll, fc_ll_calib_frames, NULL, NULL, FC_LL_NF - 1u},
    {"lower_limb_register_frame", "sfit_cluster_register", fc_prep_ll, fc_ll_register_frames, NULL, NULL, FC_LL_NF - 1u},
    {"incremental_update", "sfit_incr_update", fc_prep_incr_gdke, fc_incr_update, NULL, NULL, 1u},
    {"incremental_add", "sfit_incr_add", fc_prep_incr_gdke, fc_incr_add, NULL, NULL, 1u},
    {"incremental_solve", "sfit_incr_fit", fc_prep_incr_gdke, fc_incr_solve, NULL, NULL, 1u},
    {"incremental_update_ugdk", "sfit_incr_update", fc_prep_incr_ugdk, fc_incr_update, NULL, NULL, 1u},
    {"incremental_update_amortised", "sfit_incr_update", fc_prep_incr_gdke, fc_incr_updates, NULL, NULL, FC_NPTS - FC_NHALF},
};

static void fc_measure(fc_fn_t prep, fc_fn_t run)
{
    if (prep != NULL) {
        prep();
    }
    fc_begin();
    run();
    fc_end();
}

int main(void)
{
    unsigned i;
    int fails = 0;

    fc_setup();
    fc_setup_joint();
    fc_setup_pair();
    fc_setup_lower_limb();
    fc_setup_imu();
    printf("fcinfo sum_block %u\n", (unsigned)SFIT_SUM_BLOCK);
    printf("fcinfo npts %u\n", FC_NPTS);
    printf("fcinfo namort %u\n", (unsigned)FC_NAMORT);
    for (i = 0; i < sizeof fc_ops / sizeof fc_ops[0]; i++) {
        const fc_op_t *op = &fc_ops[i];
        printf("fcop %s %u %d %s\n", op->name, op->div, op->base != NULL ? 2 : 1, op->fn);
        fc_st = SFIT_OK;
        fc_measure(op->prep, op->run);
        if (op->base != NULL) {
            fc_measure(op->prep_base, op->base);
        }
        if (fc_st != SFIT_OK) {
            printf("fcfail %s %d\n", op->name, (int)fc_st);
            fails++;
        }
    }
    printf("fcdone %d\n", fails);
    return fails;
}
