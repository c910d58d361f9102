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
#include <stdio.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit/sfit_fit.h"
#include "sfit/sfit_mat3.h"
#include "sfit/sfit_moments.h"

#if defined(__has_include)
#if __has_include("sfit/sfit_multi.h")
#include "sfit/sfit_multi.h"
#define FC_HAVE_MULTI 1
#endif
#if __has_include("sfit/sfit_noise.h")
#include "sfit/sfit_noise.h"
#define FC_HAVE_NOISE 1
#endif
#if __has_include("sfit/sfit_incr.h")
#include "sfit/sfit_incr.h"
#define FC_HAVE_INCR 1
#endif
#endif
#include "sfit/sfit_cluster.h"
#include "sfit/sfit_joint.h"
#include "sfit/sfit_pair.h"
#define FC_HAVE_JOINT 1
#ifndef FC_HAVE_MULTI
#define FC_HAVE_MULTI 0
#endif
#ifndef FC_HAVE_NOISE
#define FC_HAVE_NOISE 0
#endif
#ifndef FC_HAVE_INCR
#define FC_HAVE_INCR 0
#endif

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
static sfit_fit_cfg_t fc_cfg_gdke_eig; /* cfg.eigen = 1: the full solver */
static sfit_fit_cfg_t fc_cfg_ugdk_eig;
static sfit_status_t fc_st;
static sfit_selfcal_result_t fc_sc;      /* self-calibrated fit of fc_pts */
static sfit_uncert_t fc_unc;
#if FC_HAVE_MULTI
static sfit_moments_t fc_mk[FC_NMARK];
static sfit_multi_result_t fc_mres;
static float fc_radii[FC_NMARK];
#endif
#if FC_HAVE_NOISE
static sfit_noise_est_t fc_nest;
#endif
#if FC_HAVE_JOINT
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
static sfit_joint_cfg_t fc_jcfg5;
static sfit_joint_cfg_t fc_jcfg1;
static sfit_joint_cfg_t fc_jcfgm;
#endif
#if FC_HAVE_INCR
static sfit_incr_t fc_inc;
static sfit_sphere_t fc_iest;
#endif

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
    fc_cfg_gdke_eig.eigen = 1;
    fc_cfg_ugdk_eig = fc_cfg_ugdk;
    fc_cfg_ugdk_eig.eigen = 1;
#if FC_HAVE_MULTI
    {
        unsigned p;
        for (p = 0; p < FC_NMARK; p++) {
            sfit_vec3_t tmp[FC_NPERMARK];
            fc_sample(tmp, FC_NPERMARK, cos45, 0, fc_centre, 80.0f + 10.0f * (float)p);
            fc_moments_of(&fc_mk[p], tmp, FC_NPERMARK);
        }
    }
#endif
}

#if FC_HAVE_JOINT
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
        float u[3], rp[9], rq[9], c, s, y[3];
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
    fc_jcfg5 = sfit_joint_cfg_default;
    fc_jcfg5.n_child = FC_NJC;
    fc_jcfg1 = sfit_joint_cfg_default;
    fc_jcfg1.n_child = 1u;
    fc_jcfgm = fc_jcfg5;
    fc_jcfgm.noise_model = SFIT_JOINT_NOISE_MARKER;
    fc_jcfgm.solve.fit.noise = SFIT_NOISE_ISO;
    fc_jcfgm.solve.fit.noise_var = fc_sigma * fc_sigma;
}
#endif

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

static void fc_batch_n(void)
{
    fc_keep(sfit_points_fit(fc_pts, FC_NPTS, NULL, &fc_res));
}

static void fc_batch_half(void)
{
    fc_keep(sfit_points_fit(fc_pts, FC_NHALF, NULL, &fc_res));
}

static void fc_prep_selfcal(void)
{
    fc_keep(sfit_points_selfcal(fc_pts, FC_NPTS, NULL, &fc_sc));
}

static void fc_uncert_selfcal_n(void)
{
    fc_keep(sfit_points_uncert_selfcal(fc_pts, FC_NPTS, &fc_sc.fit.center, fc_sc.fit.radius,
                                       fc_sc.noise_var, &fc_unc));
}

static void fc_uncert_selfcal_half(void)
{
    fc_keep(sfit_points_uncert_selfcal(fc_pts, FC_NHALF, &fc_sc.fit.center, fc_sc.fit.radius,
                                       fc_sc.noise_var, &fc_unc));
}

/* The default solve must take the screened path on the cap. */
static void fc_solve_gdke(void)
{
    fc_keep(sfit_moments_fit(&fc_mom_cap, NULL, &fc_res));
    fc_keep((fc_res.exact == 0) ? SFIT_OK : SFIT_E_RANGE);
}

static void fc_solve_ugdk(void)
{
    fc_keep(sfit_moments_fit(&fc_mom_cap, &fc_cfg_ugdk, &fc_res));
    fc_keep((fc_res.exact == 0) ? SFIT_OK : SFIT_E_RANGE);
}

static void fc_solve_gdke_eigen(void)
{
    fc_keep(sfit_moments_fit(&fc_mom_cap, &fc_cfg_gdke_eig, &fc_res));
}

static void fc_solve_ugdk_eigen(void)
{
    fc_keep(sfit_moments_fit(&fc_mom_cap, &fc_cfg_ugdk_eig, &fc_res));
}

