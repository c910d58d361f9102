/* SPDX-License-Identifier: MIT */
/**
 * @file test_joint.c
 * @brief Tests of the streaming functional joint centre (sfit_joint.h).
 *
 * Synthetic joints: a parent cluster (4 markers) moving through random
 * rigid motions 2-3 m from the origin, a child segment (5 markers) turning
 * about a known centre (ball) or a known axis (hinge) relative to it,
 * Gaussian marker noise on every marker.
 *
 * Oracles:
 *  - the same pipeline in double (tests/ref: Horn's quaternion registration,
 *    ref_fit_multi / ref_fit_multi_planar for MGDK), fed the same float
 *    inputs: the library agrees to float rounding;
 *  - the truth, by Monte Carlo with fixed seeds: the centre's bias is
 *    within 3 standard errors of zero and its mean squared error matches
 *    the first-order (delta-method) prediction from single-frame noise,
 *    computed in double by differentiating the reference pipeline with
 *    respect to every marker coordinate of every frame; the hinge axis
 *    error matches its predicted angular error the same way.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit/sfit_joint.h"
#include "sfit_ref.h"
#include "sfit_ref_joint.h"
#include "sfit_ref_multi.h"

#define P 4
#define K 5
#define FMAX 400

/* ---------- synthetic joint ---------- */

static const double g_tpl[P][3] = {
    {70.0, 40.0, 10.0}, {-75.0, 35.0, 5.0}, {-60.0, -50.0, 30.0}, {65.0, -25.0, -45.0}}; /* centroid 0 */
/* Child markers relative to the joint centre, child frame at rest (mm). */
static const double g_dk[K][3] = {{30.0, -20.0, -150.0}, {-35.0, 25.0, -220.0},
                                  {40.0, 30.0, -300.0},  {-20.0, -45.0, -380.0},
                                  {45.0, -10.0, -420.0}};
static const double g_centre[3] = {-80.0, 90.0, -70.0}; /* in the parent (template) frame */
static const double g_axis0[3] = {0.9, 0.3, -0.2};     /* hinge axis, normalised at use */

/* Truth (noise-free) and the float inputs with their double images. */
static double g_par0[FMAX][P][3], g_chi0[FMAX][K][3];
static double g_r[FMAX][9], g_t[FMAX][3];
static sfit_vec3_t g_parf[FMAX][P], g_chif[FMAX][K];
static double g_pard[FMAX][P][3], g_chid[FMAX][K][3];
static size_t g_nf;

static void unit_axis(double a[3])
{
    double n = tu_norm3(g_axis0);
    int i;
    for (i = 0; i < 3; i++) {
        a[i] = g_axis0[i] / n;
    }
}

/* Motion of nf frames: parent pose uniformly random, 2-3 m away; child
 * rotation relative to the parent: ball = random axis, angle up to 60 deg;
 * hinge = about the axis, -10..110 deg. */
static void make_motion(uint64_t seed, size_t nf, int hinge)
{
    tu_rng_t g;
    size_t f, i;
    double ax[3];
    tu_rng_seed(&g, seed);
    unit_axis(ax);
    g_nf = nf;
    for (f = 0; f < nf; f++) {
        double q[9], dir[3], n, dist;
        int k;
        /* parent pose: random rotation from a random axis-angle */
        for (k = 0; k < 3; k++) {
            dir[k] = tu_rng_gauss(&g);
        }
        tu_rot_axis_angle(dir, TU_PI * tu_rng_uniform(&g), g_r[f]);
        for (k = 0; k < 3; k++) {
            dir[k] = tu_rng_gauss(&g);
        }
        n = tu_norm3(dir);
        dist = 2000.0 + 1000.0 * tu_rng_uniform(&g);
        for (k = 0; k < 3; k++) {
            g_t[f][k] = dir[k] / n * dist;
        }
        if (hinge) {
            tu_rot_axis_angle(ax, (-10.0 + 120.0 * tu_rng_uniform(&g)) * TU_PI / 180.0, q);
        } else {
            for (k = 0; k < 3; k++) {
                dir[k] = tu_rng_gauss(&g);
            }
            tu_rot_axis_angle(dir, 60.0 * TU_PI / 180.0 * tu_rng_uniform(&g), q);
        }
        for (i = 0; i < P; i++) {
            ref_pose_to_global(g_r[f], g_t[f], g_tpl[i], g_par0[f][i]);
        }
        for (i = 0; i < K; i++) {
            double y[3], zero[3] = {0.0, 0.0, 0.0};
            ref_pose_to_global(q, zero, g_dk[i], y);
            for (k = 0; k < 3; k++) {
                y[k] += g_centre[k];
            }
            ref_pose_to_global(g_r[f], g_t[f], y, g_chi0[f][i]);
        }
    }
}

/* Noisy float inputs (and their double images) from the truth. */
static void make_noisy(tu_rng_t *g, double sigma_par, double sigma)
{
    size_t f, i;
    for (f = 0; f < g_nf; f++) {
        for (i = 0; i < P; i++) {
            double x[3];
            memcpy(x, g_par0[f][i], sizeof x);
            tu_add_noise(g, sigma_par, x);
            tc_to_vec3(x, &g_parf[f][i]);
            tc_to_double3(&g_parf[f][i], g_pard[f][i]);
        }
        for (i = 0; i < K; i++) {
            double x[3];
            memcpy(x, g_chi0[f][i], sizeof x);
            tu_add_noise(g, sigma, x);
            tc_to_vec3(x, &g_chif[f][i]);
            tc_to_double3(&g_chif[f][i], g_chid[f][i]);
        }
    }
}

static void template_f(sfit_cluster_t *cl, double tpl_d[P][3])
{
    sfit_vec3_t tv[P];
    size_t i;
    for (i = 0; i < P; i++) {
        tc_to_vec3(g_tpl[i], &tv[i]);
        tc_to_double3(&tv[i], tpl_d[i]);
    }
    assert_int_equal(sfit_cluster_init(cl, tv, P), SFIT_OK);
}

/* ---------- the double pipeline ---------- */

static double g_xs[K][FMAX][3]; /* child markers in the parent frame */

static void ref_map_frame(const double tpl[P][3], const double par[P][3], const double chi[K][3],
                          size_t f)
{
    double r[9], t[3];
    size_t k;
    assert_int_equal(ref_horn_pose(tpl, par, NULL, P, r, t, NULL), 0);
    for (k = 0; k < K; k++) {
        ref_pose_to_segment(r, t, chi[k], g_xs[k][f]);
    }
}

/* Noise model of the double solve: none or one Sigma_hat (cov6 packed
 * XX,YY,ZZ,XY,XZ,YZ), or one model per marker (Sigma_p row-major, t_p). */
typedef struct {
    int per_marker;
    const double *cov6;
    double cov9[K * 9], skew[K * 3];
} noise_t;

/* MGDK (sphere) or planar solve of the mapped markers. */
static void ref_solve(int planar, const noise_t *nz, double c[3], double a[3])
{
    const double *xs[K];
    const double *cov6 = nz->cov6;
    size_t ns[K], k;
    double radii[K];
    for (k = 0; k < K; k++) {
        xs[k] = &g_xs[k][0][0];
        ns[k] = g_nf;
    }
    if (nz->per_marker) {
        assert_int_equal(ref_fit_multi_noise(xs, ns, K, nz->cov9, nz->skew, planar, c, a, radii),
                         0);
    } else if (planar) {
        assert_int_equal(ref_fit_multi_planar(xs, ns, K, cov6, 0, c, a, radii), 0);
    } else {
        assert_int_equal(ref_fit_multi(xs, ns, K, cov6, c, radii), 0);
    }
}

static void ref_pipeline(const double tpl[P][3], const double (*par)[P][3],
                         const double (*chi)[K][3], int planar, const noise_t *nz, double c[3],
                         double a[3])
{
    size_t f;
    for (f = 0; f < g_nf; f++) {
        ref_map_frame(tpl, par[f], chi[f], f);
    }
    ref_solve(planar, nz, c, a);
}

/* Per-marker noise models (marker variance var) of the noise-free truth,
 * sample by sample (ref_joint_marker_noise). */
static void truth_noise(double var, noise_t *nz)
{
    size_t f, k;
    memset(nz, 0, sizeof *nz);
    nz->per_marker = 1;
    for (f = 0; f < g_nf; f++) {
        ref_map_frame(g_tpl, (const double (*)[3])g_par0[f], (const double (*)[3])g_chi0[f], f);
    }
    for (k = 0; k < K; k++) {
        assert_int_equal(ref_joint_marker_noise(g_tpl, P, &g_xs[k][0][0], g_nf, var,
                                                &nz->cov9[9 * k], &nz->skew[3 * k]),
                         0);
    }
}

