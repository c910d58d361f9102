/* SPDX-License-Identifier: MIT */
/**
 * @file tt_pair.c
 * @brief On-target: the pair of segments (sfit_pair.h) against the double
 * oracle of tests/ref (sfit_ref_pair.c: full 6x6 SCoRE with the
 * errors-in-variables correction, 6x6 SARA) on the same float poses, an
 * exact hinge, the statuses, and a rejected frame leaving the state
 * unchanged. Tolerances as on the host (tests/test_pair.c): centre 5e-3 mm,
 * axis 2e-5 per component.
 */
#include <math.h>
#include <string.h>

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_pair.h"
#include "sfit_ref_joint.h"
#include "sfit_ref_pair.h"
#include "tt_data.h"

void tt_pair(void);

#define TT_PP 4
#define TT_PC 4
#define TT_PF 200

static const double tt_pt[TT_PP][3] = {
    {120.0, 60.0, 0.0}, {-120.0, 60.0, 0.0}, {-40.0, -100.0, 20.0}, {40.0, -100.0, 30.0}};
static const double tt_ct[TT_PC][3] = {
    {30.0, 0.0, -200.0}, {-30.0, 40.0, -250.0}, {40.0, -10.0, -300.0}, {0.0, 50.0, -350.0}};
static const double tt_cp[3] = {80.0, -40.0, -90.0};
static const double tt_hx[3] = {0.98, 0.17, 0.1};

static sfit_cluster_t tt_pcl, tt_ccl;
static sfit_pair_t tt_s, tt_s0;
static ref_pair_frame_t tt_fr[TT_PF];

static void tt_mm(const double a[9], const double b[9], double c[9])
{
    int i, j, k;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            c[3 * i + j] = 0.0;
            for (k = 0; k < 3; k++) {
                c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
            }
        }
    }
}

/* kind 0: ball (star arcs, 30 deg), 1: hinge (0..90 deg). Returns 0 on success. */
static int tt_trial(int kind, double sigma, uint64_t seed, sfit_pair_method_t method)
{
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    tu_rng_t g;
    size_t f, i;
    int k;
    cfg.method = method;
    cfg.mode = kind ? SFIT_PAIR_MODE_HINGE : SFIT_PAIR_MODE_BALL;
    if (sfit_pair_init(&tt_s, &tt_pcl, &tt_ccl, &cfg) != SFIT_OK) {
        return 1;
    }
    tu_rng_seed(&g, seed);
    for (f = 0; f < TT_PF; f++) {
        double rrel[9], rp[9], rc[9], tp[3], tc[3], a[3];
        const double z[3] = {0.1, 0.2, 1.0}, zero[3] = {0.0, 0.0, 0.0};
        sfit_vec3_t pm[TT_PP], cm[TT_PC];
        sfit_pose_t pp, pc;
        sfit_cluster_fit_t fp, fc;
        double dd[3];
        if (kind) {
            tu_rot_axis_angle(tt_hx, 1.5708 * (double)f / TT_PF, rrel);
        } else {
            const double ph = (double)(f / 25u) * 0.3927;
            const double ax[3] = {cos(ph), sin(ph), 0.0};
            tu_rot_axis_angle(ax, 0.5236 * sin(3.14159 * (double)(f % 25u) / 24.0), rrel);
        }
        tu_rot_axis_angle(z, 0.3 * sin(0.013 * (double)f), rp);
        tp[0] = 1000.0 + 5.0 * (double)f;
        tp[1] = 2000.0;
        tp[2] = 900.0;
        tt_mm(rp, rrel, rc);
        /* t_c = R_p c_p + t_p - R_c c_c, c_c = 0 */
        ref_pose_to_global(rp, tp, tt_cp, tc);
        for (i = 0; i < TT_PP; i++) {
            double x[3];
            ref_pose_to_global(rp, tp, tt_pt[i], x);
            tu_add_noise(&g, sigma, x);
            tt_store(x, &pm[i], dd);
        }
        for (i = 0; i < TT_PC; i++) {
            double x[3];
            ref_pose_to_global(rc, tc, tt_ct[i], x);
            tu_add_noise(&g, sigma, x);
            tt_store(x, &cm[i], dd);
        }
        (void)zero;
        (void)a;
        if (sfit_cluster_register(&tt_pcl, pm, TT_PP, &pp, &fp) != SFIT_OK
            || sfit_cluster_register(&tt_ccl, cm, TT_PC, &pc, &fc) != SFIT_OK
            || sfit_pair_add(&tt_s, &pp, &fp, &pc, &fc) != SFIT_OK) {
            return 1;
        }
        for (k = 0; k < 9; k++) {
            tt_fr[f].rp[k] = (double)pp.r.m[k];
            tt_fr[f].rc[k] = (double)pc.r.m[k];
        }
        for (k = 0; k < 3; k++) {
            tt_fr[f].tp[k] = (double)pp.t.v[k];
            tt_fr[f].tc[k] = (double)pc.t.v[k];
        }
    }
    return 0;
}

