/* SPDX-License-Identifier: MIT */
/**
 * @file tt_joint.c
 * @brief On-target: rigid cluster pose and the streaming joint centre
 * against the double oracles of tests/ref (Horn's quaternion registration,
 * ref_fit_multi) on the same float inputs, the reflection and occlusion
 * cases, the statuses, and a rejected frame leaving the state unchanged.
 * Tolerances as on the host (tests/test_cluster.c, tests/test_joint.c):
 * rotation 16 eps (s1/(s2+s3) + 1), centre 2e-2 mm (host maximum 1.3e-4).
 */
#include <string.h>

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_joint.h"
#include "sfit_ref_joint.h"
#include "sfit_ref_multi.h"
#include "tt_data.h"

void tt_joint(void);

#define TT_JP 4
#define TT_JC 3
#define TT_JF 80

static const double tt_tpl[TT_JP][3] = {
    {70.0, 40.0, 10.0}, {-75.0, 35.0, 5.0}, {-60.0, -50.0, 30.0}, {65.0, -25.0, -45.0}};
static const double tt_dk[TT_JC][3] = {{30.0, -20.0, -150.0}, {-35.0, 25.0, -260.0},
                                       {45.0, -10.0, -400.0}};
static const double tt_jc[3] = {-80.0, 90.0, -70.0};

static sfit_vec3_t tt_pf[TT_JF][TT_JP], tt_cf[TT_JF][TT_JC];
static double tt_pd[TT_JF][TT_JP][3], tt_cd[TT_JF][TT_JC][3];
static double tt_xs[TT_JC][TT_JF][3];

static void tt_rot(tu_rng_t *g, double maxang, double r[9])
{
    double a[3];
    int k;
    for (k = 0; k < 3; k++) {
        a[k] = tu_rng_gauss(g);
    }
    tu_rot_axis_angle(a, maxang * tu_rng_uniform(g), r);
}

static void tt_make(uint64_t seed, double sigma)
{
    tu_rng_t g;
    size_t f, i;
    tu_rng_seed(&g, seed);
    for (f = 0; f < TT_JF; f++) {
        double rp[9], rq[9], zero[3] = {0.0, 0.0, 0.0};
        tt_rot(&g, TU_PI, rp);
        tt_rot(&g, TU_PI / 3.0, rq);
        for (i = 0; i < TT_JP; i++) {
            double x[3];
            ref_pose_to_global(rp, tt_c, tt_tpl[i], x);
            tu_add_noise(&g, sigma, x);
            tt_store(x, &tt_pf[f][i], tt_pd[f][i]);
        }
        for (i = 0; i < TT_JC; i++) {
            double y[3], x[3];
            int k;
            ref_pose_to_global(rq, zero, tt_dk[i], y);
            for (k = 0; k < 3; k++) {
                y[k] += tt_jc[k];
            }
            ref_pose_to_global(rp, tt_c, y, x);
            tu_add_noise(&g, sigma, x);
            tt_store(x, &tt_cf[f][i], tt_cd[f][i]);
        }
    }
}

static double tt_rot_bound(void)
{
    double a[3][3], w[3], v[3][3];
    size_t i;
    int k, l;
    memset(a, 0, sizeof a);
    for (i = 0; i < TT_JP; i++) { /* the template's centroid is 0 */
        for (k = 0; k < 3; k++) {
            for (l = 0; l < 3; l++) {
                a[k][l] += tt_tpl[i][k] * tt_tpl[i][l];
            }
        }
    }
    ref_sym3_eig((const double (*)[3])a, w, v);
    return 16.0 * TT_EPS * (w[2] / (w[1] + w[0]) + 1.0);
}