static void fc_solve_planar(void)
{
    fc_keep(sfit_moments_fit(&fc_mom_arc, &fc_cfg_planar, &fc_res));
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

#if FC_HAVE_MULTI
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
#endif

#if FC_HAVE_NOISE
static void fc_noise_calib(void)
{
    sfit_vec3_t c0;
    c0.v[0] = fc_centre[0];
    c0.v[1] = fc_centre[1];
    c0.v[2] = fc_centre[2];
    fc_keep(sfit_moments_calibrate(&fc_mom_cap, &c0, fc_radius, &fc_nest));
}
#endif

#if FC_HAVE_INCR
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
#endif

#if FC_HAVE_JOINT
static void fc_register(void)
{
    fc_keep(sfit_cluster_register(&fc_cl, fc_jpar[0], FC_NJP, &fc_pose, &fc_cfit));
}

static void fc_to_segment(void)
{
    fc_keep(sfit_pose_to_segment(&fc_pose, &fc_jchi[0][0], &fc_x));
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
#endif

/* ---- the table ------------------------------------------------------------ */
static const fc_op_t fc_ops[] = {
    /* name, public function, prep, run, prep_base, base, div */
    {"moments_add", "sfit_moments_add", fc_prep_empty, fc_add_amortised, NULL, NULL, FC_NAMORT},
    {"moments_add_call", "sfit_moments_add", fc_prep_mid_block, fc_add_one, NULL, NULL, 1u},
    {"moments_add_flush", "sfit_moments_add", fc_prep_block_end, fc_add_one, NULL, NULL, 1u},
    {"moments_stats", "sfit_moments_stats", NULL, fc_stats, NULL, NULL, 1u},
    {"batch_per_point", "sfit_points_fit", NULL, fc_batch_n, NULL, fc_batch_half, FC_NPTS - FC_NHALF},
    {"batch_total", "sfit_points_fit", NULL, fc_batch_n, NULL, NULL, 1u},
    {"solve_gdke", "sfit_moments_fit", NULL, fc_solve_gdke, NULL, NULL, 1u},
    {"solve_ugdk", "sfit_moments_fit", NULL, fc_solve_ugdk, NULL, NULL, 1u},
    {"solve_gdke_eigen", "sfit_moments_fit", NULL, fc_solve_gdke_eigen, NULL, NULL, 1u},
    {"solve_ugdk_eigen", "sfit_moments_fit", NULL, fc_solve_ugdk_eigen, NULL, NULL, 1u},
    {"chol_factor", "sfit_mat3_chol", NULL, fc_chol, NULL, NULL, 1u},
    {"chol_solve", "sfit_mat3_chol", NULL, fc_chol_and_subst, NULL, NULL, 1u},
    {"jacobi_eig", "sfit_mat3_eig_sym", NULL, fc_eig, NULL, NULL, 1u},
    {"jacobi_rotation", "sfit_mat3_eig_sym", NULL, fc_eig_rot, NULL, NULL, 1u},
    {"planar_solve", "sfit_moments_fit", NULL, fc_solve_planar, NULL, NULL, 1u},
    {"uncert_selfcal_per_point", "sfit_points_uncert_selfcal", fc_prep_selfcal, fc_uncert_selfcal_n,
     fc_prep_selfcal, fc_uncert_selfcal_half, FC_NPTS - FC_NHALF},
    {"uncert_selfcal", "sfit_points_uncert_selfcal", fc_prep_selfcal, fc_uncert_selfcal_n, NULL, NULL, 1u},
#if FC_HAVE_MULTI
    {"multi_solve_per_marker", "sfit_multi_fit", NULL, fc_multi_all, NULL, fc_multi_half, FC_NMARK / 2u},
    {"multi_solve_total", "sfit_multi_fit", NULL, fc_multi_all, NULL, NULL, 1u},
    {"multi_solve_noise_total", "sfit_multi_fit_noise", NULL, fc_multi_noise, NULL, NULL, 1u},
    {"multi_center_cov", "sfit_multi_center_cov", fc_multi_all, fc_multi_cov, NULL, NULL, 1u},
#endif
#if FC_HAVE_NOISE
    {"noise_calibration", "sfit_moments_calibrate", NULL, fc_noise_calib, NULL, NULL, 1u},
#endif
#if FC_HAVE_JOINT
    {"cluster_register", "sfit_cluster_register", NULL, fc_register, NULL, NULL, 1u},
    {"pose_to_segment", "sfit_pose_to_segment", fc_register, fc_to_segment, NULL, NULL, 1u},
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
#endif
#if FC_HAVE_INCR
    {"incremental_update", "sfit_incr_update", fc_prep_incr_gdke, fc_incr_update, NULL, NULL, 1u},
    {"incremental_add", "sfit_incr_add", fc_prep_incr_gdke, fc_incr_add, NULL, NULL, 1u},
    {"incremental_solve", "sfit_incr_fit", fc_prep_incr_gdke, fc_incr_solve, NULL, NULL, 1u},
    {"incremental_update_ugdk", "sfit_incr_update", fc_prep_incr_ugdk, fc_incr_update, NULL, NULL, 1u},
    {"incremental_update_amortised", "sfit_incr_update", fc_prep_incr_gdke, fc_incr_updates, NULL, NULL, FC_NPTS - FC_NHALF},
#endif
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
#if FC_HAVE_JOINT
    fc_setup_joint();
    fc_setup_pair();
#endif
    printf("fcinfo sum_block %u\n", (unsigned)SFIT_SUM_BLOCK);
    printf("fcinfo npts %u\n", FC_NPTS);
    printf("fcinfo namort %u\n", (unsigned)FC_NAMORT);
    printf("fcinfo have_multi %d\nfcinfo have_noise %d\nfcinfo have_incr %d\n", FC_HAVE_MULTI,
           FC_HAVE_NOISE, FC_HAVE_INCR);
    printf("fcinfo have_joint %d\n", FC_HAVE_JOINT);
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
