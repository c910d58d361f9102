/* SPDX-License-Identifier: MIT */
/**
 * @file test_cluster.c
 * @brief Tests of the rigid-cluster pose (sfit_cluster.h): exact motions,
 * noisy frames against Horn's quaternion method in double
 * (tests/ref/sfit_ref_joint.c), far from the origin, occlusion, the 3-marker
 * (rank-2) and reflection cases, templates from frames, every status.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit/sfit_cluster.h"
#include "sfit_ref.h"
#include "sfit_ref_joint.h"

/* ---------- helpers ---------- */

/* Uniform random rotation (unit quaternion from 4 Gaussians). */
static void rand_rot(tu_rng_t *g, double r[9])
{
    double q[4], n = 0.0;
    int i;
    for (i = 0; i < 4; i++) {
        q[i] = tu_rng_gauss(g);
        n += q[i] * q[i];
    }
    n = sqrt(n);
    for (i = 0; i < 4; i++) {
        q[i] /= n;
    }
    r[0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]);
    r[1] = 2 * (q[1] * q[2] - q[0] * q[3]);
    r[2] = 2 * (q[1] * q[3] + q[0] * q[2]);
    r[3] = 2 * (q[1] * q[2] + q[0] * q[3]);
    r[4] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]);
    r[5] = 2 * (q[2] * q[3] - q[0] * q[1]);
    r[6] = 2 * (q[1] * q[3] - q[0] * q[2]);
    r[7] = 2 * (q[2] * q[3] + q[0] * q[1]);
    r[8] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
}

/* A translation 2-3 m from the origin (mm). */
static void rand_far(tu_rng_t *g, double t[3])
{
    double d[3], n;
    int i;
    for (i = 0; i < 3; i++) {
        d[i] = tu_rng_gauss(g);
    }
    n = tu_norm3(d);
    for (i = 0; i < 3; i++) {
        t[i] = d[i] / n * (2000.0 + 1000.0 * tu_rng_uniform(g));
    }
}

/* Template: m markers in a box of +-60 mm (pelvis-like), not collinear. */
static void rand_template(tu_rng_t *g, size_t m, double (*p)[3])
{
    size_t i;
    int k;
    for (i = 0; i < m; i++) {
        for (k = 0; k < 3; k++) {
            p[i][k] = 120.0 * (tu_rng_uniform(g) - 0.5);
        }
    }
}

static void to_vec(const double (*x)[3], size_t n, sfit_vec3_t *v, double (*xr)[3])
{
    size_t i;
    for (i = 0; i < n; i++) {
        tc_to_vec3(x[i], &v[i]);
        if (xr != NULL) {
            tc_to_double3(&v[i], xr[i]);
        }
    }
}

static double det3(const float *mf)
{
    double m[9];
    int i;
    for (i = 0; i < 9; i++) {
        m[i] = (double)mf[i];
    }
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6])
           + m[2] * (m[3] * m[7] - m[4] * m[6]);
}

static double max_rot_diff(const sfit_mat3_t *a, const double *b)
{
    double d = 0.0;
    int i;
    for (i = 0; i < 9; i++) {
        double e = fabs((double)a->m[i] - b[i]);
        if (e > d) {
            d = e;
        }
    }
    return d;
}

/*
 * Rounding bound of a registered rotation: the Newton-refined rotation is
 * accurate to about eps * s1 / (s2 + s3), s_k the template scatter's
 * eigenvalues (singular values of H for a rigid motion). Tolerance:
 * 16 eps (s1 / (s2 + s3) + 1); the worst ratio error/bound seen over the
 * tests below is printed.
 */
static double g_worst_ratio;
static double rot_bound(const double (*tpl)[3], const int *seen, size_t m)
{
    double c[3] = {0, 0, 0}, a[3][3], w[3], v[3][3];
    size_t i, n = 0;
    int k, l;
    memset(a, 0, sizeof a);
    for (i = 0; i < m; i++) {
        if (seen == NULL || seen[i]) {
            for (k = 0; k < 3; k++) {
                c[k] += tpl[i][k];
            }
            n++;
        }
    }
    for (k = 0; k < 3; k++) {
        c[k] /= (double)n;
    }
    for (i = 0; i < m; i++) {
        if (seen == NULL || seen[i]) {
            for (k = 0; k < 3; k++) {
                for (l = 0; l < 3; l++) {
                    a[k][l] += (tpl[i][k] - c[k]) * (tpl[i][l] - c[l]);
                }
            }
        }
    }
    ref_sym3_eig((const double (*)[3])a, w, v);
    return 16.0 * TC_FEPS * (w[2] / (w[1] + w[0]) + 1.0);
}

static void assert_rot_near(const sfit_mat3_t *r, const double *rr, const double (*tpl)[3],
                            const int *seen, size_t m)
{
    const double d = max_rot_diff(r, rr), b = rot_bound(tpl, seen, m);
    if (d / b > g_worst_ratio) {
        g_worst_ratio = d / b;
    }
    if (!(d <= b)) {
        print_error("rotation differs from the double oracle by %.3g > bound %.3g\n", d, b);
        fail();
    }
}

/* |R^T R - I| max entry, and det. */
static void assert_proper(const sfit_mat3_t *r)
{
    int i, j, k;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += (double)r->m[3 * k + i] * (double)r->m[3 * k + j];
            }
            assert_near(s, i == j ? 1.0 : 0.0, 16.0 * TC_FEPS, "R^T R");
        }
    }
    assert_near(det3(r->m), 1.0, 24.0 * TC_FEPS, "det R");
}

/* Measured = R p + t (+ noise), returned in float and in its double image. */
static void make_frame(tu_rng_t *g, const double (*p)[3], size_t m, const double r[9],
                       const double t[3], double sigma, sfit_vec3_t *v, double (*xd)[3])
{
    double x[SFIT_CLUSTER_MAX_MARKERS][3];
    size_t i;
    for (i = 0; i < m; i++) {
        ref_pose_to_global(r, t, p[i], x[i]);
        if (sigma > 0.0) {
            tu_add_noise(g, sigma, x[i]);
        }
    }
    to_vec((const double (*)[3])x, m, v, xd);
}