/* The library's per-marker models as a double noise_t. */
static void noise_of_lib(const sfit_multi_noise_t *nl, noise_t *nz)
{
    size_t k;
    int i;
    memset(nz, 0, sizeof *nz);
    nz->per_marker = 1;
    for (k = 0; k < K; k++) {
        for (i = 0; i < 9; i++) {
            nz->cov9[9 * k + (size_t)i] = (double)nl[k].cov.m[i];
        }
        for (i = 0; i < 3; i++) {
            nz->skew[3 * k + (size_t)i] = (double)nl[k].skew.v[i];
        }
    }
}

/*
 * Delta-method prediction per unit noise variance, split by where the noise
 * is (0 = parent markers, 1 = child markers): covariance of the centre and
 * of the axis to first order, sum_j J_j J_j^T, and their bias to second
 * order, (1/2) sum_j d2/dx_j^2, over every coordinate x_j of every frame,
 * by central differences (h = 1e-2 mm) of the double pipeline around the
 * noise-free truth. The axis parts are zero for the sphere.
 */
typedef struct {
    double cc[2][3][3], ca[2][3][3], bc[2][3], ba[2][3];
    double off_c[3], off_a[3]; /* estimate at the noise-free truth minus the truth
                                  (non-zero for UGDK: Sigma_hat is subtracted) */
} pred_t;

static void predict(int planar, const noise_t *nz, pred_t *o)
{
    static double par[FMAX][P][3], chi[FMAX][K][3];
    double tpl[P][3], c0[3], a0[3];
    const double h = 1e-2;
    size_t f, i;
    int k, q, a, b;
    memcpy(tpl, g_tpl, sizeof tpl);
    memcpy(par, g_par0, sizeof par);
    memcpy(chi, g_chi0, sizeof chi);
    memset(o, 0, sizeof *o);
    ref_pipeline((const double (*)[3])tpl, (const double (*)[P][3])par,
                 (const double (*)[K][3])chi, planar, nz, c0, a0);
    {
        double ax[3];
        unit_axis(ax);
        for (q = 0; q < 3; q++) {
            o->off_c[q] = c0[q] - g_centre[q];
            o->off_a[q] = planar ? a0[q] - ax[q] : 0.0;
        }
    }
    for (f = 0; f < g_nf; f++) {
        for (i = 0; i < P + K; i++) {
            const int w = (i < P) ? 0 : 1;
            for (k = 0; k < 3; k++) {
                double *x = (i < P) ? &par[f][i][k] : &chi[f][i - P][k];
                double cp[3], cm[3], ap[3] = {0, 0, 0}, am[3] = {0, 0, 0}, jc[3], ja[3];
                const double x0 = *x;
                *x = x0 + h;
                ref_map_frame((const double (*)[3])tpl, (const double (*)[3])par[f],
                              (const double (*)[3])chi[f], f);
                ref_solve(planar, nz, cp, ap);
                *x = x0 - h;
                ref_map_frame((const double (*)[3])tpl, (const double (*)[3])par[f],
                              (const double (*)[3])chi[f], f);
                ref_solve(planar, nz, cm, am);
                *x = x0;
                ref_map_frame((const double (*)[3])tpl, (const double (*)[3])par[f],
                              (const double (*)[3])chi[f], f);
                for (q = 0; q < 3; q++) {
                    jc[q] = (cp[q] - cm[q]) / (2.0 * h);
                    ja[q] = planar ? (ap[q] - am[q]) / (2.0 * h) : 0.0;
                    o->bc[w][q] += 0.5 * (cp[q] + cm[q] - 2.0 * c0[q]) / (h * h);
                    if (planar) {
                        o->ba[w][q] += 0.5 * (ap[q] + am[q] - 2.0 * a0[q]) / (h * h);
                    }
                }
                for (a = 0; a < 3; a++) {
                    for (b = 0; b < 3; b++) {
                        o->cc[w][a][b] += jc[a] * jc[b];
                        o->ca[w][a][b] += ja[a] * ja[b];
                    }
                }
            }
        }
    }
}

/* First-order noise covariance of a child marker in the parent frame, per
 * unit marker variance, averaged over every sample of the truth:
 * I + I/P + [y]x J^-1 [y]x^T, y relative to the template centroid,
 * J = sum_i (|p_i|^2 I - p_i p_i^T) (docs/joint.md). Packed XX,YY,ZZ,XY,XZ,YZ. */
static void effective_cov(double cov6[6])
{
    double pb[3] = {0, 0, 0}, j[3][3], ji[3][3], acc[3][3], w[3], v[3][3];
    size_t f, i;
    int a, b, c;
    memset(j, 0, sizeof j);
    memset(acc, 0, sizeof acc);
    for (i = 0; i < P; i++) {
        for (a = 0; a < 3; a++) {
            pb[a] += g_tpl[i][a] / P;
        }
    }
    for (i = 0; i < P; i++) {
        double p[3];
        for (a = 0; a < 3; a++) {
            p[a] = g_tpl[i][a] - pb[a];
        }
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                j[a][b] += (a == b ? tu_dot3(p, p) : 0.0) - p[a] * p[b];
            }
        }
    }
    ref_sym3_eig((const double (*)[3])j, w, v);
    for (a = 0; a < 3; a++) {
        for (b = 0; b < 3; b++) {
            ji[a][b] = 0.0;
            for (c = 0; c < 3; c++) {
                ji[a][b] += v[a][c] * v[b][c] / w[c];
            }
        }
    }
    for (f = 0; f < g_nf; f++) {
        double r[9], t[3];
        assert_int_equal(ref_horn_pose(g_tpl, (const double (*)[3])g_par0[f], NULL, P, r, t, NULL), 0);
        for (i = 0; i < K; i++) {
            double y[3], m[3][3], mj[3][3];
            ref_pose_to_segment(r, t, g_chi0[f][i], y);
            for (a = 0; a < 3; a++) {
                y[a] -= pb[a];
            }
            /* m = [y]x */
            m[0][0] = 0; m[0][1] = -y[2]; m[0][2] = y[1];
            m[1][0] = y[2]; m[1][1] = 0; m[1][2] = -y[0];
            m[2][0] = -y[1]; m[2][1] = y[0]; m[2][2] = 0;
            for (a = 0; a < 3; a++) {
                for (b = 0; b < 3; b++) {
                    mj[a][b] = 0.0;
                    for (c = 0; c < 3; c++) {
                        mj[a][b] += m[a][c] * ji[c][b];
                    }
                }
            }
            for (a = 0; a < 3; a++) {
                for (b = 0; b < 3; b++) {
                    double s = (a == b) ? 1.0 + 1.0 / P : 0.0;
                    for (c = 0; c < 3; c++) {
                        s += mj[a][c] * m[b][c];
                    }
                    acc[a][b] += s / (double)(g_nf * K);
                }
            }
        }
    }
    cov6[0] = acc[0][0]; cov6[1] = acc[1][1]; cov6[2] = acc[2][2];
    cov6[3] = acc[0][1]; cov6[4] = acc[0][2]; cov6[5] = acc[1][2];
}

static void cfg_cov(sfit_joint_cfg_t *cfg, const double cov6[6], double s2)
{
    sfit_mat3_t *m = &cfg->solve.fit.noise_cov;
    cfg->solve.fit.noise = SFIT_NOISE_COV;
    m->m[0] = (float)(s2 * cov6[0]);
    m->m[4] = (float)(s2 * cov6[1]);
    m->m[8] = (float)(s2 * cov6[2]);
    m->m[1] = m->m[3] = (float)(s2 * cov6[3]);
    m->m[2] = m->m[6] = (float)(s2 * cov6[4]);
    m->m[5] = m->m[7] = (float)(s2 * cov6[5]);
}

static void cov6_of_cfg(const sfit_joint_cfg_t *cfg, double cov6[6])
{
    const float *m = cfg->solve.fit.noise_cov.m;
    cov6[0] = (double)m[0]; cov6[1] = (double)m[4]; cov6[2] = (double)m[8];
    cov6[3] = (double)m[1]; cov6[4] = (double)m[2]; cov6[5] = (double)m[5];
}