void tt_pair(void)
{
    sfit_vec3_t tv[TT_PP];
    double tpd[TT_PP][3], tcd[TT_PC][3];
    ref_pair_tpl_t rtp, rtc;
    sfit_pair_result_t r, r0;
    size_t i;
    int m;

    tt_case("pair: templates");
    for (i = 0; i < TT_PP; i++) {
        tt_store(tt_pt[i], &tv[i], tpd[i]);
    }
    TT_EQ_INT(sfit_cluster_init(&tt_pcl, tv, TT_PP), SFIT_OK);
    for (i = 0; i < TT_PC; i++) {
        tt_store(tt_ct[i], &tv[i], tcd[i]);
    }
    TT_EQ_INT(sfit_cluster_init(&tt_ccl, tv, TT_PC), SFIT_OK);
    TT_EQ_INT(ref_pair_tpl((const double(*)[3])tpd, TT_PP, &rtp), 0);
    TT_EQ_INT(ref_pair_tpl((const double(*)[3])tcd, TT_PC, &rtc), 0);

    for (m = 0; m < 3; m++) {
        double cp[3], cc[3], vp, vc;
        tt_case(m == 0   ? "pair: ball, default (weighted) vs 6x6 reference"
                : m == 1 ? "pair: ball, SCoRE vs 6x6 reference"
                         : "pair: ball, unweighted vs 6x6 reference");
        TT_EQ_INT(tt_trial(0, 0.5, 71u, (sfit_pair_method_t)m), 0);
        TT_EQ_INT(sfit_pair_solve(&tt_s, &r), SFIT_OK);
        TT_EQ_INT(r.mode, SFIT_PAIR_MODE_BALL);
        vp = (m != 1) ? (double)r.marker_var_p : 0.0;
        vc = (m != 1) ? (double)r.marker_var_c : 0.0;
        TT_EQ_INT(ref_pair_score(tt_fr, TT_PF, &rtp, &rtc, vp, vc, cp, cc), 0);
        if (m == 0) {
            double c0[3], k0[3];
            for (i = 0; i < 3; i++) {
                c0[i] = cp[i];
                k0[i] = cc[i];
            }
            TT_EQ_INT(ref_pair_score_wls(tt_fr, TT_PF, &rtp, &rtc, vp, vc, c0, k0, cp, cc, NULL),
                      0);
        }
        for (i = 0; i < 3; i++) {
            TT_NEAR(r.center_p.v[i], cp[i], 5e-3);
            TT_NEAR(r.center_c.v[i], cc[i], 5e-3);
        }
        TT_TRUE(r.center_cov.m[0] > 0.0f && r.center_cov.m[4] > 0.0f && r.center_cov.m[8] > 0.0f);
    }

    tt_case("pair: exact hinge, SARA vs 6x6 eigenvector");
    TT_EQ_INT(tt_trial(1, 0.0, 72u, SFIT_PAIR_METHOD_SCORE), 0);
    TT_EQ_INT(sfit_pair_solve(&tt_s, &r), SFIT_OK);
    {
        double ax[3];
        TT_EQ_INT(ref_pair_sara(tt_fr, TT_PF, &rtp, &rtc, 0.0, 0.0, ax, NULL), 0);
        for (i = 0; i < 3; i++) {
            TT_NEAR(r.axis_p.v[i], ax[i], 2e-5);
            TT_NEAR(ax[i], tt_hx[i] / tu_norm3(tt_hx), 1e-5);
        }
    }

    tt_case("pair: statuses; a rejected frame leaves the state unchanged");
    TT_EQ_INT(tt_trial(0, 0.5, 73u, SFIT_PAIR_METHOD_DEFAULT), 0);
    tt_s0 = tt_s;
    TT_EQ_INT(sfit_pair_solve(&tt_s, &r0), SFIT_OK);
    {
        sfit_pose_t pp, bad;
        sfit_cluster_fit_t fp = {0.5f, 4u};
        memset(&pp, 0, sizeof pp);
        pp.r.m[0] = pp.r.m[4] = pp.r.m[8] = 1.0f;
        bad = pp;
        bad.r.m[3] = (float)NAN;
        TT_EQ_INT(sfit_pair_add(&tt_s, &bad, &fp, &pp, &fp), SFIT_E_NONFINITE);
        bad = pp;
        bad.t.v[0] = (float)INFINITY;
        TT_EQ_INT(sfit_pair_add(&tt_s, &pp, &fp, &bad, &fp), SFIT_E_NONFINITE);
        bad = pp;
        bad.t.v[0] = 1e10f;
        TT_EQ_INT(sfit_pair_add(&tt_s, &bad, &fp, &pp, &fp), SFIT_E_RANGE);
        TT_EQ_INT(sfit_pair_add(&tt_s, NULL, &fp, &pp, &fp), SFIT_E_ARG);
        fp.used = 1u;
        TT_EQ_INT(sfit_pair_add(&tt_s, &pp, &fp, &pp, NULL), SFIT_E_ARG);
    }
    TT_TRUE(memcmp(&tt_s, &tt_s0, sizeof tt_s) == 0);
    TT_EQ_INT(sfit_pair_solve(&tt_s, &r), SFIT_OK);
    TT_TRUE(memcmp(&r, &r0, sizeof r) == 0);
    TT_EQ_INT(sfit_pair_solve(NULL, &r), SFIT_E_ARG);
    tt_s.inblk = 999u;
    TT_EQ_INT(sfit_pair_solve(&tt_s, &r), SFIT_E_ARG);
    TT_EQ_INT(sfit_pair_reset(&tt_s0), SFIT_OK);
    TT_EQ_INT(sfit_pair_solve(&tt_s0, &r), SFIT_E_TOO_FEW);
}