/* ---------- tests ---------- */

/* The double oracle itself: exact motions recovered to 1e-12. */
static void test_ref_horn_exact(void **state)
{
    tu_rng_t g;
    double p[4][3], x[4][3], r[9], t[3], rr[9], tt[3], rms;
    size_t i;
    int k, trial;
    (void)state;
    tu_rng_seed(&g, 11);
    for (trial = 0; trial < 50; trial++) {
        rand_template(&g, 4, p);
        rand_rot(&g, r);
        rand_far(&g, t);
        for (i = 0; i < 4; i++) {
            ref_pose_to_global(r, t, p[i], x[i]);
        }
        assert_int_equal(ref_horn_pose((const double (*)[3])p, (const double (*)[3])x, NULL, 4,
                                       rr, tt, &rms), 0);
        for (k = 0; k < 9; k++) {
            assert_near(rr[k], r[k], 1e-12, "ref R");
        }
        assert_vec3_near(tt, t, 1e-9, "ref t");
        assert_true(rms < 1e-9);
    }
}

/* Noise-free rigid motions 2-3 m from the origin: R to a few float
 * epsilons, t to the float resolution of 3 m (2.4e-4 mm) times a few. */
static void test_exact_far(void **state)
{
    tu_rng_t g;
    double p[6][3], r[9], t[3];
    sfit_vec3_t tv[6], mv[6];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    size_t m;
    int trial;
    (void)state;
    int skipped = 0;
    tu_rng_seed(&g, 12);
    for (trial = 0; trial < 200; trial++) {
        double tpl[6][3];
        m = 3u + (size_t)(trial % 4);
        rand_template(&g, m, p);
        to_vec((const double (*)[3])p, m, tv, tpl);
        if (sfit_cluster_init(&cl, tv, m) != SFIT_OK) {
            skipped++; /* a random triangle can be nearly flat */
            continue;
        }
        rand_rot(&g, r);
        rand_far(&g, t);
        make_frame(&g, (const double (*)[3])tpl, m, r, t, 0.0, mv, NULL);
        assert_int_equal(sfit_cluster_register(&cl, mv, m, &pose, &fit), SFIT_OK);
        assert_proper(&pose.r);
        /* vs the truth: the inputs are rounded to float (1.2e-4 mm at 3 m) */
        assert_true(max_rot_diff(&pose.r, r) < 2e-5);
        assert_vec3_near(pose.t.v, t, 2e-3, "t");
        {
            double xd[6][3], rr[9], tt[3];
            make_frame(&g, (const double (*)[3])tpl, m, r, t, 0.0, mv, xd);
            assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd,
                                           NULL, m, rr, tt, NULL), 0);
            assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, NULL, m);
        }
        assert_int_equal(fit.used, m);
        assert_true(fit.rms < 1e-3f); /* float rounding of 3 m coordinates */
    }
    assert_true(skipped < 5);
}

/* Noisy frames (sigma 0.5 mm): the float pose equals Horn's double pose on
 * the same float inputs to rounding. Measured max differences: R 5e-7,
 * t 5e-4 mm (resolution of a 3 m float 2.4e-4 mm); tolerances 4x that. */
static void test_noisy_vs_ref(void **state)
{
    tu_rng_t g;
    double p[8][3], tpl[8][3], xd[8][3], r[9], t[3], rr[9], tt[3], rms, dr = 0.0, dt = 0.0;
    sfit_vec3_t tv[8], mv[8];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    size_t m;
    int trial, k;
    (void)state;
    tu_rng_seed(&g, 13);
    for (trial = 0; trial < 500; trial++) {
        m = 3u + (size_t)(trial % 6);
        rand_template(&g, m, p);
        to_vec((const double (*)[3])p, m, tv, tpl);
        assert_int_equal(sfit_cluster_init(&cl, tv, m), SFIT_OK);
        rand_rot(&g, r);
        rand_far(&g, t);
        make_frame(&g, (const double (*)[3])tpl, m, r, t, 0.5, mv, xd);
        assert_int_equal(sfit_cluster_register(&cl, mv, m, &pose, &fit), SFIT_OK);
        assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd, NULL,
                                       m, rr, tt, &rms), 0);
        assert_proper(&pose.r);
        assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, NULL, m);
        if (max_rot_diff(&pose.r, rr) > dr) {
            dr = max_rot_diff(&pose.r, rr);
        }
        for (k = 0; k < 3; k++) {
            if (fabs((double)pose.t.v[k] - tt[k]) > dt) {
                dt = fabs((double)pose.t.v[k] - tt[k]);
            }
        }
        assert_near(fit.rms, rms, 1e-4 + 1e-3 * rms, "rms");
    }
    printf("  pose vs Horn (double): max |dR| %.3g, max |dt| %.3g mm\n", dr, dt);
    printf("  worst error / rounding bound so far: %.3f\n", g_worst_ratio);
    assert_true(dt < 2e-3);
}

/* The same cluster near the origin and 3 m away: the far pose is as
 * accurate (relative to the double oracle) as the near one, up to the
 * representation of the far coordinates. */