/* Run the library over the current noisy frames. */
static sfit_status_t lib_run(const sfit_joint_cfg_t *cfg, sfit_joint_t *j, sfit_joint_result_t *res,
                             float *radii)
{
    sfit_cluster_t cl;
    double tpl[P][3];
    size_t f;
    template_f(&cl, tpl);
    assert_int_equal(sfit_joint_init(j, &cl, cfg), SFIT_OK);
    for (f = 0; f < g_nf; f++) {
        assert_int_equal(sfit_joint_add(j, g_parf[f], P, g_chif[f], K, NULL), SFIT_OK);
    }
    return sfit_joint_fit(j, res, radii);
}

static sfit_joint_t g_j;

/* ---------- tests ---------- */

/* Noise-free ball: the centre is recovered to float rounding. */
static void test_ball_exact(void **state)
{
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t res;
    float radii[K];
    size_t k;
    (void)state;
    cfg.n_child = K;
    make_motion(101, 300, 0);
    tu_rng_seed(&g, 1);
    make_noisy(&g, 0.0, 0.0);
    assert_int_equal(lib_run(&cfg, &g_j, &res, radii), SFIT_OK);
    assert_int_equal(res.fit.mode, SFIT_MODE_SPHERE);
    assert_int_equal(res.frames, 300);
    assert_int_equal(res.fit.markers, K);
    assert_vec3_near(res.fit.center.v, g_centre, 2e-3, "centre");
    for (k = 0; k < K; k++) {
        assert_near(radii[k], tu_norm3(g_dk[k]), 2e-3, "radius");
    }
    assert_true(res.residual_mean < 2e-4f && res.residual_max < 5e-4f);
}

/* Noisy ball and hinge, GDKE, UGDK with one Sigma_hat and UGDK with the
 * per-marker models (SFIT_JOINT_NOISE_MARKER; the double solve is given the
 * library's models, checked on their own in test_noise_cov): the library
 * equals the double pipeline on the same float inputs. Worst differences
 * printed; the tolerances (2e-2 mm, 2e-5 rad) are about 10x those. */
static void test_vs_ref(void **state)
{
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t res;
    float radii[K];
    double c[3], a[3], tpl[P][3], cov6[6], dc = 0.0, da = 0.0;
    sfit_cluster_t cl;
    noise_t nz;
    int hinge, ugdk, i;
    (void)state;
    cfg.n_child = K;
    template_f(&cl, tpl);
    for (hinge = 0; hinge < 2; hinge++) {
        for (ugdk = 0; ugdk < 3; ugdk++) {
            make_motion(200 + (uint64_t)hinge, 300, hinge);
            tu_rng_seed(&g, 2 + (uint64_t)ugdk);
            make_noisy(&g, 0.5, 0.5);
            cfg.solve = sfit_multi_cfg_default;
            cfg.noise_model = SFIT_JOINT_NOISE_SOLVE;
            memset(&nz, 0, sizeof nz);
            if (ugdk == 1) {
                effective_cov(cov6);
                cfg_cov(&cfg, cov6, 0.25);
                cov6_of_cfg(&cfg, cov6); /* the float-rounded matrix */
                nz.cov6 = cov6;
            } else if (ugdk == 2) {
                cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
                cfg.solve.fit.noise = SFIT_NOISE_ISO;
                cfg.solve.fit.noise_var = 0.25f;
            }
            assert_int_equal(lib_run(&cfg, &g_j, &res, radii), SFIT_OK);
            assert_int_equal(res.fit.mode, hinge ? SFIT_MODE_PLANAR : SFIT_MODE_SPHERE);
            if (ugdk == 2) {
                sfit_multi_noise_t nl[K];
                assert_int_equal(sfit_joint_marker_noise(&g_j, 0.25f, nl), SFIT_OK);
                noise_of_lib(nl, &nz);
            }
            ref_pipeline((const double (*)[3])tpl, (const double (*)[P][3])g_pard,
                         (const double (*)[K][3])g_chid, hinge, &nz, c, a);
            for (i = 0; i < 3; i++) {
                double e = fabs((double)res.fit.center.v[i] - c[i]);
                dc = e > dc ? e : dc;
                if (hinge) {
                    e = fabs((double)res.fit.axis.v[i] - a[i]);
                    da = e > da ? e : da;
                }
            }
            assert_vec3_near(res.fit.center.v, c, 2e-2, "centre vs double");
            if (hinge) {
                assert_vec3_near(res.fit.axis.v, a, 2e-5, "axis vs double");
            }
        }
    }
    printf("  vs double pipeline: centre %.3g mm, axis %.3g\n", dc, da);
}

/* The trajectory: sfit_joint_center_at() of every frame equals the double
 * map of the same centre with Horn's pose of that frame, and the truth. */
static void test_trajectory(void **state)
{
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t res;
    double tpl[P][3], c[3], cg[3], r[9], t[3], worst = 0.0, rms = 0.0;
    sfit_cluster_t cl;
    size_t f;
    (void)state;
    cfg.n_child = K;
    template_f(&cl, tpl);
    make_motion(300, 300, 0);
    tu_rng_seed(&g, 4);
    make_noisy(&g, 0.5, 0.5);
    assert_int_equal(lib_run(&cfg, &g_j, &res, NULL), SFIT_OK);
    tc_to_double3(&res.fit.center, c);
    for (f = 0; f < g_nf; f++) {
        sfit_vec3_t cgl, ax;
        double e, truth[3];
        assert_int_equal(sfit_joint_center_at(&g_j, &res, g_parf[f], P, &cgl, &ax), SFIT_OK);
        assert_int_equal(ref_horn_pose((const double (*)[3])tpl, (const double (*)[3])g_pard[f],
                                       NULL, P, r, t, NULL), 0);
        ref_pose_to_global(r, t, c, cg);
        e = tc_dist(&cgl, cg);
        worst = e > worst ? e : worst;
        ref_pose_to_global(g_r[f], g_t[f], g_centre, truth);
        rms += tc_dist(&cgl, truth) * tc_dist(&cgl, truth);
        assert_near(tu_norm3((const double[3]){(double)ax.v[0], (double)ax.v[1], (double)ax.v[2]}),
                    1.0, 1e-5, "axis norm");
    }
    rms = sqrt(rms / (double)g_nf);
    {
        /* vs the truth: the centre's own error plus the per-frame pose error
         * at the centre, sigma^2 (1/P + tr([c]x J^-1 [c]x^T)) to first order
         * (c from the template centroid = the template origin here), i.e.
         * MSE = |c - c_true|^2 + 0.25 e_pose; the mean over 300 frames of a
         * chi-square has a relative SE of about 5 %: tolerance 20 %. */
        double e_c = tu_dist3(c, g_centre), j[3][3], w[3], v[3][3], pose2 = 1.0 / P, pred;
        double cc[3];
        size_t i;
        int a, b2;
        memset(j, 0, sizeof j);
        for (i = 0; i < P; i++) {
            for (a = 0; a < 3; a++) {
                for (b2 = 0; b2 < 3; b2++) {
                    j[a][b2] += (a == b2 ? tu_dot3(tpl[i], tpl[i]) : 0.0) - tpl[i][a] * tpl[i][b2];
                }
            }
        }
        ref_sym3_eig((const double (*)[3])j, w, v);
        for (a = 0; a < 3; a++) { /* |c x v_a|^2 / w_a summed = tr([c]x J^-1 [c]x^T) */
            double col[3] = {v[0][a], v[1][a], v[2][a]};
            tu_cross3(c, col, cc);
            pose2 += tu_dot3(cc, cc) / w[a];
        }
        pred = sqrt(e_c * e_c + 0.25 * pose2);
        printf("  trajectory: max |lib - double| %.3g mm; RMS vs truth %.3g mm, predicted %.3g\n",
               worst, rms, pred);
        assert_true(fabs(rms - pred) <= 0.2 * pred);
    }
    assert_true(worst < 5e-3);
}

/* Monte Carlo summary of T error vectors e_t (3 components): bias and its
 * standard error per component, mean |e|^2 and its standard error. */
typedef struct {
    double mean[3], se[3], mse, mse_se;
} mc_t;