static void tt_cluster(sfit_cluster_t *cl)
{
    sfit_vec3_t tv[TT_JP];
    double tpl[TT_JP][3], r[9], t[3], rms, bound = tt_rot_bound();
    sfit_pose_t pose, save;
    sfit_cluster_fit_t fit;
    size_t f, i;
    int k, seen[TT_JP] = {1, 1, 0, 1};

    tt_case("cluster.vs_horn");
    for (i = 0; i < TT_JP; i++) {
        tt_store(tt_tpl[i], &tv[i], tpl[i]);
    }
    TT_EQ_INT(sfit_cluster_init(cl, tv, TT_JP), SFIT_OK);
    for (f = 0; f < 10; f++) {
        if (TT_EQ_INT(sfit_cluster_register(cl, tt_pf[f], TT_JP, &pose, &fit), SFIT_OK)
            && TT_EQ_INT(ref_horn_pose(REF_C3(tpl), REF_C3(tt_pd[f]), NULL, TT_JP, r, t, &rms), 0)) {
            for (k = 0; k < 9; k++) {
                TT_NEAR(pose.r.m[k], r[k], bound);
            }
            for (k = 0; k < 3; k++) {
                TT_NEAR(pose.t.v[k], t[k], 2e-3);
            }
            TT_NEAR(fit.rms, rms, 1e-4 + 1e-3 * rms);
        }
    }

    tt_case("cluster.occluded");
    {
        sfit_vec3_t m[TT_JP];
        memcpy(m, tt_pf[3], sizeof m);
        m[2].v[1] = NAN;
        if (TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP, &pose, &fit), SFIT_OK)
            && TT_EQ_INT(ref_horn_pose(REF_C3(tpl), REF_C3(tt_pd[3]), seen, TT_JP, r, t, NULL), 0)) {
            TT_EQ_INT(fit.used, 3);
            for (k = 0; k < 9; k++) {
                TT_NEAR(pose.r.m[k], r[k], 1e-5); /* 3 markers: worse conditioned */
            }
        }
    }

    tt_case("cluster.reflection");
    {
        sfit_vec3_t m[TT_JP];
        double det;
        for (i = 0; i < TT_JP; i++) {
            m[i] = tv[i];
            m[i].v[0] = -m[i].v[0];
        }
        if (TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP, &pose, &fit), SFIT_OK)) {
            const float *q = pose.r.m;
            det = (double)q[0] * ((double)q[4] * (double)q[8] - (double)q[5] * (double)q[7])
                  - (double)q[1] * ((double)q[3] * (double)q[8] - (double)q[5] * (double)q[6])
                  + (double)q[2] * ((double)q[3] * (double)q[7] - (double)q[4] * (double)q[6]);
            TT_NEAR(det, 1.0, 24.0 * TT_EPS);
            TT_TRUE(fit.rms > 1.0f);
        }
    }

    tt_case("cluster.errors");
    memset(&save, 0x5A, sizeof save);
    pose = save;
    {
        sfit_vec3_t m[TT_JP];
        memcpy(m, tt_pf[0], sizeof m);
        m[0].v[0] = NAN;
        m[1].v[0] = NAN;
        TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP, &pose, NULL), SFIT_E_TOO_FEW);
        m[0].v[0] = INFINITY;
        TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP, &pose, NULL), SFIT_E_NONFINITE);
        memcpy(m, tt_pf[0], sizeof m);
        for (i = 0; i < TT_JP; i++) {
            m[i] = m[0];
            m[i].v[2] += 10.0f * (float)i;
        }
        TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP, &pose, NULL), SFIT_E_DEGENERATE);
        TT_EQ_INT(sfit_cluster_init(cl, m, TT_JP), SFIT_E_DEGENERATE);
        TT_EQ_INT(sfit_cluster_register(NULL, m, TT_JP, &pose, NULL), SFIT_E_ARG);
        TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP - 1, &pose, NULL), SFIT_E_ARG);
    }
    TT_TRUE(memcmp(&pose, &save, sizeof pose) == 0);

    tt_case("cluster.track");
    {
        /* 60 frames at 200 Hz turning at 200 deg/s about a fixed axis, noise
         * 0.5 mm: the tracked pose within the rounding bound of Horn's pose
         * and within twice that of the full solve, proper, from the previous
         * rotation after the first frame (issue 30). */
        static const double axis[3] = {0.3, -0.5, 0.8};
        sfit_cluster_track_t trk;
        tu_rng_t g;
        double rp[9], step[9], tmp[9], xd[TT_JP][3];
        size_t a, b2, l;
        tu_rng_seed(&g, 3030u);
        tt_rot(&g, TU_PI, rp);
        tu_rot_axis_angle(axis, TU_PI / 180.0, step);
        TT_EQ_INT(sfit_cluster_track_reset(&trk), SFIT_OK);
        TT_EQ_INT(sfit_cluster_init(cl, tv, TT_JP), SFIT_OK);
        for (f = 0; f < 60; f++) {
            sfit_vec3_t m[TT_JP];
            sfit_pose_t pf;
            sfit_cluster_fit_t ff;
            for (a = 0; a < 3; a++) {
                for (b2 = 0; b2 < 3; b2++) {
                    tmp[3 * a + b2] = 0.0;
                    for (l = 0; l < 3; l++) {
                        tmp[3 * a + b2] += step[3 * a + l] * rp[3 * l + b2];
                    }
                }
            }
            memcpy(rp, tmp, sizeof rp);
            for (i = 0; i < TT_JP; i++) {
                double x[3];
                ref_pose_to_global(rp, tt_c, tt_tpl[i], x);
                tu_add_noise(&g, 0.5, x);
                tt_store(x, &m[i], xd[i]);
            }
            if (TT_EQ_INT(sfit_cluster_track(cl, &trk, m, TT_JP, &pose, &fit), SFIT_OK)
                && TT_EQ_INT(sfit_cluster_register(cl, m, TT_JP, &pf, &ff), SFIT_OK)
                && TT_EQ_INT(ref_horn_pose(REF_C3(tpl), REF_C3(xd), NULL, TT_JP, r, t, NULL), 0)) {
                const float *q = pose.r.m;
                const double det =
                    (double)q[0] * ((double)q[4] * (double)q[8] - (double)q[5] * (double)q[7])
                    - (double)q[1] * ((double)q[3] * (double)q[8] - (double)q[5] * (double)q[6])
                    + (double)q[2] * ((double)q[3] * (double)q[7] - (double)q[4] * (double)q[6]);
                TT_NEAR(det, 1.0, 24.0 * TT_EPS);
                TT_TRUE((f == 0) ? (trk.steps == 0u) : (trk.steps > 0u));
                for (k = 0; k < 9; k++) {
                    TT_NEAR(pose.r.m[k], r[k], bound);
                    TT_NEAR(pose.r.m[k], pf.r.m[k], 2.0 * bound);
                }
                for (k = 0; k < 3; k++) {
                    TT_NEAR(pose.t.v[k], t[k], 2e-3);
                }
            }
        }
        {
            const unsigned char b = 7u; /* a garbage byte in the bool */
            memcpy(&trk.valid, &b, 1u);
        }
        TT_EQ_INT(sfit_cluster_track(cl, &trk, tt_pf[0], TT_JP, &pose, NULL), SFIT_E_ARG);
    }
}