static void test_far_as_good_as_near(void **state)
{
    tu_rng_t g;
    double p[4][3], tpl[4][3], xd[4][3], r[9], t0[3] = {1.0, -2.0, 3.0}, tf[3] = {2100.0, -1800.0, 1500.0};
    double rr[9], tt[3], worst_near = 0.0, worst_far = 0.0;
    sfit_vec3_t tv[4], mv[4];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    int trial, which;
    (void)state;
    tu_rng_seed(&g, 14);
    for (trial = 0; trial < 300; trial++) {
        rand_template(&g, 4, p);
        to_vec((const double (*)[3])p, 4, tv, tpl);
        assert_int_equal(sfit_cluster_init(&cl, tv, 4), SFIT_OK);
        rand_rot(&g, r);
        for (which = 0; which < 2; which++) {
            double d;
            make_frame(&g, (const double (*)[3])tpl, 4, r, which ? tf : t0, 0.3, mv, xd);
            assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, NULL), SFIT_OK);
            assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd,
                                           NULL, 4, rr, tt, NULL), 0);
            assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, NULL, 4);
            d = max_rot_diff(&pose.r, rr);
            if (which) {
                worst_far = d > worst_far ? d : worst_far;
            } else {
                worst_near = d > worst_near ? d : worst_near;
            }
        }
    }
    printf("  rotation error vs double: near %.3g, far %.3g\n", worst_near, worst_far);
    /* Centring removes the 3 m: within a factor 4 of the near case. */
    assert_true(worst_far < 4.0 * worst_near + 1e-7);
}

/* A regular tetrahedron (H^T H has three equal eigenvalues) and a square
 * (two equal, one zero): the pose is still exact. */
static void test_symmetric_clusters(void **state)
{
    static const double tet[4][3] = {{50, 50, 50}, {50, -50, -50}, {-50, 50, -50}, {-50, -50, 50}};
    static const double sq[4][3] = {{60, 0, 0}, {0, 60, 0}, {-60, 0, 0}, {0, -60, 0}};
    const double (*shapes[2])[3] = {tet, sq};
    tu_rng_t g;
    double r[9], t[3], tpl[4][3], xd[4][3], rr[9], tt[3];
    sfit_vec3_t tv[4], mv[4];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    int s, trial;
    (void)state;
    tu_rng_seed(&g, 15);
    for (s = 0; s < 2; s++) {
        to_vec(shapes[s], 4, tv, tpl);
        assert_int_equal(sfit_cluster_init(&cl, tv, 4), SFIT_OK);
        for (trial = 0; trial < 100; trial++) {
            rand_rot(&g, r);
            rand_far(&g, t);
            make_frame(&g, (const double (*)[3])tpl, 4, r, t, trial % 2 ? 0.2 : 0.0, mv, xd);
            assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, NULL), SFIT_OK);
            assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd,
                                           NULL, 4, rr, tt, NULL), 0);
            assert_proper(&pose.r);
            assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, NULL, 4);
            assert_vec3_near(pose.t.v, tt, 2e-3, "t");
        }
    }
}

/* Occlusion: a NaN marker is skipped; the pose equals the oracle on the
 * markers seen. */
static void test_occluded(void **state)
{
    tu_rng_t g;
    double p[6][3], tpl[6][3], xd[6][3], r[9], t[3], rr[9], tt[3];
    sfit_vec3_t tv[6], mv[6];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    int seen[6], trial, i;
    (void)state;
    tu_rng_seed(&g, 16);
    for (trial = 0; trial < 200; trial++) {
        int hide1 = trial % 6, hide2 = (trial / 6) % 6;
        rand_template(&g, 6, p);
        to_vec((const double (*)[3])p, 6, tv, tpl);
        assert_int_equal(sfit_cluster_init(&cl, tv, 6), SFIT_OK);
        rand_rot(&g, r);
        rand_far(&g, t);
        make_frame(&g, (const double (*)[3])tpl, 6, r, t, 0.5, mv, xd);
        for (i = 0; i < 6; i++) {
            seen[i] = (i != hide1 && i != hide2);
        }
        mv[hide1].v[trial % 3] = NAN;
        mv[hide2].v[0] = NAN;
        assert_int_equal(sfit_cluster_register(&cl, mv, 6, &pose, &fit), SFIT_OK);
        assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd, seen,
                                       6, rr, tt, NULL), 0);
        assert_int_equal(fit.used, hide1 == hide2 ? 5 : 4);
        assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, seen, 6);
        assert_vec3_near(pose.t.v, tt, 2e-3, "t");
    }
}

/* Reflection: the measured markers are the mirror image of the template
 * (det H < 0). The library must return the best proper rotation (as
 * Horn's method does), never the reflection. */
static void test_reflection(void **state)
{
    tu_rng_t g;
    double p[5][3], tpl[5][3], x[5][3], xd[5][3], r[9], t[3], rr[9], tt[3], rms;
    sfit_vec3_t tv[5], mv[5];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    int trial, i;
    (void)state;
    tu_rng_seed(&g, 17);
    for (trial = 0; trial < 100; trial++) {
        size_t m = 4u + (size_t)(trial % 2);
        rand_template(&g, m, p);
        to_vec((const double (*)[3])p, m, tv, tpl);
        assert_int_equal(sfit_cluster_init(&cl, tv, m), SFIT_OK);
        rand_rot(&g, r);
        rand_far(&g, t);
        for (i = 0; i < (int)m; i++) {
            double mir[3] = {-tpl[i][0], tpl[i][1], tpl[i][2]};
            ref_pose_to_global(r, t, mir, x[i]);
        }
        to_vec((const double (*)[3])x, m, mv, xd);
        assert_int_equal(sfit_cluster_register(&cl, mv, m, &pose, &fit), SFIT_OK);
        assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd, NULL,
                                       m, rr, tt, &rms), 0);
        assert_proper(&pose.r);
        /* Not a perfect fit (a reflection cannot be matched), same optimum. */
        assert_true(rms > 1.0);
        assert_near(fit.rms, rms, 1e-4 * rms, "rms");
        assert_true(max_rot_diff(&pose.r, rr) < 1e-5); /* measured max 7.8e-7 */
    }
}