static void mc_summary(const double (*e)[3], size_t n, mc_t *o)
{
    double s2[3] = {0, 0, 0}, q = 0.0, q2 = 0.0;
    size_t t;
    int k;
    memset(o, 0, sizeof *o);
    for (t = 0; t < n; t++) {
        double d = tu_dot3(e[t], e[t]);
        for (k = 0; k < 3; k++) {
            o->mean[k] += e[t][k] / (double)n;
        }
        q += d / (double)n;
    }
    for (t = 0; t < n; t++) {
        double d = tu_dot3(e[t], e[t]) - q;
        for (k = 0; k < 3; k++) {
            s2[k] += (e[t][k] - o->mean[k]) * (e[t][k] - o->mean[k]) / (double)(n - 1);
        }
        q2 += d * d / (double)(n - 1);
    }
    for (k = 0; k < 3; k++) {
        o->se[k] = sqrt(s2[k] / (double)n);
    }
    o->mse = q;
    o->mse_se = sqrt(q2 / (double)n);
}

/* Bias within 3 SE of the predicted (second-order) bias and MSE within
 * 3 SE of the predicted trace(cov) + |bias|^2. */
static void assert_mc(const mc_t *m, const double bias[3], double pred_mse, const char *what)
{
    int k;
    printf("  %s: bias (%.4f %.4f %.4f) mm +- (%.4f %.4f %.4f), predicted (%.4f %.4f %.4f); "
           "RMSE %.4f mm, predicted %.4f (MSE %.5f +- %.5f)\n",
           what, m->mean[0], m->mean[1], m->mean[2], m->se[0], m->se[1], m->se[2], bias[0],
           bias[1], bias[2], sqrt(m->mse), sqrt(pred_mse), m->mse, m->mse_se);
    for (k = 0; k < 3; k++) {
        assert_true(fabs(m->mean[k] - bias[k]) <= 3.0 * m->se[k]);
    }
    assert_true(fabs(m->mse - pred_mse) <= 3.0 * m->mse_se);
}

#define MC_T 400
#define MC_F 200
#define MC_SIGMA 0.5

/* Prediction for noise sigma_par on the parent markers and sigma on the
 * child markers: bias b (3), MSE (trace(cov) + |b|^2) of the centre, or of
 * its part normal to `normal` when not NULL; the same for the axis. */
static void combine(const pred_t *pr, double sp, double sc, const double *normal, double b[3],
                    double *mse, double ba[3], double *mse_a)
{
    double v[2] = {sp * sp, sc * sc}, pm[3][3];
    int w, k, l, q;
    for (k = 0; k < 3; k++) {
        for (l = 0; l < 3; l++) {
            pm[k][l] = (k == l ? 1.0 : 0.0) - (normal ? normal[k] * normal[l] : 0.0);
        }
    }
    *mse = 0.0;
    *mse_a = 0.0;
    for (k = 0; k < 3; k++) {
        double raw = 0.0;
        b[k] = 0.0;
        ba[k] = pr->off_a[k];
        for (l = 0; l < 3; l++) {
            b[k] += pm[k][l] * pr->off_c[l];
        }
        for (w = 0; w < 2; w++) {
            ba[k] += v[w] * pr->ba[w][k];
            for (l = 0; l < 3; l++) {
                b[k] += v[w] * pm[k][l] * pr->bc[w][l];
            }
            *mse_a += v[w] * pr->ca[w][k][k];
            for (l = 0; l < 3; l++) {
                for (q = 0; q < 3; q++) {
                    raw += v[w] * pm[k][l] * pr->cc[w][l][q] * pm[q][k];
                }
            }
        }
        *mse += raw;
    }
    *mse += tu_dot3(b, b);
    *mse_a += tu_dot3(ba, ba);
}

/* Bias of a Monte Carlo run against zero: every component within 3 SE. */
static void assert_unbiased(const mc_t *m)
{
    int k;
    for (k = 0; k < 3; k++) {
        assert_true(fabs(m->mean[k]) <= 3.0 * m->se[k]);
    }
}

/* The reported centre covariance (mean trace over the trials, cov_tr) is
 * true: within 3 SE of the Monte Carlo trace of the errors' covariance
 * (mean |e|^2 - |mean e|^2; its SE is that of mean |e|^2), and within 5 %
 * of the delta-method trace pred_tr of the double pipeline (both first
 * order; they differ by where the derivatives are taken). */
static void assert_cov_true(const mc_t *m, double cov_tr, double pred_tr, const char *what)
{
    const double mc_tr = m->mse - tu_dot3(m->mean, m->mean);
    printf("  %s centre covariance: reported trace %.5f mm^2, Monte Carlo %.5f +- %.5f "
           "(ratio %.3f +- %.3f), delta method %.5f\n",
           what, cov_tr, mc_tr, m->mse_se, cov_tr / mc_tr, m->mse_se / mc_tr, pred_tr);
    assert_true(fabs(cov_tr - mc_tr) <= 3.0 * m->mse_se);
    assert_true(fabs(cov_tr - pred_tr) <= 0.05 * pred_tr);
}

/* Run MC_T noisy copies of the current motion through the library; e gets
 * the centre errors (the part normal to `normal` when not NULL), ang2 /
 * ang4 (may be NULL) the mean of |a - a_true|^2 and of its square. */
static void mc_run(const sfit_joint_cfg_t *cfg, uint64_t seed, double sp, const double *normal,
                   double (*e)[3], double *ang2, double *ang4, double *cov_tr)
{
    tu_rng_t g;
    sfit_joint_result_t res;
    double ax[3];
    size_t t;
    int k;
    unit_axis(ax);
    tu_rng_seed(&g, seed);
    if (ang2 != NULL) {
        *ang2 = 0.0;
        *ang4 = 0.0;
    }
    if (cov_tr != NULL) {
        *cov_tr = 0.0;
    }
    for (t = 0; t < MC_T; t++) {
        double d = 0.0, a2 = 0.0;
        make_noisy(&g, sp, MC_SIGMA);
        assert_int_equal(lib_run(cfg, &g_j, &res, NULL), SFIT_OK);
        for (k = 0; k < 3; k++) {
            e[t][k] = (double)res.fit.center.v[k] - g_centre[k];
        }
        if (cov_tr != NULL) { /* the reported covariance (every marker: sigma^2) */
            sfit_mat3_t cov;
            if (sp > 0.0) { /* the parent's pose error shared by the child markers */
                assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0],
                                                       g_nf, (float)(MC_SIGMA * MC_SIGMA), &cov),
                                 SFIT_OK);
            } else { /* exact parent: independent child noise, the multi-marker formula */
                assert_int_equal(sfit_multi_center_cov(g_j.child, K, &cfg->solve, &res.fit,
                                                       (float)(MC_SIGMA * MC_SIGMA), &cov),
                                 SFIT_OK);
            }
            *cov_tr += ((double)cov.m[0] + (double)cov.m[4] + (double)cov.m[8]) / MC_T;
        }
        if (normal != NULL) {
            d = tu_dot3(e[t], normal);
        }
        for (k = 0; k < 3; k++) {
            const double ea = (double)res.fit.axis.v[k] - ax[k]; /* both: largest component > 0 */
            e[t][k] -= (normal != NULL) ? d * normal[k] : 0.0;
            a2 += ea * ea;
        }
        if (ang2 != NULL) {
            *ang2 += a2 / MC_T;
            *ang4 += a2 * a2 / MC_T;
        }
    }
}

/*
 * Ball joint, unbiased MGDK.
 * (a) Parent markers exact, child noise sigma = 0.5 mm: the noise of a
 *     child marker in the parent frame is sigma^2 I, the model of UGDK with
 *     one Sigma_hat: the centre is unbiased (MC bias within 3 SE of zero)
 *     and its MSE is the delta-method prediction.
 * (b) Every marker noisy: in the parent frame the child noise becomes
 *     sigma^2 (I + I/P + [y]x J^-1 [y]x^T), anisotropic and growing with the
 *     lever arm |y|. With the per-marker models (SFIT_JOINT_NOISE_MARKER,
 *     sfit_multi_fit_noise) the centre is unbiased: MC bias within 3 SE of
 *     zero, MSE the delta-method prediction (per-marker models of the
 *     truth, sample by sample, in the double solve).
 * (c) The same data with one Sigma_hat, the average of (b)'s models: the
 *     O(sigma^2) bias of the heteroscedastic noise is there (the z bias is
 *     more than 3 SE from zero, and it is its second-order prediction):
 *     the zero-bias check of (b) can fail.
 */