void tt_joint(void)
{
    static sfit_joint_t j, before;
    sfit_cluster_t cl;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t res;
    double tpl[TT_JP][3], c[3], radii_ref[TT_JC];
    float radii[TT_JC];
    size_t f, i;
    int k;

    tt_make(4242u, 0.5);
    tt_cluster(&cl);
    for (i = 0; i < TT_JP; i++) {
        sfit_vec3_t v;
        tt_store(tt_tpl[i], &v, tpl[i]);
    }

    tt_case("joint.vs_ref");
    cfg.n_child = TT_JC;
    TT_EQ_INT(sfit_joint_init(&j, &cl, &cfg), SFIT_OK);
    for (f = 0; f < TT_JF; f++) {
        double r[9], t[3];
        TT_EQ_INT(sfit_joint_add(&j, tt_pf[f], TT_JP, tt_cf[f], TT_JC, NULL), SFIT_OK);
        (void)ref_horn_pose(REF_C3(tpl), REF_C3(tt_pd[f]), NULL, TT_JP, r, t, NULL);
        for (i = 0; i < TT_JC; i++) {
            ref_pose_to_segment(r, t, tt_cd[f][i], tt_xs[i][f]);
        }
    }
    {
        const double *xs[TT_JC];
        size_t ns[TT_JC];
        for (i = 0; i < TT_JC; i++) {
            xs[i] = &tt_xs[i][0][0];
            ns[i] = TT_JF;
        }
        if (TT_EQ_INT(sfit_joint_fit(&j, &res, radii), SFIT_OK)
            && TT_EQ_INT(ref_fit_multi(xs, ns, TT_JC, NULL, c, radii_ref), 0)) {
            for (k = 0; k < 3; k++) {
                TT_NEAR(res.fit.center.v[k], c[k], 2e-2);
                TT_NEAR(res.fit.center.v[k], tt_jc[k], 3.0); /* truth, loosely */
            }
            for (i = 0; i < TT_JC; i++) {
                TT_NEAR(radii[i], radii_ref[i], 2e-2);
            }
            TT_EQ_INT(res.frames, TT_JF);
        }
    }

    tt_case("joint.center_at");
    {
        sfit_vec3_t cg;
        double r[9], t[3], want[3];
        if (TT_EQ_INT(sfit_joint_center_at(&j, &res, tt_pf[5], TT_JP, &cg, NULL), SFIT_OK)) {
            (void)ref_horn_pose(REF_C3(tpl), REF_C3(tt_pd[5]), NULL, TT_JP, r, t, NULL);
            {
                double cc[3];
                for (k = 0; k < 3; k++) {
                    cc[k] = (double)res.fit.center.v[k];
                }
                ref_pose_to_global(r, t, cc, want);
            }
            for (k = 0; k < 3; k++) {
                TT_NEAR(cg.v[k], want[k], 5e-3);
            }
        }
    }

    tt_case("joint.marker_noise");
    {
        /* per-marker models against the double per-sample ones (same mapped
         * samples tt_xs), the MARKER solve against the double solve with the
         * library's models, and the centre covariance against the double
         * formula (host: test_joint.c test_noise_cov, test_center_cov). */
        static sfit_joint_t jm;
        sfit_multi_noise_t nl[TT_JC];
        sfit_joint_cfg_t cm = cfg;
        sfit_joint_result_t rm;
        sfit_mat3_t cov;
        const double *xs[TT_JC];
        size_t ns[TT_JC];
        double cov9[9 * TT_JC], sk[3 * TT_JC], c9[9], s3[3], want[9], cc[3], big = 0.0;
        cm.noise_model = SFIT_JOINT_NOISE_MARKER;
        cm.solve.fit.noise = SFIT_NOISE_ISO;
        cm.solve.fit.noise_var = 0.25f;
        TT_EQ_INT(sfit_joint_init(&jm, &cl, &cm), SFIT_OK);
        for (f = 0; f < TT_JF; f++) {
            TT_EQ_INT(sfit_joint_add(&jm, tt_pf[f], TT_JP, tt_cf[f], TT_JC, NULL), SFIT_OK);
        }
        if (TT_EQ_INT(sfit_joint_marker_noise(&jm, 0.25f, nl), SFIT_OK)) {
            for (i = 0; i < TT_JC; i++) {
                double bigc = 0.0;
                xs[i] = &tt_xs[i][0][0];
                ns[i] = TT_JF;
                TT_EQ_INT(ref_joint_marker_noise(REF_C3(tpl), TT_JP, xs[i], TT_JF, 0.25, c9, s3), 0);
                for (k = 0; k < 9; k++) {
                    bigc = (c9[k] > bigc) ? c9[k] : (-c9[k] > bigc ? -c9[k] : bigc);
                    cov9[9 * i + (size_t)k] = (double)nl[i].cov.m[k];
                }
                for (k = 0; k < 9; k++) {
                    TT_NEAR(nl[i].cov.m[k], c9[k], 1e-4 * bigc);
                }
                for (k = 0; k < 3; k++) {
                    sk[3 * i + (size_t)k] = (double)nl[i].skew.v[k];
                }
            }
            if (TT_EQ_INT(sfit_joint_fit(&jm, &rm, NULL), SFIT_OK)
                && TT_EQ_INT(ref_fit_multi_noise(xs, ns, TT_JC, cov9, sk, 0, c, NULL, NULL), 0)) {
                for (k = 0; k < 3; k++) {
                    TT_NEAR(rm.fit.center.v[k], c[k], 2e-2);
                    cc[k] = (double)rm.fit.center.v[k];
                }
                if (TT_EQ_INT(sfit_joint_center_cov(&jm, &rm, &tt_pf[0][0], &tt_cf[0][0], TT_JF,
                                                    0.25f, &cov),
                              SFIT_OK)
                    && TT_EQ_INT(ref_joint_center_cov(REF_C3(tpl), TT_JP, xs, TT_JC, TT_JF, cov9,
                                                      cc, NULL, 0.25, want),
                                 0)) {
                    for (k = 0; k < 9; k++) {
                        big = (want[k] > big) ? want[k] : (-want[k] > big ? -want[k] : big);
                    }
                    for (k = 0; k < 9; k++) {
                        TT_NEAR(cov.m[k], want[k], 1e-3 * big);
                    }
                }
                /* the multi-marker formula (independent markers) */
                {
                    sfit_multi_result_t mr;
                    if (TT_EQ_INT(sfit_multi_fit(jm.child, TT_JC, NULL, &mr, NULL), SFIT_OK)
                        && TT_EQ_INT(sfit_multi_center_cov(jm.child, TT_JC, NULL, &mr, 0.25f,
                                                           &cov),
                                     SFIT_OK)) {
                        for (k = 0; k < 3; k++) {
                            cc[k] = (double)mr.center.v[k];
                        }
                        big = 0.0;
                        if (TT_EQ_INT(ref_joint_center_cov(NULL, 0, xs, TT_JC, TT_JF, NULL, cc,
                                                           NULL, 0.25, want),
                                      0)) {
                            for (k = 0; k < 9; k++) {
                                big = (want[k] > big) ? want[k] : (-want[k] > big ? -want[k] : big);
                            }
                            for (k = 0; k < 9; k++) {
                                TT_NEAR(cov.m[k], want[k], 2e-3 * big);
                            }
                        }
                    }
                }
            }
        }
    }

    tt_case("joint.reject_unchanged");
    memcpy(&before, &j, sizeof before);
    {
        sfit_vec3_t p[TT_JP], ch[TT_JC];
        memcpy(p, tt_pf[0], sizeof p);
        memcpy(ch, tt_cf[0], sizeof ch);
        p[0].v[0] = NAN;
        p[1].v[1] = NAN;
        TT_EQ_INT(sfit_joint_add(&j, p, TT_JP, ch, TT_JC, NULL), SFIT_E_TOO_FEW);
        memcpy(p, tt_pf[0], sizeof p);
        ch[1].v[2] = INFINITY;
        TT_EQ_INT(sfit_joint_add(&j, p, TT_JP, ch, TT_JC, NULL), SFIT_E_NONFINITE);
        ch[1].v[2] = 1e30f;
        TT_EQ_INT(sfit_joint_add(&j, p, TT_JP, ch, TT_JC, NULL), SFIT_E_RANGE);
        TT_EQ_INT(sfit_joint_add(&j, p, TT_JP, ch, TT_JC + 1, NULL), SFIT_E_ARG);
        TT_TRUE(memcmp(&before, &j, sizeof j) == 0);
        j.frames = 1u; /* garbage counter */
        TT_EQ_INT(sfit_joint_fit(&j, &res, NULL), SFIT_E_ARG);
    }
}