/* 3 markers: H has rank 2 (the third singular value is 0). */
static void test_three_markers(void **state)
{
    tu_rng_t g;
    double p[3][3], tpl[3][3], xd[3][3], r[9], t[3], rr[9], tt[3];
    sfit_vec3_t tv[3], mv[3];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    int trial;
    (void)state;
    tu_rng_seed(&g, 18);
    for (trial = 0; trial < 300; trial++) {
        rand_template(&g, 3, p);
        to_vec((const double (*)[3])p, 3, tv, tpl);
        if (sfit_cluster_init(&cl, tv, 3) != SFIT_OK) {
            continue; /* a random triangle can be nearly flat */
        }
        rand_rot(&g, r);
        rand_far(&g, t);
        make_frame(&g, (const double (*)[3])tpl, 3, r, t, trial % 2 ? 0.5 : 0.0, mv, xd);
        assert_int_equal(sfit_cluster_register(&cl, mv, 3, &pose, NULL), SFIT_OK);
        assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd, NULL,
                                       3, rr, tt, NULL), 0);
        assert_proper(&pose.r);
        assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, NULL, 3);
    }
}

/* Mapping into the segment frame and back. */
static void test_pose_maps(void **state)
{
    tu_rng_t g;
    double r[9], t[3], x[3], xs_ref[3];
    sfit_pose_t pose;
    sfit_vec3_t xg, xs, back;
    int i, trial;
    (void)state;
    tu_rng_seed(&g, 19);
    for (trial = 0; trial < 100; trial++) {
        rand_rot(&g, r);
        rand_far(&g, t);
        for (i = 0; i < 9; i++) {
            pose.r.m[i] = (float)r[i];
        }
        tc_to_vec3(t, &pose.t);
        tc_to_double3(&pose.t, t);
        for (i = 0; i < 9; i++) {
            r[i] = (double)pose.r.m[i];
        }
        for (i = 0; i < 3; i++) {
            x[i] = t[i] + 300.0 * (tu_rng_uniform(&g) - 0.5);
        }
        tc_to_vec3(x, &xg);
        tc_to_double3(&xg, x);
        assert_int_equal(sfit_cluster_to_segment(&pose, &xg, &xs), SFIT_OK);
        ref_pose_to_segment(r, t, x, xs_ref);
        assert_vec3_near(xs.v, xs_ref, 1e-4, "to_segment");
        assert_int_equal(sfit_cluster_to_global(&pose, &xs, &back), SFIT_OK);
        assert_vec3_near(back.v, xg.v, 1e-3, "round trip");
        /* aliasing */
        back = xg;
        assert_int_equal(sfit_cluster_to_segment(&pose, &back, &back), SFIT_OK);
        assert_memory_equal(&back, &xs, sizeof back);
    }
    assert_int_equal(sfit_cluster_to_global(NULL, &xs, &back), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_to_global(&pose, NULL, &back), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_to_global(&pose, &xs, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_to_segment(NULL, &xs, &back), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_to_segment(&pose, NULL, &back), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_to_segment(&pose, &xs, NULL), SFIT_E_ARG);
}

/* Template from one frame: origin at the centroid, lab axes; registering
 * that same frame gives R = I and t = centroid. */
static void test_from_frame(void **state)
{
    tu_rng_t g;
    double p[5][3], r[9], t[3], c[3] = {0, 0, 0}, xd[5][3];
    sfit_vec3_t mv[5];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    int i, k;
    (void)state;
    tu_rng_seed(&g, 20);
    rand_template(&g, 5, p);
    rand_rot(&g, r);
    rand_far(&g, t);
    make_frame(&g, (const double (*)[3])p, 5, r, t, 0.0, mv, xd);
    assert_int_equal(sfit_cluster_from_frame(&cl, mv, 5), SFIT_OK);
    for (i = 0; i < 5; i++) {
        for (k = 0; k < 3; k++) {
            c[k] += xd[i][k] / 5.0;
        }
    }
    for (i = 0; i < 5; i++) {
        double e[3];
        for (k = 0; k < 3; k++) {
            e[k] = xd[i][k] - c[k];
        }
        assert_vec3_near(cl.pos[i].v, e, 5e-4, "centred template");
    }
    assert_int_equal(sfit_cluster_register(&cl, mv, 5, &pose, NULL), SFIT_OK);
    for (k = 0; k < 9; k++) {
        assert_near(pose.r.m[k], k % 4 == 0 ? 1.0 : 0.0, 4.0 * TC_FEPS, "R = I");
    }
    assert_vec3_near(pose.t.v, c, 5e-4, "t = centroid");
}

/* Template averaged over noisy frames: its inter-marker distances approach
 * the truth as sigma / sqrt(F) (F = 400 frames, sigma = 1 mm: the error of
 * a distance has sd about sigma sqrt(2 / F) = 0.07 mm; tolerance 0.25 mm),
 * while a single frame is off by about sigma. Occluded markers and
 * unregistrable frames are skipped. */
static void test_from_frames(void **state)
{
    enum { F = 400, M = 5 };
    static sfit_vec3_t frames[F * M];
    tu_rng_t g;
    double p[M][3], r[9], t[3];
    sfit_cluster_t cl;
    size_t used, f;
    int i, j;
    (void)state;
    tu_rng_seed(&g, 21);
    rand_template(&g, M, p);
    for (f = 0; f < F; f++) {
        rand_rot(&g, r);
        rand_far(&g, t);
        make_frame(&g, (const double (*)[3])p, M, r, t, 1.0, &frames[f * M], NULL);
    }
    frames[0].v[1] = NAN; /* frame 0 incomplete: the reference is frame 1 */
    frames[7 * M + 2].v[0] = NAN; /* frame 7: marker 2 occluded */
    for (i = 0; i < 3; i++) { /* frame 9: only 2 seen -> skipped */
        frames[9 * M + i].v[2] = NAN;
    }
    assert_int_equal(sfit_cluster_from_frames(&cl, frames, F, M, &used), SFIT_OK);
    assert_int_equal(used, F - 2);
    for (i = 0; i < M; i++) {
        for (j = i + 1; j < M; j++) {
            double dt = tu_dist3(p[i], p[j]), de[3], ds;
            tc_to_double3(&cl.pos[i], de);
            {
                double dj[3];
                tc_to_double3(&cl.pos[j], dj);
                ds = tu_dist3(de, dj);
            }
            assert_near(ds, dt, 0.25, "averaged distance");
        }
    }
    /* Centroid at the origin. */
    {
        double c[3] = {0, 0, 0};
        for (i = 0; i < M; i++) {
            for (j = 0; j < 3; j++) {
                c[j] += (double)cl.pos[i].v[j];
            }
        }
        for (j = 0; j < 3; j++) {
            assert_near(c[j], 0.0, 1e-3, "centroid");
        }
    }
    /* No complete frame at all. */
    for (f = 0; f < F; f++) {
        frames[f * M + 4].v[0] = NAN;
    }
    assert_int_equal(sfit_cluster_from_frames(&cl, frames, F, M, NULL), SFIT_E_TOO_FEW);
}

/* Every failure status, outputs untouched. */
static void test_statuses(void **state)
{
    static const double good[4][3] = {{0, 0, 0}, {100, 0, 0}, {0, 80, 0}, {0, 0, 60}};
    static const double line[4][3] = {{0, 0, 0}, {100, 0, 0}, {50, 0, 0}, {-30, 0, 0}};
    /* 3 collinear + 1 off the line. */
    static const double tee[4][3] = {{0, 0, 0}, {100, 0, 0}, {50, 0, 0}, {50, 70, 0}};
    sfit_vec3_t tv[4], mv[4], lv[4];
    sfit_cluster_t cl, cl2, sent_cl;
    sfit_pose_t pose, sent;
    sfit_cluster_fit_t fit, sent_fit;
    (void)state;
    memset(&sent, 0xA5, sizeof sent);
    memset(&sent_fit, 0xA5, sizeof sent_fit);
    memset(&sent_cl, 0xA5, sizeof sent_cl);
    to_vec(good, 4, tv, NULL);
    to_vec(line, 4, lv, NULL);

    /* init / from_frame arguments */
    cl = sent_cl;
    assert_int_equal(sfit_cluster_init(NULL, tv, 4), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_init(&cl, NULL, 4), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_init(&cl, tv, 2), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_init(&cl, tv, SFIT_CLUSTER_MAX_MARKERS + 1u), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_init(&cl, lv, 4), SFIT_E_DEGENERATE);
    assert_int_equal(sfit_cluster_from_frame(&cl, lv, 4), SFIT_E_DEGENERATE);
    assert_int_equal(sfit_cluster_from_frame(NULL, tv, 4), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_from_frame(&cl, tv, 0), SFIT_E_ARG);
    mv[0] = tv[0]; mv[1] = tv[1]; mv[2] = tv[2]; mv[3] = tv[3];
    mv[0] = mv[1];
    mv[2] = mv[1];
    mv[3] = mv[1];
    assert_int_equal(sfit_cluster_init(&cl, mv, 4), SFIT_E_DEGENERATE); /* coincident */
    mv[0] = tv[0]; mv[2] = tv[2]; mv[3] = tv[3];
    mv[2].v[1] = NAN;
    assert_int_equal(sfit_cluster_init(&cl, mv, 4), SFIT_E_NONFINITE);
    assert_int_equal(sfit_cluster_from_frame(&cl, mv, 4), SFIT_E_NONFINITE);
    mv[2].v[1] = INFINITY;
    assert_int_equal(sfit_cluster_init(&cl, mv, 4), SFIT_E_NONFINITE);
    mv[2].v[1] = 3e38f;
    assert_int_equal(sfit_cluster_init(&cl, mv, 4), SFIT_E_RANGE);
    assert_int_equal(sfit_cluster_from_frames(&cl, NULL, 1, 4, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_from_frames(&cl, tv, 0, 4, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_from_frames(&cl, tv, 1, 1, NULL), SFIT_E_ARG);
    assert_memory_equal(&cl, &sent_cl, sizeof cl);

    assert_int_equal(sfit_cluster_init(&cl, tv, 4), SFIT_OK);
    mv[0] = tv[0]; mv[1] = tv[1]; mv[2] = tv[2]; mv[3] = tv[3];
    pose = sent;
    fit = sent_fit;
    assert_int_equal(sfit_cluster_register(NULL, mv, 4, &pose, &fit), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_register(&cl, NULL, 4, &pose, &fit), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_register(&cl, mv, 4, NULL, &fit), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_register(&cl, mv, 3, &pose, &fit), SFIT_E_ARG);
    /* garbage template counters and contents */
    cl2 = cl;
    cl2.count = 0;
    assert_int_equal(sfit_cluster_register(&cl2, mv, 0, &pose, &fit), SFIT_E_ARG);
    cl2.count = 0xFFFFFFFFu;
    assert_int_equal(sfit_cluster_register(&cl2, mv, 4, &pose, &fit), SFIT_E_ARG);
    cl2 = cl;
    cl2.pos[1].v[1] = NAN;
    assert_int_equal(sfit_cluster_register(&cl2, mv, 4, &pose, &fit), SFIT_E_ARG);
    /* too few seen */
    mv[0].v[0] = NAN;
    mv[3].v[2] = NAN;
    assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, &fit), SFIT_E_TOO_FEW);
    mv[0] = tv[0]; mv[3] = tv[3];
    /* Inf is an error, not an occlusion */
    mv[1].v[2] = -INFINITY;
    assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, &fit), SFIT_E_NONFINITE);
    mv[1] = tv[1];
    mv[1].v[0] = 2e9f;
    assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, &fit), SFIT_E_RANGE);
    mv[0].v[0] = NAN; /* status rule: TOO_FEW before RANGE */
    mv[3].v[0] = NAN;
    assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, &fit), SFIT_E_TOO_FEW);
    mv[0] = tv[0];
    mv[3] = tv[3];
    mv[1] = tv[1];
    /* measured markers collinear */
    assert_int_equal(sfit_cluster_register(&cl, lv, 4, &pose, &fit), SFIT_E_DEGENERATE);
    /* measured coincident */
    mv[0] = mv[1]; mv[2] = mv[1]; mv[3] = mv[1];
    assert_int_equal(sfit_cluster_register(&cl, mv, 4, &pose, &fit), SFIT_E_DEGENERATE);
    /* template fine, but the markers seen are collinear (the off-line one hidden) */
    to_vec(tee, 4, mv, NULL);
    assert_int_equal(sfit_cluster_init(&cl2, mv, 4), SFIT_OK);
    assert_int_equal(sfit_cluster_register(&cl2, mv, 4, &pose, &fit), SFIT_OK);
    pose = sent;
    fit = sent_fit;
    mv[3].v[0] = NAN;
    assert_int_equal(sfit_cluster_register(&cl2, mv, 4, &pose, &fit), SFIT_E_DEGENERATE);
    assert_memory_equal(&pose, &sent, sizeof pose);
    assert_memory_equal(&fit, &sent_fit, sizeof fit);
    /* fit may be NULL */
    assert_int_equal(sfit_cluster_register(&cl, tv, 4, &pose, NULL), SFIT_OK);
}