static void test_mc_ball(void **state)
{
    static double err[MC_T][3];
    static pred_t pr;
    static noise_t nz;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    double cov6[6], b[3], mse, ba[3], msea, cov_tr = 0.0;
    mc_t m;
    int k, run;
    (void)state;
    make_motion(400, MC_F, 0);
    for (run = 0; run < 3; run++) {
        const double sp = (run > 0) ? MC_SIGMA : 0.0;
        cfg = sfit_joint_cfg_default;
        cfg.n_child = K;
        memset(&nz, 0, sizeof nz);
        if (run == 0) {
            static const double iso[6] = {1, 1, 1, 0, 0, 0};
            cfg_cov(&cfg, iso, MC_SIGMA * MC_SIGMA);
            cov6_of_cfg(&cfg, cov6);
            nz.cov6 = cov6;
        } else if (run == 1) {
            cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
            cfg.solve.fit.noise = SFIT_NOISE_ISO;
            cfg.solve.fit.noise_var = (float)(MC_SIGMA * MC_SIGMA);
            truth_noise(MC_SIGMA * MC_SIGMA, &nz);
        } else {
            effective_cov(cov6);
            cfg_cov(&cfg, cov6, MC_SIGMA * MC_SIGMA);
            cov6_of_cfg(&cfg, cov6);
            nz.cov6 = cov6;
        }
        predict(0, &nz, &pr);
        combine(&pr, sp, MC_SIGMA, NULL, b, &mse, ba, &msea);
        mc_run(&cfg, 5 + (uint64_t)(run > 0), sp, NULL, err, NULL, NULL,
               (run < 2) ? &cov_tr : NULL);
        mc_summary((const double (*)[3])err, MC_T, &m);
        if (run < 2) {
            assert_cov_true(&m, cov_tr, mse - tu_dot3(b, b),
                            run == 0 ? "ball, exact parent (sfit_multi_center_cov)"
                                     : "ball (sfit_joint_center_cov)");
        }
        assert_mc(&m, b, mse,
                  run == 0   ? "ball, exact parent, one Sigma_hat"
                  : run == 1 ? "ball, all markers noisy, per-marker models"
                             : "ball, all markers noisy, one (average) Sigma_hat");
        if (run < 2) {
            assert_unbiased(&m);
            for (k = 0; k < 3; k++) { /* and so is the prediction */
                assert_true(fabs(b[k]) <= m.se[k]);
            }
        } else {
            assert_true(fabs(m.mean[2]) > 3.0 * m.se[2]);
        }
    }
}

/* Hinge, every marker noisy (sigma 0.5 mm), unbiased planar MGDK with the
 * per-marker models: the part of the centre normal to the axis is unbiased
 * (within 3 SE of zero) with the predicted MSE, and the axis error
 * |a - a_true| (the angle in radians, to first order) has the predicted
 * mean square. */
static void test_mc_hinge(void **state)
{
    static double err[MC_T][3];
    static pred_t pr;
    static noise_t nz;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    double ax[3], b[3], mse, ba[3], msea, ang2, ang4, cov_tr;
    mc_t m;
    (void)state;
    cfg.n_child = K;
    cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
    cfg.solve.fit.noise = SFIT_NOISE_ISO;
    cfg.solve.fit.noise_var = (float)(MC_SIGMA * MC_SIGMA);
    unit_axis(ax);
    make_motion(500, MC_F, 1);
    truth_noise(MC_SIGMA * MC_SIGMA, &nz);
    predict(1, &nz, &pr);
    combine(&pr, MC_SIGMA, MC_SIGMA, ax, b, &mse, ba, &msea);
    mc_run(&cfg, 7, MC_SIGMA, ax, err, &ang2, &ang4, &cov_tr);
    mc_summary((const double (*)[3])err, MC_T, &m);
    assert_cov_true(&m, cov_tr, mse - tu_dot3(b, b), "hinge (normal to the axis)");
    assert_mc(&m, b, mse, "hinge centre (normal to the axis), per-marker models");
    assert_unbiased(&m);
    {
        double se = sqrt((ang4 - ang2 * ang2) / (MC_T - 1));
        printf("  hinge axis: RMS angle %.3g mrad, predicted %.3g mrad (MSE %.3g +- %.2g)\n",
               1e3 * sqrt(ang2), 1e3 * sqrt(msea), ang2, se);
        assert_true(fabs(ang2 - msea) <= 3.0 * se);
    }
}

/* Rejected frames leave the state bit for bit unchanged, each with its
 * status; a NaN child marker is skipped for that marker only. */
static void test_reject_unchanged(void **state)
{
    static sfit_joint_t before;
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_cluster_t cl;
    double tpl[P][3];
    sfit_vec3_t par[P], chi[K], col[P];
    sfit_pose_t pose, sent;
    size_t f;
    int k;
    (void)state;
    cfg.n_child = K;
    make_motion(600, 50, 0);
    tu_rng_seed(&g, 8);
    make_noisy(&g, 0.5, 0.5);
    template_f(&cl, tpl);
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_OK);
    for (f = 0; f < 20; f++) {
        assert_int_equal(sfit_joint_add(&g_j, g_parf[f], P, g_chif[f], K, NULL), SFIT_OK);
    }
    memcpy(&before, &g_j, sizeof before);
    memset(&sent, 0x5A, sizeof sent);
    pose = sent;
#define REJECT(call, status)                                                                \
    do {                                                                                    \
        assert_int_equal((call), (status));                                                 \
        assert_memory_equal(&g_j, &before, sizeof before);                                  \
        assert_memory_equal(&pose, &sent, sizeof pose);                                     \
    } while (0)
    memcpy(par, g_parf[20], sizeof par);
    memcpy(chi, g_chif[20], sizeof chi);
    /* parent: 2 seen */
    par[0].v[0] = NAN;
    par[2].v[1] = NAN;
    REJECT(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_E_TOO_FEW);
    memcpy(par, g_parf[20], sizeof par);
    /* parent: Inf, huge */
    par[1].v[2] = INFINITY;
    REJECT(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_E_NONFINITE);
    par[1].v[2] = 1e30f;
    REJECT(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_E_RANGE);
    memcpy(par, g_parf[20], sizeof par);
    /* parent collinear */
    for (k = 0; k < P; k++) {
        col[k] = par[0];
        col[k].v[0] += 10.0f * (float)k;
    }
    REJECT(sfit_joint_add(&g_j, col, P, chi, K, &pose), SFIT_E_DEGENERATE);
    /* child: Inf, huge */
    chi[3].v[1] = -INFINITY;
    REJECT(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_E_NONFINITE);
    chi[3].v[1] = 3e9f;
    REJECT(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_E_RANGE);
    /* the status rule's order: TOO_FEW before RANGE before DEGENERATE */
    REJECT(sfit_joint_add(&g_j, col, P, chi, K, &pose), SFIT_E_RANGE);
    par[0].v[0] = NAN;
    par[2].v[1] = NAN;
    REJECT(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_E_TOO_FEW);
    memcpy(par, g_parf[20], sizeof par);
    memcpy(chi, g_chif[20], sizeof chi);
    /* arguments */
    REJECT(sfit_joint_add(&g_j, NULL, P, chi, K, &pose), SFIT_E_ARG);
    REJECT(sfit_joint_add(&g_j, par, P, NULL, K, &pose), SFIT_E_ARG);
    REJECT(sfit_joint_add(&g_j, par, P - 1, chi, K, &pose), SFIT_E_ARG);
    REJECT(sfit_joint_add(&g_j, par, P, chi, K + 1, &pose), SFIT_E_ARG);
    assert_int_equal(sfit_joint_add(NULL, par, P, chi, K, &pose), SFIT_E_ARG);
#undef REJECT
    /* a NaN child marker: skipped for that marker only */
    chi[2].v[0] = NAN;
    assert_int_equal(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_OK);
    assert_int_equal(g_j.frames, 21);
    for (k = 0; k < K; k++) {
        assert_int_equal(sfit_moments_count(&g_j.child[k]), k == 2 ? 20 : 21);
    }
    /* an occluded parent marker (3 of 4 seen) is fine; the pose is returned */
    memcpy(chi, g_chif[21], sizeof chi);
    memcpy(par, g_parf[21], sizeof par);
    par[3].v[2] = NAN;
    assert_int_equal(sfit_joint_add(&g_j, par, P, chi, K, &pose), SFIT_OK);
    assert_true(memcmp(&pose, &sent, sizeof pose) != 0);
    assert_int_equal(g_j.frames, 22);
}

/* Contract: NULLs, bad options, garbage state counters -> SFIT_E_ARG;
 * too few samples -> SFIT_E_TOO_FEW; outputs untouched on failure. */