/* Huge but in-range coordinates (2^26) and tiny clusters: a result or a
 * status, never a NaN. */
static void test_extremes(void **state)
{
    tu_rng_t g;
    double p[4][3], r[9], t[3];
    sfit_vec3_t tv[4], mv[4];
    sfit_cluster_t cl;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    int trial, k;
    (void)state;
    tu_rng_seed(&g, 22);
    for (trial = 0; trial < 200; trial++) {
        double scale = pow(10.0, -6.0 + 12.0 * tu_rng_uniform(&g));
        sfit_status_t st;
        size_t i;
        rand_template(&g, 4, p);
        for (i = 0; i < 4; i++) {
            for (k = 0; k < 3; k++) {
                p[i][k] *= scale;
            }
        }
        to_vec((const double (*)[3])p, 4, tv, NULL);
        st = sfit_cluster_init(&cl, tv, 4);
        if (st != SFIT_OK) {
            assert_true(st == SFIT_E_DEGENERATE || st == SFIT_E_RANGE);
            continue;
        }
        rand_rot(&g, r);
        rand_far(&g, t);
        for (k = 0; k < 3; k++) {
            t[k] *= (trial % 3 == 0) ? 2e4 : 1.0;
        }
        make_frame(&g, (const double (*)[3])p, 4, r, t, 0.0, mv, NULL);
        st = sfit_cluster_register(&cl, mv, 4, &pose, &fit);
        if (st == SFIT_OK) {
            for (k = 0; k < 9; k++) {
                assert_true(isfinite(pose.r.m[k]));
            }
            assert_proper(&pose.r);
            assert_true(isfinite(fit.rms));
        } else {
            assert_true(st == SFIT_E_DEGENERATE || st == SFIT_E_RANGE);
        }
    }
}

/* ---------- tracking from the previous frame (sfit_cluster_track) ---------- */

/* r := exp([w]x) r (a rotation vector w, rad, applied in the global frame). */
static void rot_step(const double w[3], double r[9])
{
    const double th = tu_norm3(w);
    double k[3] = {0, 0, 0}, e[9], out[9];
    int i, j, l;
    if (th > 0.0) {
        for (i = 0; i < 3; i++) {
            k[i] = w[i] / th;
        }
    }
    {
        const double c = cos(th), s = sin(th), v = 1.0 - c;
        e[0] = c + k[0] * k[0] * v;
        e[1] = k[0] * k[1] * v - k[2] * s;
        e[2] = k[0] * k[2] * v + k[1] * s;
        e[3] = k[1] * k[0] * v + k[2] * s;
        e[4] = c + k[1] * k[1] * v;
        e[5] = k[1] * k[2] * v - k[0] * s;
        e[6] = k[2] * k[0] * v - k[1] * s;
        e[7] = k[2] * k[1] * v + k[0] * s;
        e[8] = c + k[2] * k[2] * v;
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double sum = 0.0;
            for (l = 0; l < 3; l++) {
                sum += e[3 * i + l] * r[3 * l + j];
            }
            out[3 * i + j] = sum;
        }
    }
    memcpy(r, out, sizeof out);
}

/* Translation bound matching rot_bound(): |dt| <= b |p_bar| sqrt(3) + 8 eps
 * (|x_bar| + |p_bar|) per solver (the rotation error carried to the template
 * centroid, plus the rounding of t = x_bar - R p_bar). */
static double trans_bound(double b, const double (*tpl)[3], const double (*x)[3], const int *seen,
                          size_t m)
{
    double pb[3] = {0, 0, 0}, xb[3] = {0, 0, 0};
    size_t i, n = 0;
    int k;
    for (i = 0; i < m; i++) {
        if (seen[i]) {
            for (k = 0; k < 3; k++) {
                pb[k] += tpl[i][k];
                xb[k] += x[i][k];
            }
            n++;
        }
    }
    for (k = 0; k < 3; k++) {
        pb[k] /= (double)n;
        xb[k] /= (double)n;
    }
    return b * tu_norm3(pb) * sqrt(3.0) + 8.0 * TC_FEPS * (tu_norm3(xb) + tu_norm3(pb));
}

/*
 * Issue 30: 10^4 random frame sequences at 200 Hz (smooth motion: angular
 * velocity up to 600 deg/s with angular acceleration, translation 1-3 m
 * from the origin moving up to 2 m/s; noise 0 - 1 mm; a marker occluded
 * now and then; gaps of 1-5 frames with every marker lost). Every frame:
 * the tracked pose and the full solve (sfit_cluster_register) have the same
 * status; each is a proper rotation, each is within the rounding bound
 * rot_bound() (16 eps (s1/(s2+s3) + 1), from float epsilon and the
 * conditioning of the template scatter) of Horn's double pose on the same
 * float inputs, so the two differ by at most twice that bound; the
 * translations likewise (trans_bound()). The tracked path must carry most
 * frames; after a gap the full solve runs.
 */