static void test_contract(void **state)
{
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_cluster_t cl, bad;
    sfit_joint_t j2;
    sfit_joint_result_t res, sent;
    sfit_vec3_t c, a;
    double tpl[P][3];
    float radii[K], rsent[K];
    tu_rng_t g;
    size_t f;
    (void)state;
    template_f(&cl, tpl);
    cfg.n_child = K;
    /* init */
    assert_int_equal(sfit_joint_init(NULL, &cl, &cfg), SFIT_E_ARG);
    assert_int_equal(sfit_joint_init(&g_j, NULL, &cfg), SFIT_E_ARG);
    assert_int_equal(sfit_joint_init(&g_j, &cl, NULL), SFIT_OK); /* defaults: 1 child */
    assert_int_equal(g_j.cfg.n_child, 1);
    cfg.n_child = 0;
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_E_ARG);
    cfg.n_child = SFIT_JOINT_MAX_CHILD + 1u;
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_E_ARG);
    cfg.n_child = K;
    cfg.solve.fit.mode = (sfit_mode_t)7;
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_E_ARG);
    cfg.solve.fit.mode = SFIT_MODE_AUTO;
    cfg.solve.weight = (sfit_multi_weight_t)9;
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_E_ARG);
    cfg.solve.weight = SFIT_MULTI_WEIGHT_EQUAL;
    cfg.solve.fit.noise = SFIT_NOISE_ISO;
    cfg.solve.fit.noise_var = -1.0f;
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_E_ARG);
    cfg.solve = sfit_multi_cfg_default;
    bad = cl;
    bad.count = 2;
    assert_int_equal(sfit_joint_init(&g_j, &bad, &cfg), SFIT_E_ARG);
    bad = cl;
    bad.pos[0].v[0] = NAN;
    assert_int_equal(sfit_joint_init(&g_j, &bad, &cfg), SFIT_E_ARG);

    /* too few samples */
    assert_int_equal(sfit_joint_init(&g_j, &cl, &cfg), SFIT_OK);
    memset(&sent, 0x33, sizeof sent);
    memset(rsent, 0x33, sizeof rsent);
    res = sent;
    memcpy(radii, rsent, sizeof radii);
    assert_int_equal(sfit_joint_fit(&g_j, &res, radii), SFIT_E_TOO_FEW);
    make_motion(700, 40, 0);
    tu_rng_seed(&g, 9);
    make_noisy(&g, 0.5, 0.5);
    for (f = 0; f < 3; f++) {
        assert_int_equal(sfit_joint_add(&g_j, g_parf[f], P, g_chif[f], K, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_joint_fit(&g_j, &res, radii), SFIT_E_TOO_FEW);
    assert_memory_equal(&res, &sent, sizeof res);
    assert_memory_equal(radii, rsent, sizeof radii);
    for (f = 3; f < 40; f++) {
        assert_int_equal(sfit_joint_add(&g_j, g_parf[f], P, g_chif[f], K, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_joint_fit(&g_j, &res, radii), SFIT_OK);
    assert_int_equal(sfit_joint_fit(&g_j, &res, NULL), SFIT_OK);
    assert_int_equal(sfit_joint_fit(NULL, &res, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_joint_fit(&g_j, NULL, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_at(&g_j, &res, g_parf[0], P, &c, &a), SFIT_OK);
    assert_int_equal(sfit_joint_center_at(&g_j, &res, g_parf[0], P, &c, NULL), SFIT_OK);
    assert_int_equal(sfit_joint_center_at(NULL, &res, g_parf[0], P, &c, &a), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_at(&g_j, NULL, g_parf[0], P, &c, &a), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_at(&g_j, &res, NULL, P, &c, &a), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_at(&g_j, &res, g_parf[0], P, NULL, &a), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_at(&g_j, &res, g_parf[0], P + 1, &c, &a), SFIT_E_ARG);
    /* a non-finite centre or axis in res: SFIT_E_NONFINITE (it was
     * SFIT_E_RANGE, as if the mapping had overflowed) */
    {
        sfit_joint_result_t rb = res;
        rb.fit.center.v[0] = NAN;
        assert_int_equal(sfit_joint_center_at(&g_j, &rb, g_parf[0], P, &c, &a),
                         SFIT_E_NONFINITE);
        rb = res;
        rb.fit.axis.v[2] = INFINITY;
        assert_int_equal(sfit_joint_center_at(&g_j, &rb, g_parf[0], P, &c, NULL),
                         SFIT_E_NONFINITE);
    }

    /* garbage counters in the state -> SFIT_E_ARG everywhere, no crash */
    {
        int which;
        for (which = 0; which < 6; which++) {
            j2 = g_j;
            switch (which) {
            case 0: j2.parent.count = 0x7FFFFFFFu; break;
            case 1: j2.cfg.n_child = 0; break;
            case 2: j2.cfg.n_child = 0xFFFFFFFFu; break;
            case 3: j2.frames = 5; break; /* fewer than a child's count */
            case 4: j2.res_mean = NAN; break;
            default: j2.res_max = -1.0f; break;
            }
            assert_int_equal(sfit_joint_add(&j2, g_parf[0], P, g_chif[0], K, NULL), SFIT_E_ARG);
            assert_int_equal(sfit_joint_fit(&j2, &res, NULL), SFIT_E_ARG);
            assert_int_equal(sfit_joint_reset(&j2), SFIT_E_ARG);
            assert_int_equal(sfit_joint_center_at(&j2, &res, g_parf[0], P, &c, NULL), SFIT_E_ARG);
        }
        /* corrupted options (sfit_joint_init() checks them): SFIT_E_ARG from
         * the fit with either noise model (the per-marker model returned an
         * unlisted SFIT_E_NONFINITE for a NaN variance) */
        for (which = 0; which < 2; which++) {
            j2 = g_j;
            j2.cfg.solve.fit.noise = SFIT_NOISE_ISO;
            j2.cfg.solve.fit.noise_var = NAN;
            j2.cfg.noise_model = which ? SFIT_JOINT_NOISE_MARKER : SFIT_JOINT_NOISE_SOLVE;
            assert_int_equal(sfit_joint_fit(&j2, &res, NULL), SFIT_E_ARG);
        }
    }
    /* reset keeps template and options, forgets frames */
    assert_int_equal(sfit_joint_reset(NULL), SFIT_E_ARG);
    assert_int_equal(sfit_joint_reset(&g_j), SFIT_OK);
    assert_int_equal(g_j.frames, 0);
    assert_int_equal(sfit_joint_fit(&g_j, &res, NULL), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_joint_init(&j2, &cl, &cfg), SFIT_OK);
    assert_memory_equal(&g_j, &j2, sizeof j2);
}

/* A template built from the frames themselves (sfit_cluster_from_frames):
 * the centre is then in that template's frame; mapped to the global frame
 * at every frame it agrees with the truth as well as with the exact
 * template (both trajectories within 5e-3 mm of each other). */
static void test_template_from_frames(void **state)
{
    static sfit_vec3_t frames[FMAX * P];
    static sfit_joint_t j2;
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_cluster_t cl;
    sfit_joint_result_t r1, r2;
    size_t f, used;
    double worst = 0.0;
    (void)state;
    cfg.n_child = K;
    make_motion(800, 300, 0);
    tu_rng_seed(&g, 10);
    make_noisy(&g, 0.5, 0.5);
    for (f = 0; f < g_nf; f++) {
        memcpy(&frames[f * P], g_parf[f], sizeof g_parf[f]);
    }
    assert_int_equal(sfit_cluster_from_frames(&cl, frames, g_nf, P, &used), SFIT_OK);
    assert_int_equal(used, g_nf);
    assert_int_equal(sfit_joint_init(&j2, &cl, &cfg), SFIT_OK);
    for (f = 0; f < g_nf; f++) {
        assert_int_equal(sfit_joint_add(&j2, g_parf[f], P, g_chif[f], K, NULL), SFIT_OK);
    }
    assert_int_equal(sfit_joint_fit(&j2, &r2, NULL), SFIT_OK);
    assert_int_equal(lib_run(&cfg, &g_j, &r1, NULL), SFIT_OK);
    for (f = 0; f < g_nf; f++) {
        sfit_vec3_t c1, c2;
        double d[3];
        assert_int_equal(sfit_joint_center_at(&g_j, &r1, g_parf[f], P, &c1, NULL), SFIT_OK);
        assert_int_equal(sfit_joint_center_at(&j2, &r2, g_parf[f], P, &c2, NULL), SFIT_OK);
        tc_to_double3(&c2, d);
        worst = tc_dist(&c1, d) > worst ? tc_dist(&c1, d) : worst;
    }
    printf("  template from frames vs exact template: max trajectory difference %.3g mm\n",
           worst);
    assert_true(worst < 5e-3); /* measured 3.5e-4 mm */
}

/* sfit_joint_noise_cov() against the double first-order expression at the
 * true positions (effective_cov): they differ only by the noise in the
 * mapped samples (relative 1e-4 here); tolerance 1e-2 of the largest
 * entry. sfit_joint_marker_noise() against the double per-sample models of
 * the same mapped samples (ref_joint_marker_noise): the covariances to
 * float rounding (1e-4 of the largest entry), the skews to the one term the
 * moments cannot give (printed; 0.05 of the largest skew entry). The solve
 * in SFIT_JOINT_NOISE_MARKER mode is sfit_multi_fit_noise() with those
 * models, bit for bit. */
static void test_noise_cov(void **state)
{
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t r1, r2;
    sfit_mat3_t cov, sent;
    sfit_multi_noise_t nl[K], nsent[K];
    sfit_multi_cfg_t mcfg = sfit_multi_cfg_default;
    double cov6[6], want[9], big = 0.0, tpl[P][3];
    float rad1[K], rad2[K];
    size_t f;
    int k;
    (void)state;
    cfg.n_child = K;
    cfg.solve.fit.noise = SFIT_NOISE_ISO;
    cfg.solve.fit.noise_var = 0.25f;
    cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
    make_motion(900, 300, 0);
    tu_rng_seed(&g, 11);
    make_noisy(&g, 0.5, 0.5);
    assert_int_equal(lib_run(&cfg, &g_j, &r1, rad1), SFIT_OK);
    assert_int_equal(r1.fit.method, SFIT_METHOD_UGDK);
    assert_int_equal(sfit_joint_noise_cov(&g_j, 0.25f, &cov), SFIT_OK);
    effective_cov(cov6);
    want[0] = cov6[0]; want[4] = cov6[1]; want[8] = cov6[2];
    want[1] = want[3] = cov6[3]; want[2] = want[6] = cov6[4]; want[5] = want[7] = cov6[5];
    for (k = 0; k < 9; k++) {
        want[k] *= 0.25;
        big = fabs(want[k]) > big ? fabs(want[k]) : big;
    }
    printf("  effective noise in the parent frame (sigma 0.5 mm): diag %.3f %.3f %.3f mm^2 "
           "(marker alone 0.25)\n", want[0], want[4], want[8]);
    for (k = 0; k < 9; k++) {
        assert_near(cov.m[k], want[k], 1e-2 * big, "noise cov");
    }
    /* per-marker models against the double ones, sample by sample */
    assert_int_equal(sfit_joint_marker_noise(&g_j, 0.25f, nl), SFIT_OK);
    memcpy(tpl, g_tpl, sizeof tpl);
    for (f = 0; f < g_nf; f++) {
        ref_map_frame((const double (*)[3])tpl, (const double (*)[3])g_pard[f],
                      (const double (*)[3])g_chid[f], f);
    }
    {
        double dcov = 0.0, dsk = 0.0, bigc = 0.0, bigs = 0.0;
        for (k = 0; k < K; k++) {
            double c9[9], sk[3];
            int i;
            assert_int_equal(ref_joint_marker_noise(g_tpl, P, &g_xs[k][0][0], g_nf, 0.25, c9, sk),
                             0);
            for (i = 0; i < 9; i++) {
                dcov = fmax(dcov, fabs((double)nl[k].cov.m[i] - c9[i]));
                bigc = fmax(bigc, fabs(c9[i]));
            }
            for (i = 0; i < 3; i++) {
                dsk = fmax(dsk, fabs((double)nl[k].skew.v[i] - sk[i]));
                bigs = fmax(bigs, fabs(sk[i]));
            }
        }
        printf("  per-marker models vs double per-sample: covariance %.3g (largest entry %.3g), "
               "skew %.3g (largest %.3g) mm^2, mm^3\n", dcov, bigc, dsk, bigs);
        assert_true(dcov <= 1e-4 * bigc);
        assert_true(dsk <= 0.05 * bigs); /* measured 0.029 */
    }
    /* the MARKER solve is sfit_multi_fit_noise() with these models */
    mcfg = cfg.solve;
    mcfg.fit.noise = SFIT_NOISE_NONE;
    memset(&r2, 0, sizeof r2);
    r2.frames = r1.frames;
    r2.residual_mean = r1.residual_mean;
    r2.residual_max = r1.residual_max;
    assert_int_equal(sfit_multi_fit_noise(g_j.child, K, &mcfg, nl, &r2.fit, rad2), SFIT_OK);
    assert_memory_equal(&r1, &r2, sizeof r1);
    assert_memory_equal(rad1, rad2, sizeof rad1);
    /* with one Sigma_hat given explicitly, SOLVE mode is sfit_multi_fit() */
    cfg.noise_model = SFIT_JOINT_NOISE_SOLVE;
    cfg.solve.fit.noise = SFIT_NOISE_COV;
    cfg.solve.fit.noise_cov = cov;
    assert_int_equal(lib_run(&cfg, &g_j, &r2, rad2), SFIT_OK);
    assert_int_equal(sfit_multi_fit(g_j.child, K, &cfg.solve, &r1.fit, rad1), SFIT_OK);
    assert_memory_equal(&r1.fit, &r2.fit, sizeof r1.fit);
    assert_memory_equal(rad1, rad2, sizeof rad1);
    /* contract */
    memset(&sent, 0xA5, sizeof sent);
    cov = sent;
    assert_int_equal(sfit_joint_noise_cov(NULL, 0.25f, &cov), SFIT_E_ARG);
    assert_int_equal(sfit_joint_noise_cov(&g_j, 0.25f, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_joint_noise_cov(&g_j, -1.0f, &cov), SFIT_E_ARG);
    assert_int_equal(sfit_joint_noise_cov(&g_j, NAN, &cov), SFIT_E_NONFINITE);
    memset(nsent, 0xA5, sizeof nsent);
    memcpy(nl, nsent, sizeof nl);
    assert_int_equal(sfit_joint_marker_noise(NULL, 0.25f, nl), SFIT_E_ARG);
    assert_int_equal(sfit_joint_marker_noise(&g_j, 0.25f, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_joint_marker_noise(&g_j, -1.0f, nl), SFIT_E_ARG);
    assert_int_equal(sfit_joint_marker_noise(&g_j, INFINITY, nl), SFIT_E_NONFINITE);
    assert_int_equal(sfit_joint_marker_noise(&g_j, 1e38f, nl), SFIT_E_RANGE);
    assert_memory_equal(nl, nsent, sizeof nl);
    /* a corrupted child accumulator (valid count, non-finite totals): it
     * was taken for a marker without samples (SFIT_OK from the others);
     * now SFIT_E_RANGE, outputs untouched */
    {
        static sfit_joint_t jb;
        jb = g_j;
        jb.child[2].tot.m2[1] = NAN;
        assert_int_equal(sfit_joint_noise_cov(&jb, 0.25f, &cov), SFIT_E_RANGE);
        assert_memory_equal(&cov, &sent, sizeof cov);
        assert_int_equal(sfit_joint_marker_noise(&jb, 0.25f, nl), SFIT_E_RANGE);
        assert_memory_equal(nl, nsent, sizeof nl);
    }
    assert_int_equal(sfit_joint_reset(&g_j), SFIT_OK);
    assert_int_equal(sfit_joint_noise_cov(&g_j, 0.25f, &cov), SFIT_E_TOO_FEW);
    assert_memory_equal(&cov, &sent, sizeof cov);
    assert_int_equal(sfit_joint_marker_noise(&g_j, 0.25f, nl), SFIT_E_TOO_FEW);
    assert_memory_equal(nl, nsent, sizeof nl);
    /* options: MARKER needs SFIT_NOISE_ISO; an unknown model is rejected */
    cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
    cfg.solve.fit.noise = SFIT_NOISE_NONE;
    assert_int_equal(sfit_joint_init(&g_j, &g_j.parent, &cfg), SFIT_E_ARG);
    cfg.noise_model = (sfit_joint_noise_t)5;
    assert_int_equal(sfit_joint_init(&g_j, &g_j.parent, &cfg), SFIT_E_ARG);
}

/* sfit_joint_center_cov() against the double formula (ref_joint_center_cov)
 * on the same mapped samples, ball and hinge, with the per-marker models in
 * A: within 1e-3 of the largest entry (measured: printed). Its statistical
 * truth is checked in test_mc_ball / test_mc_hinge. Contract: statuses,
 * output untouched on failure. */
static void test_center_cov(void **state)
{
    tu_rng_t g;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_result_t res, bad;
    sfit_multi_noise_t nl[K];
    sfit_mat3_t cov, sent;
    noise_t nz;
    double tpl[P][3], want[9], c[3], ax[3], worst = 0.0;
    const double *xs[K];
    size_t f, k;
    int hinge, i;
    (void)state;
    cfg.n_child = K;
    cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
    cfg.solve.fit.noise = SFIT_NOISE_ISO;
    cfg.solve.fit.noise_var = 0.25f;
    memcpy(tpl, g_tpl, sizeof tpl);
    for (hinge = 0; hinge < 2; hinge++) {
        double big = 0.0, d = 0.0;
        make_motion(1000 + (uint64_t)hinge, 300, hinge);
        tu_rng_seed(&g, 12);
        make_noisy(&g, 0.5, 0.5);
        assert_int_equal(lib_run(&cfg, &g_j, &res, NULL), SFIT_OK);
        assert_int_equal(res.fit.mode, hinge ? SFIT_MODE_PLANAR : SFIT_MODE_SPHERE);
        assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0], g_nf,
                                               0.25f, &cov),
                         SFIT_OK);
        assert_int_equal(sfit_joint_marker_noise(&g_j, 0.25f, nl), SFIT_OK);
        noise_of_lib(nl, &nz);
        for (f = 0; f < g_nf; f++) {
            ref_map_frame((const double (*)[3])tpl, (const double (*)[3])g_pard[f],
                          (const double (*)[3])g_chid[f], f);
        }
        for (k = 0; k < K; k++) {
            xs[k] = &g_xs[k][0][0];
        }
        tc_to_double3(&res.fit.center, c);
        tc_to_double3(&res.fit.axis, ax);
        assert_int_equal(ref_joint_center_cov(g_tpl, P, xs, K, g_nf, nz.cov9, c,
                                              hinge ? ax : NULL, 0.25, want),
                         0);
        for (i = 0; i < 9; i++) {
            big = fmax(big, fabs(want[i]));
        }
        for (i = 0; i < 9; i++) {
            d = fmax(d, fabs((double)cov.m[i] - want[i]));
            assert_near(cov.m[i], want[i], 1e-3 * big, "centre covariance");
        }
        worst = fmax(worst, d / big);
        printf("  centre covariance (%s): trace %.4f mm^2\n", hinge ? "hinge" : "ball",
               want[0] + want[4] + want[8]);
        /* the multi-marker formula (independent markers) against the double one
         * without the parent term: within 2e-3 of the largest entry (r_p^2 and
         * C'_p from the moments against |y - c|^2 and y y^T sample by sample;
         * the reference is first order, the library's second-order term is
         * ~1.5e-4 of the largest entry here: sigma^2 / lambda_min is small) */
        {
            sfit_multi_cfg_t mc = sfit_multi_cfg_default;
            sfit_multi_result_t mr;
            double wm[9], bm = 0.0, dm = 0.0;
            mc.fit.mode = hinge ? SFIT_MODE_PLANAR : SFIT_MODE_SPHERE;
            assert_int_equal(sfit_multi_fit(g_j.child, K, &mc, &mr, NULL), SFIT_OK);
            assert_int_equal(sfit_multi_center_cov(g_j.child, K, &mc, &mr, 0.25f, &cov), SFIT_OK);
            tc_to_double3(&mr.center, c);
            tc_to_double3(&mr.axis, ax);
            assert_int_equal(ref_joint_center_cov(NULL, 0, xs, K, g_nf, NULL, c,
                                                  hinge ? ax : NULL, 0.25, wm),
                             0);
            for (i = 0; i < 9; i++) {
                bm = fmax(bm, fabs(wm[i]));
            }
            for (i = 0; i < 9; i++) {
                dm = fmax(dm, fabs((double)cov.m[i] - wm[i]));
            }
            printf("  multi-marker centre covariance (%s) vs double: %.3g of the largest entry\n",
                   hinge ? "hinge" : "ball", dm / bm);
            assert_true(dm <= 2e-3 * bm); /* measured 3.2e-4 (1.6e-4 first order) */
        }
    }
    printf("  centre covariance vs double: %.3g of the largest entry\n", worst);
    /* contract */
    memset(&sent, 0x5A, sizeof sent);
    cov = sent;
    assert_int_equal(sfit_joint_center_cov(NULL, &res, &g_parf[0][0], &g_chif[0][0], g_nf, 0.25f,
                                           &cov), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_cov(&g_j, NULL, &g_parf[0][0], &g_chif[0][0], g_nf, 0.25f,
                                           &cov), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, NULL, &g_chif[0][0], g_nf, 0.25f, &cov),
                     SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], NULL, g_nf, 0.25f, &cov),
                     SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0], g_nf, 0.25f,
                                           NULL), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0], g_nf, -1.0f,
                                           &cov), SFIT_E_ARG);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0], g_nf, NAN,
                                           &cov), SFIT_E_NONFINITE);
    bad = res;
    bad.fit.center.v[1] = INFINITY;
    assert_int_equal(sfit_joint_center_cov(&g_j, &bad, &g_parf[0][0], &g_chif[0][0], g_nf, 0.25f,
                                           &cov), SFIT_E_NONFINITE);
    bad = res;
    bad.fit.mode = (sfit_mode_t)9;
    assert_int_equal(sfit_joint_center_cov(&g_j, &bad, &g_parf[0][0], &g_chif[0][0], g_nf, 0.25f,
                                           &cov), SFIT_E_NONFINITE);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0], 0, 0.25f,
                                           &cov), SFIT_E_TOO_FEW);
    assert_memory_equal(&cov, &sent, sizeof cov);
    /* sfit_multi_center_cov: the same statuses */
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, &res.fit, 0.25f, &cov), SFIT_OK);
    cov = sent;
    assert_int_equal(sfit_multi_center_cov(NULL, K, NULL, &res.fit, 0.25f, &cov), SFIT_E_ARG);
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, NULL, 0.25f, &cov), SFIT_E_ARG);
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, &res.fit, 0.25f, NULL), SFIT_E_ARG);
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, &res.fit, -1.0f, &cov), SFIT_E_ARG);
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, &res.fit, NAN, &cov),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, &bad.fit, 0.25f, &cov),
                     SFIT_E_NONFINITE);
    assert_int_equal(sfit_multi_center_cov(g_j.child, 0, NULL, &res.fit, 0.25f, &cov),
                     SFIT_E_TOO_FEW);
    assert_memory_equal(&cov, &sent, sizeof cov);
    /* a corrupted child accumulator (counts valid, origin not finite): its
     * statistics are not finite, SFIT_E_RANGE with either noise model
     * (its mean and C were read unwritten before: valgrind) */
    {
        static sfit_joint_t jb;
        int nm;
        for (nm = 0; nm < 2; nm++) {
            jb = g_j;
            jb.cfg.noise_model = nm ? SFIT_JOINT_NOISE_MARKER : SFIT_JOINT_NOISE_SOLVE;
            jb.child[1].origin[2] = INFINITY;
            assert_int_equal(sfit_joint_center_cov(&jb, &res, &g_parf[0][0], &g_chif[0][0],
                                                   g_nf, 0.25f, &cov),
                             SFIT_E_RANGE);
        }
        assert_memory_equal(&cov, &sent, sizeof cov);
    }
    assert_int_equal(sfit_joint_reset(&g_j), SFIT_OK);
    assert_int_equal(sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0], g_nf, 0.25f,
                                           &cov), SFIT_E_TOO_FEW);
    assert_int_equal(sfit_multi_center_cov(g_j.child, K, NULL, &res.fit, 0.25f, &cov),
                     SFIT_E_TOO_FEW);
    assert_memory_equal(&cov, &sent, sizeof cov);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ball_exact),
        cmocka_unit_test(test_vs_ref),
        cmocka_unit_test(test_trajectory),
        cmocka_unit_test(test_mc_ball),
        cmocka_unit_test(test_mc_hinge),
        cmocka_unit_test(test_reject_unchanged),
        cmocka_unit_test(test_contract),
        cmocka_unit_test(test_template_from_frames),
        cmocka_unit_test(test_noise_cov),
        cmocka_unit_test(test_center_cov),
    };
    return cmocka_run_group_tests_name("joint", tests, NULL, NULL);
}