static void test_track_sequences(void **state)
{
    enum { NSEQ = 10000, NFRAME = 24 };
    tu_rng_t g;
    double worst_dr = 0.0, worst_dt = 0.0, worst_ratio = 0.0;
    long frames = 0, tracked = 0, full = 0, gaps = 0, gave_up = 0, steps_hist[SFIT_CLUSTER_TRACK_STEPS + 1];
    int seq;
    (void)state;
    memset(steps_hist, 0, sizeof steps_hist);
    tu_rng_seed(&g, 3030);
    for (seq = 0; seq < NSEQ; seq++) {
        double p[6][3], tpl[6][3], r[9], t[3], w[3], v[3], dw[3], sigma, dist, dir[3];
        sfit_vec3_t tv[6];
        sfit_cluster_t cl;
        sfit_cluster_track_t tr;
        const size_t m = 3u + (size_t)(tu_rng_u64(&g) % 4u);
        int f, k, gap_left = 0, after_gap = 1;
        rand_template(&g, m, p);
        to_vec((const double (*)[3])p, m, tv, tpl);
        if (sfit_cluster_init(&cl, tv, m) != SFIT_OK) {
            continue; /* a nearly collinear random triangle */
        }
        rand_rot(&g, r);
        for (k = 0; k < 3; k++) {
            dir[k] = tu_rng_gauss(&g);
        }
        dist = 1000.0 + 2000.0 * tu_rng_uniform(&g);
        for (k = 0; k < 3; k++) {
            t[k] = dir[k] / tu_norm3(dir) * dist;
        }
        {
            /* angular velocity: up to 600 deg/s = 3 deg per 5 ms frame */
            const double speed = (3.0 * TU_PI / 180.0) * tu_rng_uniform(&g);
            for (k = 0; k < 3; k++) {
                w[k] = tu_rng_gauss(&g);
                v[k] = 10.0 * (2.0 * tu_rng_uniform(&g) - 1.0) / sqrt(3.0); /* <= 10 mm/frame */
            }
            dist = tu_norm3(w);
            for (k = 0; k < 3; k++) {
                w[k] *= speed / dist;
            }
        }
        sigma = (double)(tu_rng_u64(&g) % 5u) * 0.25;
        assert_int_equal(sfit_cluster_track_reset(&tr), SFIT_OK);
        for (f = 0; f < NFRAME; f++) {
            double xd[6][3], rr[9], tt[3], b, bt, d, dt = 0.0;
            sfit_vec3_t mv[6];
            sfit_pose_t pt, pf;
            sfit_cluster_fit_t ft, ff;
            int seen[6];
            sfit_status_t st, sf;
            size_t i, nseen = 0;
            /* smooth motion: small angular acceleration */
            for (k = 0; k < 3; k++) {
                dw[k] = 2e-3 * tu_rng_gauss(&g);
                w[k] += dw[k];
            }
            rot_step(w, r);
            for (k = 0; k < 3; k++) {
                t[k] += v[k];
            }
            make_frame(&g, (const double (*)[3])tpl, m, r, t, sigma, mv, xd);
            if (gap_left == 0 && tu_rng_uniform(&g) < 0.02) {
                gap_left = 1 + (int)(tu_rng_u64(&g) % 5u);
            }
            for (i = 0; i < m; i++) {
                seen[i] = gap_left == 0;
                if (seen[i] && m > 3u && tu_rng_uniform(&g) < 0.03) {
                    seen[i] = 0; /* one marker occluded */
                }
                if (!seen[i]) {
                    mv[i].v[0] = mv[i].v[1] = mv[i].v[2] = NAN;
                }
                nseen += (size_t)seen[i];
            }
            if (gap_left > 0) {
                gap_left--;
            }
            memset(&pt, 0, sizeof pt);
            st = sfit_cluster_track(&cl, &tr, mv, m, &pt, &ft);
            sf = sfit_cluster_register(&cl, mv, m, &pf, &ff);
            assert_int_equal(st, sf);
            frames++;
            if (st == SFIT_E_TOO_FEW) {
                assert_true(nseen < 3u);
                assert_int_equal(tr.valid, 0);
                gaps++;
                after_gap = 1;
                continue;
            }
            if (st != SFIT_OK) {
                /* a nearly collinear triangle left by an occlusion: both agree */
                assert_int_equal(st, SFIT_E_DEGENERATE);
                continue;
            }
            assert_true(tr.steps <= (uint32_t)SFIT_CLUSTER_TRACK_STEPS);
            steps_hist[tr.steps]++;
            if (after_gap) {
                assert_int_equal(tr.steps, 0); /* the full solve at the start and after a gap */
            } else if (tr.steps == 0u) {
                gave_up++; /* the convergence test failed: the full solve */
            }
            after_gap = 0;
            if (tr.steps > 0u) {
                tracked++;
            } else {
                full++;
            }
            assert_true(det3(pt.r.m) > 0.0); /* never a reflection */
            assert_proper(&pt.r);
            assert_int_equal(tr.valid, 1);
            assert_near(tr.q[0] * tr.q[0] + tr.q[1] * tr.q[1] + tr.q[2] * tr.q[2] + tr.q[3] * tr.q[3],
                        1.0, 4.0 * TC_FEPS, "|q|");
            assert_int_equal(ft.used, ff.used);
            assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd, seen, m,
                                           rr, tt, NULL),
                             0);
            b = rot_bound((const double (*)[3])tpl, seen, m);
            bt = trans_bound(b, (const double (*)[3])tpl, (const double (*)[3])xd, seen, m);
            assert_rot_near(&pt.r, rr, (const double (*)[3])tpl, seen, m);
            assert_rot_near(&pf.r, rr, (const double (*)[3])tpl, seen, m);
            {
                double rf[9];
                for (k = 0; k < 9; k++) {
                    rf[k] = (double)pf.r.m[k];
                }
                d = max_rot_diff(&pt.r, rf);
            }
            assert_true(d <= 2.0 * b);
            for (k = 0; k < 3; k++) {
                const double e = fabs((double)pt.t.v[k] - (double)pf.t.v[k]);
                assert_true(fabs((double)pt.t.v[k] - tt[k]) <= bt);
                if (e > dt) {
                    dt = e;
                }
            }
            assert_true(dt <= 2.0 * bt);
            assert_near(ft.rms, ff.rms, 1e-4 + 1e-3 * (double)ff.rms, "rms");
            if (d > worst_dr) {
                worst_dr = d;
            }
            if (dt > worst_dt) {
                worst_dt = dt;
            }
            if (d / (2.0 * b) > worst_ratio) {
                worst_ratio = d / (2.0 * b);
            }
        }
    }
    printf("  %ld frames, %ld tracked, %ld full solves (%ld of them after a failed convergence "
           "test), %ld gap frames; steps 1/2/3: %ld/%ld/%ld\n",
           frames, tracked, full, gave_up, gaps, steps_hist[1], steps_hist[2],
           SFIT_CLUSTER_TRACK_STEPS >= 3 ? steps_hist[3] : 0L);
    printf("  tracked vs full solve: max |dR| %.3g (worst / bound %.3f), max |dt| %.3g mm\n",
           worst_dr, worst_ratio, worst_dt);
    printf("  worst error / rounding bound (both vs Horn in double): %.3f\n", g_worst_ratio);
    assert_true(tracked > 8 * full); /* the short path carries the sequences */
}

/* The convergence test can fail: a jump of 120 degrees between frames, or a
 * state rotated away from the truth, runs the full solve (or converges to
 * the global maximum); a corrupted state is SFIT_E_ARG and stays as it was. */
static void test_track_fallback_and_state(void **state)
{
    tu_rng_t g;
    double p[4][3], tpl[4][3], r[9], t[3], xd[4][3], rr[9], tt[3];
    const double jump[3] = {0.0, 2.0944, 0.0};
    sfit_vec3_t tv[4], mv[4];
    sfit_cluster_t cl;
    sfit_cluster_track_t tr, before;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    const int all[4] = {1, 1, 1, 1};
    int k;
    (void)state;
    tu_rng_seed(&g, 3031);
    rand_template(&g, 4u, p);
    to_vec((const double (*)[3])p, 4u, tv, tpl);
    assert_int_equal(sfit_cluster_init(&cl, tv, 4u), SFIT_OK);
    rand_rot(&g, r);
    rand_far(&g, t);
    make_frame(&g, (const double (*)[3])tpl, 4u, r, t, 0.5, mv, xd);
    assert_int_equal(sfit_cluster_track_reset(&tr), SFIT_OK);
    assert_int_equal(tr.valid, 0);
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, &fit), SFIT_OK);
    assert_int_equal(tr.steps, 0);
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, &fit), SFIT_OK);
    assert_true(tr.steps >= 1u); /* the same frame again: converges at once */
    rot_step(jump, r);
    make_frame(&g, (const double (*)[3])tpl, 4u, r, t, 0.5, mv, xd);
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, &fit), SFIT_OK);
    assert_int_equal(tr.steps, 0); /* 120 degrees: the short path gives up */
    assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])xd, NULL, 4u, rr,
                                   tt, NULL),
                     0);
    assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, all, 4u);
    /* a unit quaternion far from the truth (180 degrees about x) */
    tr.q[0] = 0.0f;
    tr.q[1] = 1.0f;
    tr.q[2] = tr.q[3] = 0.0f;
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, &fit), SFIT_OK);
    assert_rot_near(&pose.r, rr, (const double (*)[3])tpl, all, 4u);
    assert_true(det3(pose.r.m) > 0.0);
    /* corrupted states */
    for (k = 0; k < 5; k++) {
        sfit_pose_t sent;
        memset(&sent, 0xA5, sizeof sent);
        pose = sent;
        assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, NULL), SFIT_OK);
        before = tr;
        if (k == 0) {
            tu_set_byte(&tr.valid, 2u); /* a garbage byte in the bool */
        } else if (k == 1) {
            tr.q[2] = NAN;
        } else if (k == 2) {
            tr.q[0] *= 1.01f;
        } else if (k == 3) {
            tr.q[0] = tr.q[1] = tr.q[2] = tr.q[3] = 0.0f;
        } else {
            tr.q[1] = INFINITY;
        }
        {
            const sfit_cluster_track_t bad = tr;
            pose = sent;
            assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, NULL), SFIT_E_ARG);
            assert_memory_equal(&tr, &bad, sizeof tr);
            assert_memory_equal(&pose, &sent, sizeof pose);
        }
        tr = before;
    }
    /* invalid frames leave the state as it was; a gap (TOO_FEW) forgets it */
    before = tr;
    mv[1].v[0] = INFINITY;
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, NULL), SFIT_E_NONFINITE);
    assert_memory_equal(&tr, &before, sizeof tr);
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 3u, &pose, NULL), SFIT_E_ARG);
    assert_memory_equal(&tr, &before, sizeof tr);
    mv[1].v[0] = NAN;
    mv[2].v[1] = NAN;
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, &pose, NULL), SFIT_E_TOO_FEW);
    assert_int_equal(tr.valid, 0);
    assert_int_equal(sfit_cluster_track(NULL, &tr, mv, 4u, &pose, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_track(&cl, NULL, mv, 4u, &pose, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_track(&cl, &tr, mv, 4u, NULL, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_cluster_track_reset(NULL), SFIT_E_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ref_horn_exact),
        cmocka_unit_test(test_exact_far),
        cmocka_unit_test(test_noisy_vs_ref),
        cmocka_unit_test(test_far_as_good_as_near),
        cmocka_unit_test(test_symmetric_clusters),
        cmocka_unit_test(test_occluded),
        cmocka_unit_test(test_reflection),
        cmocka_unit_test(test_three_markers),
        cmocka_unit_test(test_pose_maps),
        cmocka_unit_test(test_from_frame),
        cmocka_unit_test(test_from_frames),
        cmocka_unit_test(test_statuses),
        cmocka_unit_test(test_extremes),
        cmocka_unit_test(test_track_sequences),
        cmocka_unit_test(test_track_fallback_and_state),
    };
    return cmocka_run_group_tests_name("cluster", tests, NULL, NULL);
}
